"""The mock's fork server: each forked Athrill must be what a fresh `athrill-sim` process is (the program
imported anew, its own random seed, its output and exit status), and the launcher must fall back to plain
processes where the server cannot serve."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from athrill_sim.programs import launcher as launcher_module
from athrill_sim.programs.kinds.python import python_program
from athrill_sim.programs.launcher import AthrillLauncher
from athrill_sim.programs.program import Program
from athrill_sim.programs.zygote import ForkedProcess, Zygote, ZygoteGone
from hakoniwa.wire.processes import kill
from hakoniwa.wire.protocol import SyncMode

# Loaded by `athrill-sim --check`, which imports the program and exits: its module-level code is the test.
PROGRAM = """
import os, random, sys
RUNS = []
RUNS.append(1)
with open(os.environ["ZYGOTE_TEST_OUT"], "a") as f:
    f.write(f"{len(RUNS)} {random.random()!r} {os.getpid()} {os.getsid(0) == os.getpid()}\\n")
print("hello from", os.getpid(), flush=True)
if os.environ.get("ZYGOTE_TEST_EXIT"):
    sys.exit(int(os.environ["ZYGOTE_TEST_EXIT"]))
if os.environ.get("ZYGOTE_TEST_RAISE"):
    raise RuntimeError("the program's own bug")

def run(api):
    pass
"""


@pytest.fixture
def program_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    (tmp_path / "zygote_prog.py").write_text(PROGRAM)
    monkeypatch.chdir(tmp_path)  # the zygote, like the mock, finds the program's module from its start folder
    monkeypatch.setenv("ZYGOTE_TEST_OUT", str(tmp_path / "runs.txt"))
    return tmp_path


def check_args() -> list[str]:
    return ["--app", "zygote_prog:run", "--check"]


def run_forked(zygote: Zygote) -> tuple[ForkedProcess, str]:
    proc = zygote.spawn(check_args(), None)
    assert proc.stdout is not None
    out = proc.stdout.read().decode()
    proc.wait(timeout=30)
    return proc, out


def test_each_forked_mock_imports_the_program_afresh_with_its_own_seed_session_and_output(program_dir: Path) -> None:
    zygote = Zygote()
    try:
        runs = [run_forked(zygote) for _ in range(3)]
    finally:
        zygote.close()
    lines = [line.split() for line in (program_dir / "runs.txt").read_text().splitlines()]
    assert [line[0] for line in lines] == ["1", "1", "1"]  # module state never carried from one test to the next
    assert len({line[1] for line in lines}) == 3  # three seeds, as three processes would draw
    assert [int(line[2]) for line in lines] == [proc.pid for proc, _ in runs]  # the pid the mock writes is its own
    assert all(line[3] == "True" for line in lines)  # a session of its own: the campaign's Ctrl-C is not its
    for proc, out in runs:
        assert proc.returncode == 0 and out == f"hello from {proc.pid}\n"


@pytest.mark.parametrize(("env", "code", "said"), [
    ({"ZYGOTE_TEST_EXIT": "3"}, 3, "hello from"),
    ({"ZYGOTE_TEST_RAISE": "1"}, 1, "the program's own bug"),  # an uncaught exception: its traceback, status 1
])
def test_a_forked_mock_exits_and_speaks_as_a_process_of_its_own(program_dir: Path, monkeypatch: pytest.MonkeyPatch,
                                                                 env: dict, code: int, said: str) -> None:
    for name, value in env.items():
        monkeypatch.setenv(name, value)
    zygote = Zygote()
    try:
        proc, out = run_forked(zygote)
    finally:
        zygote.close()
    plain = subprocess.run([sys.executable, "-m", "athrill_sim.mock.main", *check_args()], capture_output=True,
                           text=True)
    assert proc.returncode == plain.returncode == code
    assert said in out and said in plain.stdout + plain.stderr


def test_a_killed_forked_mock_reports_the_signal_like_popen(program_dir: Path) -> None:
    (program_dir / "zygote_prog.py").write_text("import time\ntime.sleep(60)\ndef run(api):\n    pass\n")
    zygote = Zygote()
    try:
        proc = zygote.spawn(check_args(), None)
        assert proc.poll() is None
        with pytest.raises(subprocess.TimeoutExpired):
            proc.wait(timeout=0.05)
        kill(proc)
        assert proc.returncode == -signal.SIGKILL and proc.poll() == -signal.SIGKILL
    finally:
        zygote.close()


def test_the_launcher_forks_the_mock_and_falls_back_to_processes_without_a_zygote(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    program = python_program("line_trace")
    launcher = AthrillLauncher(tmp_path, program)
    try:
        proc = launcher.take(1)
        assert isinstance(proc, ForkedProcess)
        kill(proc)
    finally:
        launcher.close()

    def no_zygote() -> Zygote:
        raise ZygoteGone("no pidfd_open on this system")

    monkeypatch.setattr(launcher_module, "Zygote", no_zygote)
    launcher = AthrillLauncher(tmp_path, program)
    try:
        proc = launcher.take(1)
        assert type(proc) is subprocess.Popen
        kill(proc)
    finally:
        launcher.close()
    assert os.path.exists(tmp_path / "athrill.log")


def test_a_process_that_ends_while_the_next_is_started_keeps_its_last_lines(tmp_path: Path) -> None:
    """The prelaunched process starts its test as soon as the physics side announces it, so it can crash before
    `take` has started the spare for the test after: its last lines (the program's own error) stay readable."""
    program = Program("prints, then waits for its go file", SyncMode.LOCKSTEP, True,
                      ("sh", "-c", "echo last words {test}; while [ ! -e {run_dir}/go{test} ]; do sleep 0.01; done"))
    launcher = AthrillLauncher(tmp_path, program)
    spawn = launcher._spawn

    def spawn_after_the_test_ended(seq: int, prog: Program) -> subprocess.Popen:
        if seq == 3:  # the spare for test 3 is started once test 2's process has ended, output and all
            (tmp_path / "go2").touch()
            ended = launcher._outputs[launcher._taken]
            ended.join()
            assert not ended.running
        return spawn(seq, prog)

    launcher._spawn = spawn_after_the_test_ended  # type: ignore[method-assign]
    try:
        kill(launcher.take(1))
        proc = launcher.take(2)
        proc.wait(10)
        assert launcher.last_lines(proc, 5) == ["last words 2"]
    finally:
        launcher.close()
