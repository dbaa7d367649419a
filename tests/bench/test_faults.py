"""Faults of the bench itself: damaged files are repaired and never scored, a process that dies is named, and
Ctrl-C ends a campaign cleanly with the command that continues it."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hakoniwa.physics.sync import exit_crash
from hakoniwa.wire.exits import EXIT_BENCH_FAULT
from hakoniwa.wire.processes import BENCH_FAULT_MARKER
from hakoniwa.wire.protocol import ATHRILL_FILE, HEADER_SIZE, UNITY_FILE, BenchCause, CrashKind, Event, Rx
from hakoniwa.wire.rundir import PHYSICS_LOG
from testctl.campaign.journal import JOURNAL_FILE, read_journal
from tests.helpers.bench_fixtures import PAPER, physics
from tests.helpers.commands import one_line_error
from tests.helpers.processes import interruptible
from tests.helpers.waiting import wait_until

IDLE_APP = '''
def main_task(api):
    while True:  # drives nowhere: a test that lasts until its time limit
        api.tslp_tsk(100_000)
'''


class Exited:
    def __init__(self, code: int, pid: int = 4242) -> None:
        self.returncode = code
        self.pid = pid


@pytest.mark.parametrize("code, started, marked, kind", [
    (EXIT_BENCH_FAULT, True, True, CrashKind.BENCH),  # it could not use the mapped files, and said so
    (EXIT_BENCH_FAULT, True, False, CrashKind.PROGRAM),  # the user's own exit(3)
    (0, True, False, CrashKind.PROGRAM),  # the user's own exit(0) mid-test
    (1, False, False, CrashKind.BENCH),  # exited before it opened them: the bench's fault
    (-signal.SIGSEGV, True, False, CrashKind.PROGRAM),  # died running the program
    (-signal.SIGSEGV, False, False, CrashKind.PROGRAM),  # in the program's own start-up code
    (-signal.SIGKILL, True, False, CrashKind.BENCH),  # the OOM killer or kill -9: from outside the program
    (1, True, False, CrashKind.PROGRAM),
])
def test_whose_fault_an_exited_athrill_is(tmp_path, code, started, marked, kind):
    if marked:
        (tmp_path / f"{BENCH_FAULT_MARKER}4242").write_text("athrill_mmap.bin: size 104 bytes\n")
    crash = exit_crash(Exited(code), started=started, run_dir=tmp_path)
    assert crash.kind == kind and crash.detail == code
    assert ("size 104 bytes" in str(crash)) == marked
    assert not (tmp_path / f"{BENCH_FAULT_MARKER}4242").exists()  # taken, so a reused pid cannot inherit it


@pytest.mark.parametrize("victim", [UNITY_FILE, ATHRILL_FILE])
def test_an_overwritten_magic_is_repaired_not_scored(tmp_path, victim):
    """The test that finds the damage is the bench's fault (its parameters may have been overwritten too);
    the next one is as if nothing had happened."""
    with physics(tmp_path) as (_, runner):
        first = runner.run_test(PAPER)
        for _ in range(2):
            with open(tmp_path / victim, "r+b") as f:
                f.write(b"JUNK")
            spoiled = runner.run_test(PAPER)
            assert (spoiled.crash_kind, spoiled.bench_cause) == (CrashKind.BENCH, BenchCause.FILE_DAMAGED)
            again = runner.run_test(PAPER)
            assert (again.event, again.goal_time_us) == (first.event, first.goal_time_us)
    assert f"repaired {tmp_path / victim}: " in (tmp_path / PHYSICS_LOG).read_text()


def start_idle(tmp_path: Path, command: tuple[str, ...], *extra: str) -> subprocess.Popen:
    """`python -m COMMAND` running the idle program on the run directory tmp_path/run, then `extra`."""
    apps = tmp_path / "apps"
    apps.mkdir(exist_ok=True)
    (apps / "idle_app.py").write_text(IDLE_APP)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(apps), os.environ.get("PYTHONPATH", "")]))
    return subprocess.Popen([sys.executable, "-m", *command, "--app", "idle_app:main_task", "--time-limit", "3000",
                             "--run-dir", str(tmp_path / "run"), *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                            start_new_session=True, preexec_fn=interruptible)


def start_trial(tmp_path: Path) -> subprocess.Popen:
    return start_idle(tmp_path, ("testctl.hako", "try"))


def pid_of(module: str, run_dir: Path, timeout_s: float = 60) -> int:
    """The pid of the process running `python -m module` for this run directory."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        for entry in Path("/proc").iterdir():
            try:
                cmd = (entry / "cmdline").read_bytes().split(b"\0")
            except OSError:
                continue
            if cmd[1:3] == [b"-m", module.encode()] and any(str(run_dir).encode() in c for c in cmd):
                return int(entry.name)
        time.sleep(0.05)
    raise AssertionError(f"no {module} process for {run_dir}")


def wait_for_test(run_dir: Path) -> None:
    """Until the physics process has started test 1 (it announces the test's number to Athrill)."""
    wait_until(lambda: current_test_number(run_dir) >= 1, 60, what="test 1")


