"""End-to-end: the three processes over real mapped files in a temporary run directory."""

import json
import os
import signal
import subprocess
import sys

import pytest

from hakoniwa.wire.protocol import BenchCause, CrashKind, Event, Rx, Tx
from hakoniwa.wire.rundir import LOCK_FILE
from testctl.bench_options import BenchOptions
from tests.helpers.bench_fixtures import PAPER, ZERO, physics
from tests.helpers.commands import hako
from tests.helpers.waiting import wait_until


def test_paper_gains_finish_a_lap_and_zero_gains_do_not(tmp_path):
    with physics(tmp_path) as (_, runner):
        good = runner.run_test(PAPER)
        bad = runner.run_test(ZERO)
        again = runner.run_test(PAPER)
    assert good.event == Event.GOAL
    assert 20 <= good.lap_time_s <= 60  # tens of seconds, like the paper's 32 s
    assert bad.event in (Event.HIT_WALL, Event.TIME_OVER)
    assert bad.goal_time_us == 0
    # A reset between tests restores everything: the same parameters give the same microsecond.
    assert (again.event, again.goal_time_us) == (good.event, good.goal_time_us)
    assert (tmp_path / "trajectory.csv").read_text().count("\n") > 100


def test_athrill_killed_mid_test_is_a_crash_and_the_bench_stays_usable(tmp_path):
    with physics(tmp_path) as (_, runner):
        runner.write_params(PAPER)
        runner.athrill.write_i32(Tx.START, 1)
        wait_until(lambda: runner.unity.unity_time_us >= 2_000_000, 30, 0.005, what="two simulated seconds")
        os.kill(runner.athrill.read_u32(Tx.ATHRILL_PID), signal.SIGKILL)
        wait_until(lambda: runner.unity.read_i32(Rx.EVENT) != Event.NONE, 60, 0.005, what="an event")
        assert runner.unity.read_i32(Rx.EVENT) == Event.CRASH  # not HIT_WALL
        # noticed through the process, not by the silence watchdog; SIGKILL came from outside the program
        crash = runner.read_result()
        assert (crash.crash_kind, crash.bench_cause, crash.crash_detail) == (CrashKind.BENCH,
                                                                            BenchCause.ATHRILL_KILLED, -signal.SIGKILL)
        runner.athrill.write_i32(Tx.START, 0)
        wait_until(lambda: runner.unity.read_i32(Rx.EVENT) == Event.NONE, 10, 0.005, what="the reset")
        assert runner.run_test(PAPER).event == Event.GOAL


SILENT_APP = '''
def main_task(api):
    api.tslp_tsk(100_000)
    while True:  # a program that never sleeps again: simulated time cannot advance
        pass
'''


def test_silent_athrill_is_a_crash_within_the_timeout(tmp_path):
    apps = tmp_path / "apps"
    apps.mkdir()
    (apps / "silent_app.py").write_text(SILENT_APP)
    run_dir = tmp_path / "run"
    env = {"PYTHONPATH": os.pathsep.join([str(apps), os.environ.get("PYTHONPATH", "")])}
    with physics(run_dir, extra_env=env, app="silent_app:main_task", athrill_timeout_s=1.0) as (_, runner):
        result = runner.run_test(PAPER)
    assert result.event == Event.CRASH and result.crash_kind == CrashKind.SILENT


def test_a_run_directory_serves_one_run_at_a_time(tmp_path):
    with physics(tmp_path):
        second = subprocess.run(BenchOptions().physics_command(tmp_path, []), capture_output=True, text=True,
                                timeout=60)
    assert second.returncode != 0
    assert "in use by another run" in second.stderr
    assert "Traceback" not in second.stderr


def test_leftovers_of_a_crashed_run_do_not_confuse_a_new_one(tmp_path):
    (tmp_path / "unity_mmap.bin").write_bytes(b"garbage from a crashed run")
    (tmp_path / "athrill_mmap.bin").write_bytes(b"\xff" * 5000)
    (tmp_path / LOCK_FILE).write_text("99999\n")  # a stale lock file, no live holder
    with physics(tmp_path) as (_, runner):
        assert runner.run_test(PAPER).event == Event.GOAL


def hako_trial_json(*extra: str, env=None) -> dict:
    out = hako("try", "--json", *extra, timeout=300, env=env)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def test_hako_try_cli_prints_event_and_lap_time(tmp_path):
    png = tmp_path / "path.png"
    result = hako_trial_json("--trajectory", str(png))
    assert result["event"] == "GOAL" and result["lap_time_s"] > 0
    assert result["sync"] == "lockstep" and result["checkpoints"] == 4 and result["max_time_diff_us"] == 0
    assert 6.0 < result["distance_m"] < 7.0  # about a lap of the 6.1 m line
    assert png.stat().st_size > 10_000


def test_hako_try_rejects_bad_course():
    out = hako("try", "--course", "/nonexistent", timeout=60)
    assert out.returncode != 0
    assert "no course at /nonexistent" in out.stderr and "Traceback" not in out.stderr


@pytest.mark.slow
def test_same_trial_same_json_even_under_cpu_load():
    quiet = hako_trial_json("--kp", "2.2", "--ki", "0.4", "--kd", "1.6")
    burners = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(2)]
    try:
        loaded = hako_trial_json("--kp", "2.2", "--ki", "0.4", "--kd", "1.6")
    finally:
        for b in burners:
            b.kill()
            b.wait()
    assert quiet == loaded
    assert quiet["event"] == "GOAL"


def test_controller_notices_a_dead_physics_process(tmp_path):
    from testctl.runner import PhysicsGone

    with pytest.raises(PhysicsGone, match="is gone"):
        with physics(tmp_path) as (proc, runner):
            proc.kill()
            proc.wait()
            runner.run_test(PAPER)  # "is gone", not "no event within ..." after the long test timeout


def test_time_limit_option_ends_the_test():
    result = hako_trial_json("--time-limit", "5", "--noise", "0")
    assert result["event"] == "TIME_OVER" and result["lap_time_s"] is None
    assert 0.8 < result["distance_m"] < 1.3  # five seconds of driving at power 15: about 0.22 m/s
