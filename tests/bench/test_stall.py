"""A silent Athrill: a machine that stalls it (SIGSTOP, no CPU) is the bench's fault, rerun and never scored;
a program that spins without sleeping is the program's. The process's CPU time tells them apart."""

from __future__ import annotations

import os
import signal
import threading
from pathlib import Path

from hakoniwa.wire.protocol import CrashKind, Event, Tx
from hakoniwa.wire.rundir import PHYSICS_LOG
from tests.helpers.bench_fixtures import ZERO, physics
from tests.helpers.waiting import wait_until

APPS = '''
def idle(api):
    while True:
        api.tslp_tsk(100_000)


def spin(api):
    api.tslp_tsk(100_000)
    while True:  # never sleeps again: simulated time cannot pass
        pass
'''


def bench(tmp_path: Path, app: str):
    (tmp_path / "stall_apps.py").write_text(APPS)
    env = {"PYTHONPATH": os.pathsep.join([str(tmp_path), os.environ.get("PYTHONPATH", "")])}
    return physics(tmp_path / "run", app=f"stall_apps:{app}", athrill_timeout_s=2.0, extra_env=env)


def test_a_stopped_athrill_is_a_bench_fault_and_the_next_test_runs(tmp_path):
    with bench(tmp_path, "idle") as (_, runner):
        results = []
        test = threading.Thread(target=lambda: results.append(runner.run_test(ZERO)))
        test.start()
        wait_until(lambda: runner.athrill.read_u32(Tx.ANSWER_SEQ) >= 2, 60, 0.01, what="the program's loop")
        pid = runner.athrill.read_u32(Tx.ATHRILL_PID)
        os.kill(pid, signal.SIGSTOP)  # the machine stalls it, longer than --athrill-timeout
        try:
            test.join(60)
        finally:
            try:
                os.kill(pid, signal.SIGCONT)
            except ProcessLookupError:
                pass
        (stalled,) = results
        assert (stalled.event, stalled.crash_kind) == (Event.CRASH, CrashKind.BENCH)
        assert stalled.bench_fault
        assert runner.run_test(ZERO).event == Event.TIME_OVER  # the same bench, the next test: as usual
    assert "athrill was stopped" in (tmp_path / "run" / PHYSICS_LOG).read_text()


def test_a_program_that_spins_without_sleeping_is_the_programs_fault(tmp_path):
    with bench(tmp_path, "spin") as (_, runner):
        result = runner.run_test(ZERO)
    assert (result.event, result.crash_kind) == (Event.CRASH, CrashKind.SILENT)
    assert not result.bench_fault
    assert "the program does not sleep" in (tmp_path / "run" / PHYSICS_LOG).read_text()
