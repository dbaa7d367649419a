"""Every fault of the bench is reported, counted and the test run again: a physics process killed mid-test, a
mapped file truncated or overwritten under a running test. None is ever a result of the parameters, and a
campaign's summary says how many tests were spoiled and by what."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from hakoniwa.wire.protocol import ATHRILL_FILE, UNITY_FILE, BenchCause, CrashKind, Event, Tx
from hakoniwa.wire.result import TestResult
from hakoniwa.wire.rundir import PHYSICS_LOG
from testctl.bench import Bench
from testctl.bench_options import BenchOptions
from testctl.campaign.journal import JOURNAL_FILE, PHASE_VALIDATION, read_journal
from testctl.campaign.loop import MAX_BENCH_FAULTS_IN_A_ROW, Campaign, CampaignConfig
from testctl.campaign.report import format_summary
from testctl.executor import TestSpec
from tests.helpers.bench_fixtures import PAPER, ZERO, physics
from tests.helpers.campaign_doubles import result
from tests.helpers.processes import tagged_env, tagged_processes
from tests.helpers.waiting import wait_until

IDLE_APP = '''
def idle(api):
    while True:  # drives nowhere: a test that lasts until its time limit
        api.tslp_tsk(100_000)
'''


def spec(params=PAPER) -> TestSpec:
    return TestSpec(0, 1, params)


def idle_bench(tmp_path: Path, monkeypatch) -> Bench:
    """A bench whose tests last 3000 simulated seconds, long enough to be hit mid-test."""
    (tmp_path / "idle_app.py").write_text(IDLE_APP)
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(tmp_path), os.environ.get("PYTHONPATH", "")]))
    return Bench(BenchOptions(app="idle_app:idle", time_limit_s=3000), tmp_path / "run")


def mid_test(bench: Bench, harm) -> TestResult:
    """Run a test on `bench` and do `harm(run_dir)` once the program is running it."""
    results: list[TestResult] = []
    test = threading.Thread(target=lambda: results.append(bench.run(spec(ZERO))))
    runner = bench.start()
    test.start()
    wait_until(lambda: runner.athrill.read_u32(Tx.ANSWER_SEQ) >= 3, 60, 0.01, alive=test.is_alive,
               what="the program's loop")
    harm(bench.run_dir)
    test.join(90)
    (r,) = results
    return r


def test_a_killed_physics_process_spoils_the_test_and_the_bench_is_rebuilt(tmp_path, monkeypatch):
    with idle_bench(tmp_path, monkeypatch) as bench:
        def kill_physics(run_dir: Path) -> None:
            os.kill(bench.start()._physics_pid, signal.SIGKILL)

        spoiled = mid_test(bench, kill_physics)
        assert spoiled.bench_fault and spoiled.bench_cause == BenchCause.PHYSICS_KILLED
        assert spoiled.crash_reason() == "bench (physics process killed): the physics process was killed by SIGKILL"
        assert spoiled.to_dict()["bench_cause"] == "physics_killed"
        assert TestResult.from_dict(spoiled.to_dict(), 0.0).bench_cause == BenchCause.PHYSICS_KILLED
        bench.options = BenchOptions(app="line_trace")  # the next test, on a fresh bench: as usual
        assert bench.run(spec()).event == Event.GOAL


def test_a_sigkilled_program_spoils_the_test_and_the_next_runs(tmp_path, monkeypatch):
    """SIGKILL is the OOM killer's or a person's, never a program crash: a bench fault, run again."""
    with idle_bench(tmp_path, monkeypatch) as bench:
        def kill_athrill(run_dir: Path) -> None:
            os.kill(bench.start().athrill.read_u32(Tx.ATHRILL_PID), signal.SIGKILL)

        spoiled = mid_test(bench, kill_athrill)
        assert spoiled.bench_fault and spoiled.bench_cause == BenchCause.ATHRILL_KILLED
        assert spoiled.crash_reason().startswith("bench (athrill killed): athrill was killed by SIGKILL")
        assert TestResult.from_dict(spoiled.to_dict(), 0.0).bench_cause == BenchCause.ATHRILL_KILLED
        bench.options = BenchOptions(app="line_trace")
        assert bench.run(spec()).event == Event.GOAL


SELF_KILLING_APP = '''
import os
import signal


def main_task(api):
    api.tslp_tsk(100_000)
    os.kill(os.getpid(), signal.SIGKILL)  # as the OOM killer would end this bench's Athrill, every test
'''


@pytest.mark.slow
def test_a_program_sigkilled_in_every_test_stops_the_campaign_with_one_line(tmp_path):
    """Never a result of the parameters: each kill is journaled as a bench fault and the test run again, until
    MAX_BENCH_FAULTS_IN_A_ROW in a row say the bench is broken; then one line and the resume command."""
    (tmp_path / "killed_app.py").write_text(SELF_KILLING_APP)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), os.environ.get("PYTHONPATH", "")])}
    out = tmp_path / "c"
    done = subprocess.run([sys.executable, "-m", "testctl.hako", "run", "--app", "killed_app:main_task",
                           "--trials", "1", "--init-points", "1", "--repeats", "1", "--benches", "1", "--out",
                           str(out)], capture_output=True, text=True, timeout=600, env=env)
    assert done.returncode == 1 and "Traceback" not in done.stderr, done.stderr
    error = [line for line in done.stderr.splitlines() if line.startswith("Error: ")]  # besides the progress lines
    assert error == [done.stderr.strip().splitlines()[-1]], done.stderr
    for words in (f"the bench failed {MAX_BENCH_FAULTS_IN_A_ROW} tests in a row", "athrill killed",
                  f"continue with: hako run --resume {out}"):
        assert words in error[0], done.stderr
    _, records = read_journal(out / JOURNAL_FILE)
    assert len(records) == MAX_BENCH_FAULTS_IN_A_ROW
    assert all(r.result.bench_cause == BenchCause.ATHRILL_KILLED for r in records)  # none scored


def test_a_file_truncated_mid_test_spoils_it_and_the_controller_survives(tmp_path, monkeypatch):
    """The physics process dies of SIGBUS touching the lost page; the controller reads the files without a
    mapping, so it lives to report it."""
    with idle_bench(tmp_path, monkeypatch) as bench:
        spoiled = mid_test(bench, lambda run_dir: os.truncate(run_dir / UNITY_FILE, 0))
        assert spoiled.bench_fault and spoiled.bench_cause == BenchCause.FILE_DAMAGED
        assert "mapped file damaged" in spoiled.crash_reason()
        bench.options = BenchOptions(app="line_trace")  # the next test, on a fresh bench: as usual
        assert bench.run(spec()).event == Event.GOAL

def test_a_file_overwritten_mid_test_spoils_it(tmp_path, monkeypatch):
    def overwrite(run_dir: Path) -> None:
        with open(run_dir / ATHRILL_FILE, "r+b") as f:
            f.write(b"JUNK")

    with idle_bench(tmp_path, monkeypatch) as bench:
        bench.options = BenchOptions(app="idle_app:idle", time_limit_s=20)
        spoiled = mid_test(bench, overwrite)
        assert (spoiled.event, spoiled.crash_kind, spoiled.bench_cause) == (Event.CRASH, CrashKind.BENCH,
                                                                            BenchCause.FILE_DAMAGED)
    log = (tmp_path / "run" / PHYSICS_LOG).read_text()
    assert "mapped file damaged during the test" in log and "magic b'JUNK'" in log


def test_a_file_overwritten_between_tests_spoils_the_next_and_no_other(tmp_path):
    with physics(tmp_path) as (_, runner):
        first = runner.run_test(PAPER)
        with open(tmp_path / UNITY_FILE, "r+b") as f:
            f.write(b"JUNK")
        spoiled = runner.run_test(PAPER)
        assert spoiled.bench_fault and spoiled.bench_cause == BenchCause.FILE_DAMAGED
        again = runner.run_test(PAPER)
        assert (again.event, again.goal_time_us) == (first.event, first.goal_time_us)
    assert f"repaired {tmp_path / UNITY_FILE}: magic b'JUNK'" in (tmp_path / PHYSICS_LOG).read_text()


def test_the_summary_says_how_many_tests_were_spoiled_and_by_what(tmp_path):
    faults = {1: BenchCause.PHYSICS_KILLED, 3: BenchCause.FILE_DAMAGED, 4: BenchCause.PHYSICS_KILLED}
    calls = []

    def bench(s: TestSpec) -> TestResult:
        calls.append(s)
        if len(calls) in faults:
            return TestResult(Event.CRASH, 0, 0.01, crash_kind=CrashKind.BENCH, bench_cause=faults[len(calls)])
        return result(Event.GOAL, 30.0 + s.set_index)

    summary = Campaign(CampaignConfig(init_points=2, trials=0, repeats=2, optimizer="random"), tmp_path, bench).run()
    assert summary.bench_faults == 3
    assert ("3 tests spoiled by the bench and rerun: physics process killed (2), mapped file damaged (1)"
            in format_summary(summary).splitlines())
    _, records = read_journal(tmp_path / JOURNAL_FILE)
    assert [r.result.bench_cause for r in records if r.result.bench_fault] == list(faults.values())
    assert len([r for r in records if not r.result.bench_fault]) == 4  # each spoiled test ran again


@pytest.mark.slow
def test_a_physics_process_killed_mid_campaign_is_counted_in_the_summary(tmp_path):
    """`hako run` on a Dask worker's bench: the kill is journaled as a bench fault, the test runs again on a
    fresh bench, and the summary line says so."""
    out, tag = tmp_path / "c", f"killed-physics-{os.getpid()}"
    proc = subprocess.Popen([sys.executable, "-m", "testctl.hako", "run", "--trials", "3", "--init-points", "2",
                             "--repeats", "1", "--benches", "1", "--noise", "0", "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=tagged_env(tag))
    wait_until(lambda: (out / JOURNAL_FILE).exists() and len(read_journal(out / JOURNAL_FILE)[1]) >= 1, 300, 0.1,
               alive=lambda: proc.poll() is None, what="a first test")
    # the worker's bench; the campaign's own bench in OUT/run films and draws the best sets, not tested here
    (physics_pid,) = [pid for pid in tagged_processes(tag, b"testctl.physics_process")
                      if str(out).encode() not in Path(f"/proc/{pid}/cmdline").read_bytes()]
    os.kill(physics_pid, signal.SIGKILL)
    stdout, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 0, stderr
    assert "1 test spoiled by the bench and rerun: physics process killed (1)" in stdout.splitlines()
    _, records = read_journal(out / JOURNAL_FILE)
    (fault,) = [r for r in records if r.result.bench_fault]
    assert fault.result.bench_cause == BenchCause.PHYSICS_KILLED
    searched = [r for r in records if r.phase != PHASE_VALIDATION]
    assert len([r for r in searched if not r.result.bench_fault]) == 5  # every set's test, once


def test_a_physics_process_that_never_reports_is_stopped_and_the_test_spoiled(tmp_path, monkeypatch):
    """Past the runner's own timeout (the last resort behind the physics side's wall-clock ceiling)."""
    with idle_bench(tmp_path, monkeypatch) as bench:
        runner = bench.start()
        runner.test_timeout_s = 3.0
        spoiled = bench.run(spec(ZERO))  # a 3000 s test does not end in 3 s of wall time
        assert (spoiled.crash_kind, spoiled.bench_cause, spoiled.crash_detail) == (CrashKind.BENCH,
                                                                                   BenchCause.TIME_STALLED, 0)
        assert spoiled.crash_reason() == "bench (simulated time stalled)"


def test_the_campaigns_own_bench_failing_under_a_picture_reruns_it(tmp_path):
    """A killed physics process on the bench that reruns a set for its picture once ended the campaign with a
    traceback; now the set runs again on the rebuilt bench."""
    from hakoniwa.wire.protocol import LayoutError
    from testctl.campaign.session import test_for_picture

    outcomes = [LayoutError("unity_mmap.bin: no such file"), result(Event.GOAL, 31.0)]

    def test_once(s: TestSpec):
        outcome = outcomes.pop(0)
        if isinstance(outcome, Exception):
            raise outcome
        return outcome, tmp_path

    assert test_for_picture(test_once, spec(ZERO)) == (result(Event.GOAL, 31.0), tmp_path)
    assert outcomes == []


def test_the_campaigns_own_bench_failing_twice_is_one_bench_error(tmp_path):
    from testctl.campaign.session import test_for_picture
    from testctl.executor import BenchFault
    from testctl.runner import PhysicsGone

    spoiled = TestResult(Event.CRASH, 0, 0.01, crash_kind=CrashKind.BENCH, bench_cause=BenchCause.FILE_DAMAGED)
    with pytest.raises(BenchFault, match="spoiled set 0's picture twice"):
        test_for_picture(lambda s: (spoiled, tmp_path), spec(ZERO))

    def gone(s):
        raise PhysicsGone("physics process 1 is gone")
    with pytest.raises(PhysicsGone, match="rerunning set 0 for its picture"):
        test_for_picture(gone, spec(ZERO))