def current_test_number(run_dir: Path) -> int:
    try:
        data = (run_dir / UNITY_FILE).read_bytes()
    except OSError:
        return 0
    offset = HEADER_SIZE + Rx.TEST_SEQ
    return int.from_bytes(data[offset:offset + 4], "little") if len(data) >= offset + 4 else 0


def test_a_killed_physics_process_is_named(tmp_path):
    proc = start_trial(tmp_path)
    wait_for_test(tmp_path / "run")
    os.kill(pid_of("testctl.physics_process", tmp_path / "run"), signal.SIGKILL)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 128 + signal.SIGKILL
    assert "the physics process was killed by SIGKILL" in err and "Traceback" not in err


def test_a_killed_controller_is_named(tmp_path):
    """In the paper's arrangement, where the physics process starts the controller given after `--`."""
    controller_args = ("--kp", "1", "--ki", "0", "--kd", "0", "--out", str(tmp_path / "run" / "result.json"))
    proc = start_idle(tmp_path, ("testctl.physics_process",), "--", sys.executable, "-m", "testctl.cli", "try",
                      *controller_args)
    wait_for_test(tmp_path / "run")
    controller = pid_of("testctl.cli", tmp_path / "run")
    os.kill(controller, signal.SIGKILL)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 128 + signal.SIGKILL
    assert f"the test controller (pid {controller}) was killed by SIGKILL" in err and "Traceback" not in err


def test_a_truncated_mapped_file_is_a_clear_error(tmp_path):
    proc = start_trial(tmp_path)
    wait_for_test(tmp_path / "run")
    os.truncate(tmp_path / "run" / UNITY_FILE, 0)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode != 0
    # The physics process dies of SIGBUS if it touches the lost page first, else it finds the damage itself.
    assert ("SIGBUS" in err and f"{UNITY_FILE}: size 0 bytes, expected 8192" in err
            or "the bench spoiled the test (bench (mapped file damaged))" in err), err
    assert "Traceback" not in err


@pytest.mark.parametrize("when", ["early", "mid-test"])
def test_ctrl_c_in_hako_trial_is_one_line_and_130(tmp_path, when):
    """Early: while the physics process is still starting (importing); mid-test: once test 1 runs."""
    proc = start_trial(tmp_path)
    if when == "early":
        pid_of("testctl.physics_process", tmp_path / "run")
    else:
        wait_for_test(tmp_path / "run")
    os.killpg(proc.pid, signal.SIGINT)  # what the terminal does on Ctrl-C
    _, err = proc.communicate(timeout=60)
    one_line_error(subprocess.CompletedProcess(proc.args, proc.returncode, "", err), "interrupted")
    assert proc.returncode == 130


@pytest.mark.slow
@pytest.mark.parametrize("signum, status, word", [(signal.SIGINT, 130, "interrupted"),
                                                  (signal.SIGTERM, 143, "terminated")])
def test_ctrl_c_or_sigterm_ends_a_campaign_with_the_resume_command(tmp_path, signum, status, word):
    out = tmp_path / "c"
    proc = subprocess.Popen([sys.executable, "-m", "testctl.hako", "run", "--trials", "20", "--repeats", "1",
                             "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, preexec_fn=interruptible)
    wait_until(lambda: (out / JOURNAL_FILE).exists() and len(read_journal(out / JOURNAL_FILE)[1]) >= 2, 300, 0.1,
               alive=lambda: proc.poll() is None, what="two tests")
    if signum == signal.SIGINT:
        os.killpg(proc.pid, signal.SIGINT)  # what the terminal does on Ctrl-C
    else:
        proc.terminate()  # what `kill PID`, a CI runner or a supervisor does
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == status, err
    assert f"{word}: every finished test is in {out / JOURNAL_FILE}; continue with: hako run --resume {out}" in err
    assert "Aborted" not in err and "Traceback" not in err and "leaked" not in err
    records = read_journal(out / JOURNAL_FILE)[1]
    assert all(r.result.event != Event.CRASH for r in records)  # the interrupt spoiled no result


@pytest.mark.slow
def test_a_sigkilled_campaign_leaves_no_leaked_semaphore_warning(tmp_path):
    """The local workers' queues hold semaphores; multiprocessing's resource tracker, which outlives a
    SIGKILLed `hako run`, unlinks them, and says nothing about it."""
    out = tmp_path / "c"
    proc = subprocess.Popen([sys.executable, "-m", "testctl.hako", "run", "--trials", "20", "--repeats", "1",
                             "--benches", "2", "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)
    deadline = time.monotonic() + 300
    while not ((out / JOURNAL_FILE).exists() and len(read_journal(out / JOURNAL_FILE)[1]) >= 1):
        assert proc.poll() is None and time.monotonic() < deadline
        time.sleep(0.1)
    proc.kill()
    _, err = proc.communicate(timeout=120)  # until the tracker and the workers, which share stderr, are gone
    assert proc.returncode == -signal.SIGKILL
    assert "leaked" not in err and "Traceback" not in err, err
