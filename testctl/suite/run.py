"""Running a test file's cases on the benches and judging each case.

Tests go to the executors a campaign uses (one bench serially, or Dask workers), as `TestSpec`s: set = the
case, repetition = its noise draw. An executor serves one bench configuration, so the cases are run in
groups of the same bench, in file order. A CRASH the bench caused says nothing about the program, and a
test run that met one has not tested what it claims: it stops the run as a `BenchFault`, never a failed case.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import AbstractContextManager, contextmanager
from dataclasses import dataclass
from pathlib import Path

from hakoniwa.wire.result import TestResult
from testctl.bench import Bench
from testctl.bench_options import BenchOptions
from testctl.cluster_address import ClusterAddress
from testctl.executor import Executor, SerialExecutor, TestSpec, bench_fault, results_of
from testctl.lapstats import LapStats, lap_or_inf
from testctl.suite.cases import Case
from testctl.suite.expect import Check


@dataclass(frozen=True)
class Run:
    """One test of a case: its noise seed, where it ran and what it gave."""

    seed: int
    bench: str
    result: TestResult

    @property
    def label(self) -> str:
        return f"seed {self.seed}"


@dataclass(frozen=True)
class CaseRun:
    case: Case
    runs: tuple[Run, ...]  # in the case's seed order
    checks: tuple[Check, ...]

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks)

    @property
    def stats(self) -> LapStats:
        return LapStats.of([r.result for r in self.runs])

    @property
    def wall_s(self) -> float:
        return sum(r.result.wall_s for r in self.runs)

    def worst_run(self) -> Run:
        """The run to show when the case fails: the first that did not reach GOAL, else the slowest."""
        return next((r for r in self.runs if not r.result.success),
                    max(self.runs, key=lambda r: lap_or_inf(r.result)))


def judge(case: Case, runs: Sequence[Run]) -> CaseRun:
    results = [r.result for r in runs]
    labels = [r.label for r in runs]
    return CaseRun(case, tuple(runs), tuple(e.check(results, labels) for e in case.expect))


def run_specs(executor: Executor, specs: Iterable[TestSpec],
              on_result: Callable[[TestSpec, TestResult], None] = lambda spec, result: None,
              ) -> dict[tuple[int, int], tuple[TestResult, str]]:
    """Run every spec on `executor`; {(set, repetition): (result, bench)}. A bench fault is a `BenchFault`."""
    done: dict[tuple[int, int], tuple[TestResult, str]] = {}
    for spec, result, bench in results_of(executor, specs):
        if result.bench_fault:
            raise bench_fault(result, bench)
        done[spec.set_index, spec.rep] = result, bench
        on_result(spec, result)
    return done


def case_specs(index: int, case: Case) -> list[TestSpec]:
    return [TestSpec(index, rep, case.params, seed, case.noise, case.slot_types)
            for rep, seed in enumerate(case.seeds, 1)]


def run_cases(cases: Sequence[Case], open_executor: Callable[[BenchOptions], AbstractContextManager[Executor]],
              on_result: Callable[[TestSpec, TestResult], None] = lambda spec, result: None) -> list[CaseRun]:
    """Every case, judged, in file order."""
    groups: dict[BenchOptions, list[int]] = {}
    for i, case in enumerate(cases):
        groups.setdefault(case.bench, []).append(i)
    done: dict[tuple[int, int], tuple[TestResult, str]] = {}
    for bench, indices in groups.items():
        with open_executor(bench) as executor:
            done |= run_specs(executor, (s for i in indices for s in case_specs(i, cases[i])), on_result)
    return [judge(case, [Run(seed, done[i, rep][1], done[i, rep][0]) for rep, seed in enumerate(case.seeds, 1)])
            for i, case in enumerate(cases)]


@contextmanager
def bench_executor(bench: BenchOptions, run_dir: Path, benches: int,
                   scheduler: ClusterAddress | None) -> Iterator[Executor]:
    """The executor of one bench configuration: a bench of our own in `run_dir` when one is wanted (no
    cluster to start, and its run folder stays where the user looks), else Dask workers, as a campaign's."""
    if scheduler is None and benches == 1:
        local = Bench(bench, run_dir)
        try:
            yield SerialExecutor(local.run, name=str(run_dir))
        finally:
            local.close()
        return
    from testctl.cluster import DaskExecutor

    # A bench that dies is the run's failure (exit 2) on every path, as on one bench: not rerun quietly.
    executor = DaskExecutor(bench, benches=None if scheduler else benches, scheduler=scheduler, retries=0)
    try:
        yield executor
    finally:
        executor.close()


def rerun_worst(run: CaseRun, run_dir: Path) -> tuple[TestResult, Path]:
    """The case's worst run once more, on a bench of its own in `run_dir`, which keeps its files."""
    worst = run.worst_run()
    rep = run.runs.index(worst) + 1
    with Bench(run.case.bench, run_dir) as bench:
        return bench.run(TestSpec(0, rep, run.case.params, worst.seed, run.case.noise, run.case.slot_types)), run_dir
