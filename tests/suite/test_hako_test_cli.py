"""`hako test` as a user and a CI system meet it: exit 0 / 1 / 2, the table, JUnit XML that a JUnit reader
takes, the files a failing case keeps, and a bench killed mid-run."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from junitparser import Failure, JUnitXml

from tests.bench.test_faults import IDLE_APP
from tests.helpers.commands import hako, one_line_error
from tests.helpers.paths import REPO
from tests.helpers.processes import tagged_env, tagged_processes
from tests.helpers.waiting import wait_until

EXAMPLE = REPO / "docs" / "examples" / "hako-tests.toml"
GAINS = "params = { Kp = 1.539, Ki = 4.267, Kd = 4.511 }\n"


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "hako-tests.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("text, words", [
    (f'[case.a]\nspeed = 3\n{GAINS}expect = ["GOAL"]\n', ["case 'a'", "unknown key(s) speed"]),
    (f'[case.a]\n{GAINS}', ["case 'a'", "no expectations"]),
    (f'[case.a]\n{GAINS}expect = ["speed < 40"]\n', ["no value 'speed'"]),
    (f'[case.a]\nseeds = 0\n{GAINS}expect = ["GOAL"]\n', ["seeds", "at least 1"]),
    ('[case.a]\nfrom = "runs/none"\nexpect = ["GOAL"]\n', ["best.json does not exist"]),
    (f'[case.a]\napp = "no_such_module:main"\n{GAINS}expect = ["GOAL"]\n', ["no_such_module"]),
])
def test_bad_input_is_one_line_and_exit_2_before_any_test(tmp_path, text, words):
    out = tmp_path / "out"
    r = hako("test", str(write(tmp_path, text)), "--out", str(out), timeout=120)
    one_line_error(r, *words)
    assert r.returncode == 2
    assert not out.exists()


def test_a_missing_test_file_is_exit_2(tmp_path):
    r = hako("test", cwd=tmp_path, timeout=60)
    one_line_error(r, "hako-tests.toml", "no such test file")
    assert r.returncode == 2


@pytest.mark.slow
def test_an_impossible_bound_fails_the_case_naming_bound_and_lap(tmp_path):
    path = write(tmp_path, f'[case.ok]\nseeds = 1\nnoise = 0\n{GAINS}expect = ["GOAL", "lap_s < 60"]\n'
                           f'[case.too-fast]\nseeds = 1\nnoise = 0\n{GAINS}expect = ["GOAL", "lap_s < 5"]\n')
    out, xml, js = tmp_path / "out", tmp_path / "out.xml", tmp_path / "out.json"
    r = hako("test", str(path), "--benches", "1", "--out", str(out), "--junit", str(xml), "--json", str(js))
    assert r.returncode == 1, r.stderr
    results = json.loads(js.read_text())
    lap = results["cases"][1]["runs"][0]["lap_time_s"]
    assert 20 < lap < 60
    assert f"lap_s < 5  {lap:.3f} s" in r.stdout and "1 of 2 cases passed; failing: too-fast" in r.stdout

    suite = next(iter(JUnitXml.fromfile(str(xml))))
    assert (suite.tests, suite.failures, suite.errors) == (2, 1, 0)
    ok, failed = list(suite)
    assert ok.is_passed and ok.name == "ok"
    (failure,) = [f for f in failed.result if isinstance(f, Failure)]
    assert failure.message.startswith(f"lap_s < 5: measured {lap:.3f} s (seed ")

    kept = out / "too-fast"
    assert (kept / "trajectory.png").stat().st_size > 0 and (kept / "run" / "trajectory.csv").exists()
    assert not (out / "ok" / "trajectory.png").exists() and (out / "ok" / "laps.png").exists()
    from hakoniwa.pictures.video import gl_problem

    if gl_problem() is None:  # where MuJoCo can render, the failing run filmed beside its picture
        assert (kept / "lap.mp4").stat().st_size > 0 and not (out / "ok" / "lap.mp4").exists()
        again = hako("replay", str(kept), "--video", str(tmp_path / "again.gif"), "--speed", "8x", "--fps", "5")
        assert again.returncode == 0, again.stderr


@pytest.mark.slow
def test_the_example_suite_passes_and_its_junit_reads(tmp_path):
    """As docs/CI.md and .ci/run run it: the JUnit file inside the output folder the run creates."""
    xml = tmp_path / "out" / "junit.xml"
    r = hako("test", str(EXAMPLE), "--out", str(tmp_path / "out"), "--junit", str(xml))
    assert r.returncode == 0, r.stdout + r.stderr
    suite = next(iter(JUnitXml.fromfile(str(xml))))
    assert suite.tests >= 2 and suite.failures == suite.errors == 0
    assert all(case.is_passed for case in suite)


@pytest.mark.slow
@pytest.mark.parametrize("benches", ["1", "2"])
def test_a_bench_killed_mid_run_is_exit_2_not_a_failed_case(tmp_path, benches):
    """On one bench (our own) and on two (Dask workers, which would otherwise rerun the test quietly)."""
    apps = tmp_path / "apps"
    apps.mkdir()
    (apps / "idle_app.py").write_text(IDLE_APP)
    path = write(tmp_path, f'[case.idle]\napp = "idle_app:main_task"\ntime_limit_s = 3000\nseeds = 2\n{GAINS}'
                           'expect = ["not HIT_WALL"]\n')
    out = tmp_path / "out"
    tag = f"hako-test-kill-{benches}-{os.getpid()}-{time.monotonic_ns()}"
    env = tagged_env(tag, dict(os.environ, PYTHONPATH=os.pathsep.join([str(apps), os.environ.get("PYTHONPATH", "")])))
    proc = subprocess.Popen([sys.executable, "-m", "testctl.hako", "test", str(path), "--benches", benches, "--out",
                             str(out), "--junit", str(tmp_path / "out.xml")], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env, start_new_session=True)
    try:
        victims = wait_until(lambda: tagged_processes(tag, b"testctl.physics_process"), 120,
                             alive=lambda: proc.poll() is None, what="a bench")
        os.kill(victims[0], signal.SIGKILL)
        stdout, err = proc.communicate(timeout=300)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 2, stdout + err
    assert "the test run broke" in err and "Traceback" not in err
    assert not (tmp_path / "out.xml").exists()


@pytest.mark.slow
def test_sigterm_ends_hako_test_with_one_line_and_143(tmp_path):
    """A CI runner cancelling the job sends SIGTERM: it ends the run as Ctrl-C does, judging nothing."""
    apps = tmp_path / "apps"
    apps.mkdir()
    (apps / "idle_app.py").write_text(IDLE_APP)
    path = write(tmp_path, f'[case.idle]\napp = "idle_app:main_task"\ntime_limit_s = 3000\nseeds = 1\n{GAINS}'
                           'expect = ["not HIT_WALL"]\n')
    tag = f"hako-test-term-{os.getpid()}-{time.monotonic_ns()}"
    env = tagged_env(tag, dict(os.environ, PYTHONPATH=os.pathsep.join([str(apps), os.environ.get("PYTHONPATH", "")])))
    proc = subprocess.Popen([sys.executable, "-m", "testctl.hako", "test", str(path), "--benches", "1", "--out",
                             str(tmp_path / "out")], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env, start_new_session=True)
    try:
        wait_until(lambda: tagged_processes(tag, b"testctl.physics_process"), 120, alive=lambda: proc.poll() is None,
                   what="a bench")
        proc.terminate()
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 143, err
    assert "terminated: nothing is judged" in err and "Traceback" not in err
