"""A parameter-search campaign: the paper's experiment loop (section 3.4.3, 4.1), in parallel and resumable.

`init_points` random parameter sets, then `trials` sets proposed by the sampler, in rounds of `batch` sets
(each round proposed at once, later points of a round taking the earlier ones as pending). Every set is
tested until the repetition rule decides it; its repetitions run in parallel as far as the rule allows
(`RepetitionRule.still_needed`), on as many benches as the executor has. Every test goes to the journal as
soon as it finishes.

What a campaign produces depends only on its configuration: proposals are a pure function of (seed, round,
the decided sets before the round), each test's noise seed of (seed, set, repetition), and a set's verdict of
its results in repetition order; so neither the number of benches nor the order in which tests finish changes
the journal's sets and results. That is also what makes `--resume` exact: it rebuilds the decided sets from
the journal, proposes the current round again (and checks it against the journal), and runs only the
repetitions that are missing.

The campaign knows nothing of processes or mapped files: it hands `TestSpec`s to an executor.
"""

from __future__ import annotations

import dataclasses
import time
from collections import Counter
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.result import TestResult

# The configuration lives apart so that --help can read its defaults without NumPy; importers of the campaign
# find it here too.
from testctl.campaign.config import PHASE_INIT as PHASE_INIT
from testctl.campaign.config import CampaignConfig as CampaignConfig
from testctl.campaign.journal import (
    JOURNAL_FILE,
    PHASE_VALIDATION,
    Journal,
    JournalError,
    TestRecord,
    now_timestamp,
    read_journal,
)
from testctl.campaign.repetition import Verdict
from testctl.executor import Executor, SerialExecutor, TestSpec
from testctl.noise_seed import noise_seed
from testctl.search.optimizers import make_sampler
from testctl.search.sampler import RandomSampler, Sampler
from testctl.search.space import ParameterSpace

MAX_BENCH_FAULTS_IN_A_ROW = 5  # then the bench is broken, not unlucky: stop rather than spin


class BenchBroken(HakoError, RuntimeError):
    """The bench spoiled test after test; the campaign stops (its journal is intact and resumable)."""


@dataclass(frozen=True)
class SetResult:
    """A decided parameter set: its point (in `space.names` order), verdict and counted tests."""

    index: int
    phase: str
    x: tuple[float, ...]
    verdict: Verdict
    tests: tuple[TestRecord, ...]

    @property
    def number(self) -> int:
        """The set's number for people (figures, tables, summaries): from 1."""
        return self.index + 1

    @property
    def value(self) -> float:
        assert self.verdict.value is not None
        return self.verdict.value


def best_set(sets: list[SetResult] | tuple[SetResult, ...]) -> SetResult | None:
    """The successful set with the shortest mean lap (the earliest on a tie), or None before any success."""
    return min((s for s in sets if s.verdict.success), key=lambda s: s.value, default=None)


@dataclass(frozen=True)
class Progress:
    """Reported after loading the journal, after each test (`last_test`) and after each decided set."""

    sets_done: int
    sets_total: int
    tests_done: int
    best: SetResult | None
    last_test: TestRecord | None
    running: int = 0  # tests on the benches now
    benches: int = 1


@dataclass(frozen=True)
class CampaignSummary:
    config: CampaignConfig
    sets: tuple[SetResult, ...]
    best: SetResult | None
    n_tests: int  # all tests in the journal, including earlier sessions and bench faults
    tests_run: int  # tests run by this session
    wall_s: float  # this session's wall time
    test_wall_s: float  # wall time of all tests in the journal
    bench_faults: int  # tests the bench spoiled (journaled, never scored)
    proposal_s: tuple[float, ...] = ()  # the sampler's own wall time for each round this session proposed
    bench_causes: tuple[tuple[str, int], ...] = ()  # what spoiled them, in words, most frequent first

    def describe_bench_faults(self) -> str | None:
        """`2 tests spoiled by the bench and rerun: physics process killed (1), mapped file damaged (1)`."""
        if not self.bench_faults:
            return None
        causes = ", ".join(f"{words} ({n})" for words, n in self.bench_causes)
        tests = f"{self.bench_faults} test{'s' if self.bench_faults > 1 else ''}"
        return f"{tests} spoiled by the bench and rerun: {causes}"


def load_config(out_dir: Path) -> CampaignConfig:
    """The configuration a campaign directory was started with (for `--resume DIR` without options)."""
    header, _ = read_journal(Path(out_dir) / JOURNAL_FILE)
    return CampaignConfig.from_header(header)


@dataclass
class _OpenSet:
    """A set being tested: its tests so far by repetition, and the repetitions still out on benches."""

    index: int
    x: tuple[float, ...]
    records: dict[int, TestRecord] = field(default_factory=dict)
    out: set[int] = field(default_factory=set)


def gap_free(by_rep: Mapping[int, TestRecord]) -> list[TestRecord]:
    """The tests of repetitions 1, 2, ... up to the first missing one: what an uninterrupted run judges. A gap
    is left by a kill while later repetitions of the set had already finished."""
    done: list[TestRecord] = []
    while len(done) + 1 in by_rep:
        done.append(by_rep[len(done) + 1])
    return done


class Campaign:
    """Runs (or, with `resume=True`, continues) the campaign journaled in `out_dir`.

    `executor` runs the tests: an `Executor`, or simply a function TestSpec -> TestResult (run one at a time).
    `bench_info` describes the bench (course, program, time limit) for the journal's header: a resumed
    campaign runs on the same bench. `on_sets` is given every set decided so far: none at the start, then
    whenever there are more (those of the journal first); the Optuna study mirror, `testctl.campaign.study`.
    `header` holds further keys for a new journal's header that the campaign itself does not read.
    """

    def __init__(
        self,
        config: CampaignConfig,
        out_dir: Path,
        executor: Executor | Callable[[TestSpec], TestResult],
        *,
        on_progress: Callable[[Progress], None] | None = None,
        on_sets: Callable[[tuple[SetResult, ...]], None] | None = None,
        resume: bool = False,
        bench_info: Mapping[str, Any] | None = None,
        header: Mapping[str, Any] | None = None,
    ) -> None:
        self.config = config
        self.bench_info = dict(bench_info or {})
        self.header = dict(header or {})
        self.out_dir = Path(out_dir)
        self.executor = executor if isinstance(executor, Executor) else SerialExecutor(executor)
        self.on_progress = on_progress
        self.on_sets = on_sets
        self.resume = resume
        self._init_sampler: Sampler = RandomSampler(config.seed)
        self._bo_sampler: Sampler = make_sampler(config.optimizer, config.seed)
        self._done: list[SetResult] = []
        self._faults_in_a_row = 0
        self._proposal_s: list[float] = []

    @property
    def _space(self) -> ParameterSpace:
        return self.config.space

    def run(self) -> CampaignSummary:
        started = time.monotonic()
        path = self.out_dir / JOURNAL_FILE
        if self.resume:
            journal = Journal.open(path)
            self._check_header(journal)
        else:
            self.out_dir.mkdir(parents=True, exist_ok=True)
            journal = Journal.create(path, {**self.config.header(), "bench": self.bench_info, **self.header})
        with journal:
            n_before = len(journal.records)
            by_set = self._group([r for r in journal.records if r.phase != PHASE_VALIDATION])
            self._report(len(journal.records), None)
            if self.on_sets is not None:
                self.on_sets(())
            for round_index, indices in enumerate(self.config.rounds()):
                journaled = [self._decided(by_set.get(i, [])) for i in indices]
                if all(journaled):
                    self._add(*(s for s in journaled if s is not None))
                    continue
                t0 = time.perf_counter()
                points = self._propose(round_index, indices)
                self._proposal_s.append(time.perf_counter() - t0)
                points = self._check_against_journal(indices, points, by_set)
                self._run_round([_OpenSet(i, x) for i, x in zip(indices, points)], by_set, journal)
            self._add(*(s for i in sorted(by_set) if i >= self.config.total_sets
                        for s in [self._decided(by_set[i])] if s is not None))
            records = journal.records
        sets = tuple(sorted(self._done, key=lambda s: s.index))
        return CampaignSummary(
            config=self.config,
            sets=sets,
            best=best_set(sets),
            n_tests=len(records),
            tests_run=len(records) - n_before,
            wall_s=time.monotonic() - started,
            test_wall_s=sum(r.result.wall_s for r in records),
            bench_faults=sum(r.result.bench_fault for r in records),
            proposal_s=tuple(self._proposal_s),
            bench_causes=tuple(Counter(r.result.bench_cause.words for r in records
                                       if r.result.bench_fault).most_common()),
        )

    # -- one round ------------------------------------------------------------------------------------
    def _run_round(self, open_sets: list[_OpenSet], by_set: dict[int, list[TestRecord]], journal: Journal) -> None:
        ex = self.executor
        live: dict[int, _OpenSet] = {}
        for s in open_sets:
            for r in by_set.get(s.index, []):
                if not r.result.bench_fault:
                    s.records[r.rep] = r
            self._launch(s)
            if s.out:
                live[s.index] = s
            else:  # decided before an interruption
                self._close(s)
        while live:
            spec, result, bench = ex.next_result()
            s = live[spec.set_index]
            record = TestRecord(spec.set_index, self.config.phase(spec.set_index), self._space.to_named(s.x),
                                spec.rep, result, now_timestamp(), spec.noise_seed, bench)
            journal.append(record)
            if result.bench_fault:
                self._faults_in_a_row += 1
                if self._faults_in_a_row >= MAX_BENCH_FAULTS_IN_A_ROW:
                    raise BenchBroken(f"the bench failed {self._faults_in_a_row} tests in a row, the last on "
                                      f"{bench}: {result.crash_reason()}")
                ex.submit(spec)  # the same repetition, the same noise: as if it had not happened
                self._report(len(journal.records), record)
                continue
            self._faults_in_a_row = 0
            s.out.discard(spec.rep)
            s.records[spec.rep] = record
            if not s.out:
                self._launch(s)
                if not s.out:
                    del live[s.index]
                    self._close(s)
            self._report(len(journal.records), record)

    def _close(self, s: _OpenSet) -> None:
        tests = tuple(gap_free(s.records))
        verdict = self.config.rule.judge([r.result for r in tests])
        self._add(SetResult(s.index, self.config.phase(s.index), s.x, verdict, tests))

    def _add(self, *decided: SetResult) -> None:
        self._done.extend(decided)
        if decided and self.on_sets is not None:
            self.on_sets(tuple(self._done))

    def _launch(self, s: _OpenSet) -> None:
        """Submit as many further repetitions of `s` as the rule says every continuation needs, counting from
        the first missing one (those after it that finished before an interruption are not run again)."""
        done = gap_free(s.records)
        needed = self.config.rule.still_needed([r.result for r in done])
        params = self._space.to_offsets(s.x)
        for rep in range(len(done) + 1, len(done) + 1 + needed):
            if rep in s.records:
                continue
            s.out.add(rep)
            self.executor.submit(TestSpec(s.index, rep, params, noise_seed(self.config.seed, s.index, rep),
                                          self.config.noise, self._space.slot_types))

    # -- proposals ------------------------------------------------------------------------------------
    def _propose(self, round_index: int, indices: range) -> list[tuple[float, ...]]:
        if round_index == 0:  # each initial point drawn for its own set index, as journals of format 1 have it
            X, Y = np.empty((0, self._space.dim)), np.empty((0, 1))
            return [self._space.snap(self._init_sampler.suggest(self._space, X, Y, i)) for i in indices]
        done = sorted((s for s in self._done if s.index < indices.start), key=lambda s: s.index)
        X = np.array([s.x for s in done], dtype=float).reshape(len(done), self._space.dim)
        Y = np.array([[s.value] for s in done], dtype=float).reshape(len(done), 1)
        # Always a whole batch, of which a last, short round runs the first points: so a campaign extended
        # on resume proposes what a longer one would have.
        batch = self._bo_sampler.suggest_batch(self._space, X, Y, round_index, self.config.batch)[:len(indices)]
        return [self._space.snap(x) for x in batch]  # an integer parameter is used, and recorded, rounded

    def _check_against_journal(self, indices: range, points: list[tuple[float, ...]],
                               by_set: dict[int, list[TestRecord]]) -> list[tuple[float, ...]]:
        """A resumed round must propose what the interrupted one did; anything else means the journal belongs
        to another version of the campaign. The journal's points are the ones kept: on another machine the
        linear algebra may round the last bits differently."""
        kept = []
        for i, x in zip(indices, points):
            if i in by_set:
                tested = self._space.from_named(by_set[i][0].params)
                if not np.allclose(tested, x, rtol=1e-6, atol=1e-9):
                    raise JournalError(f"set {i + 1} was tested with {dict(by_set[i][0].params)} but this campaign "
                                       f"proposes {self._space.to_named(x)}: the journal is from another version")
                x = tested
            kept.append(x)
        return kept

    # -- the journal ---------------------------------------------------------------------------------
    def _group(self, records: list[TestRecord]) -> dict[int, list[TestRecord]]:
        by_set: dict[int, list[TestRecord]] = {}
        for r in records:
            by_set.setdefault(r.set_index, []).append(r)
        for i, rs in by_set.items():
            if any(r.params != rs[0].params for r in rs):
                raise JournalError(f"set {i + 1} has tests with different parameters")
            try:
                self._space.from_named(rs[0].params)
            except KeyError as e:
                raise JournalError(f"set {i + 1} lacks parameter {e}") from None
            rs.sort(key=lambda r: r.rep)
        return by_set

    def _decided(self, records: list[TestRecord]) -> SetResult | None:
        counted = gap_free({r.rep: r for r in records if not r.result.bench_fault})
        if not counted:
            return None
        verdict = self.config.rule.judge([r.result for r in counted])
        if not verdict.decided:
            return None
        i = counted[0].set_index
        return SetResult(i, self.config.phase(i), self._space.from_named(counted[0].params), verdict, tuple(counted))

    def _report(self, tests_done: int, last: TestRecord | None) -> None:
        if self.on_progress is not None:
            self.on_progress(Progress(len(self._done), self.config.total_sets, tests_done, best_set(self._done),
                                      last, self.executor.running, self.executor.capacity))

    def _check_header(self, journal: Journal) -> None:
        stored = CampaignConfig.from_header(journal.header)
        if stored.space != self._space:
            raise JournalError(
                f"{journal.path}: the journal was written for a different parameter space "
                f"(journal: {stored.space.describe()}; given: {self._space.describe()})"
            )
        differ = [
            f"{f.name} {getattr(stored, f.name)!r} (journal) vs {getattr(self.config, f.name)!r} (given)"
            for f in dataclasses.fields(self.config)
            if f.name not in ("space", "trials") and getattr(stored, f.name) != getattr(self.config, f.name)
        ]
        if differ:
            raise JournalError(f"{journal.path}: the journal was written with other options: {'; '.join(differ)}")
