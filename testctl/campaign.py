"""A parameter-search campaign: the paper's experiment loop (section 3.4.3, 4.1) made resumable.

`init_points` random parameter sets, then `trials` sets proposed by the sampler; each set is tested until the
repetition rule decides it, and every test goes to the journal before the next one starts. The journal is the
campaign's only state: resuming rebuilds everything from it, continues an interrupted set with its remaining
repetitions, and, because suggestions depend only on (seed, set index, finished sets), proposes the same
sets an uninterrupted run would have.

The campaign knows nothing of processes or mmap files: it calls `run_test({data offset: value})`.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from testctl.journal import JOURNAL_FILE, Journal, JournalError, TestRecord, now_timestamp, read_journal
from testctl.objective import RepetitionRule, Verdict
from testctl.result import TestResult
from testctl.sampler import SAMPLERS, RandomSampler, Sampler
from testctl.space import ParameterSpace

PHASE_INIT = "init"  # the random initial design
PHASE_BO = "bo"  # an optimization iteration, whichever sampler proposes it

RunTest = Callable[[Mapping[int, float]], TestResult]


@dataclass(frozen=True)
class CampaignConfig:
    """Everything that determines a campaign's sequence of parameter sets. Only `trials` may change on
    resume (to extend a campaign); the rest is checked against the journal's header."""

    space: ParameterSpace = field(default_factory=ParameterSpace.default)
    trials: int = 100
    init_points: int = 5
    repeats: int = 5
    max_crashes: int = 3
    seed: int = 0
    optimizer: str = "gpyopt"

    def __post_init__(self) -> None:
        if self.optimizer not in SAMPLERS:
            raise ValueError(f"unknown optimizer {self.optimizer!r}; choose from {', '.join(SAMPLERS)}")
        if self.trials < 0:
            raise ValueError(f"trials must be at least 0, got {self.trials}")
        if self.init_points < 1:
            raise ValueError(f"init_points must be at least 1, got {self.init_points}")
        if self.seed < 0:
            raise ValueError(f"seed must be at least 0, got {self.seed}")
        RepetitionRule(self.repeats, self.max_crashes)  # validates both

    @property
    def rule(self) -> RepetitionRule:
        return RepetitionRule(self.repeats, self.max_crashes)

    @property
    def total_sets(self) -> int:
        return self.init_points + self.trials

    def phase(self, index: int) -> str:
        return PHASE_INIT if index < self.init_points else PHASE_BO

    def header(self) -> dict[str, Any]:
        options = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name != "space"}
        return {"space": self.space.to_dict(), "options": options}

    @classmethod
    def from_header(cls, header: Mapping[str, Any]) -> CampaignConfig:
        try:
            return cls(space=ParameterSpace.from_dict(header["space"]), **header["options"])
        except (KeyError, TypeError, ValueError) as e:  # SpaceError is a ValueError
            raise JournalError(f"the journal header does not describe a campaign: {e}") from None


@dataclass(frozen=True)
class SetResult:
    """A decided parameter set: its point (in `space.names` order), verdict and tests."""

    index: int
    phase: str
    x: tuple[float, ...]
    verdict: Verdict
    tests: tuple[TestRecord, ...]

    @property
    def value(self) -> float:
        assert self.verdict.value is not None
        return self.verdict.value

    @property
    def wall_s(self) -> float:
        return sum(t.result.wall_s for t in self.tests)


def best_set(sets: list[SetResult]) -> SetResult | None:
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


@dataclass(frozen=True)
class CampaignSummary:
    config: CampaignConfig
    sets: tuple[SetResult, ...]
    best: SetResult | None
    n_tests: int  # all tests in the journal, including earlier sessions
    tests_run: int  # tests run by this session
    wall_s: float  # this session's wall time
    test_wall_s: float  # wall time of all tests in the journal


def load_config(out_dir: Path) -> CampaignConfig:
    """The configuration a campaign directory was started with (for `--resume DIR` without options)."""
    header, _ = read_journal(Path(out_dir) / JOURNAL_FILE)
    return CampaignConfig.from_header(header)


class Campaign:
    """Runs (or, with `resume=True`, continues) the campaign journaled in `out_dir`."""

    def __init__(
        self,
        config: CampaignConfig,
        out_dir: Path,
        run_test: RunTest,
        *,
        on_progress: Callable[[Progress], None] | None = None,
        resume: bool = False,
    ) -> None:
        self.config = config
        self.out_dir = Path(out_dir)
        self.run_test = run_test
        self.on_progress = on_progress
        self.resume = resume
        self._init_sampler: Sampler = RandomSampler(config.seed)
        self._bo_sampler: Sampler = SAMPLERS[config.optimizer](config.seed)

    def run(self) -> CampaignSummary:
        started = time.monotonic()
        path = self.out_dir / JOURNAL_FILE
        if self.resume:
            journal = Journal.open(path)
            self._check_header(journal)
        else:
            self.out_dir.mkdir(parents=True, exist_ok=True)
            journal = Journal.create(path, self.config.header())
        with journal:
            done, pending = self._replay(journal.records)
            n_tests = len(journal.records)
            self._report(done, n_tests, None)
            while len(done) < self.config.total_sets:
                index = len(done)
                records, pending = pending, []  # only the first set may have been interrupted
                x = self._space.from_named(records[0].params) if records else self._suggest(done, index)
                verdict = self.config.rule.judge([r.result for r in records])
                while not verdict.decided:
                    record = TestRecord(
                        index,
                        self.config.phase(index),
                        self._space.to_named(x),
                        len(records) + 1,
                        self.run_test(self._space.to_offsets(x)),
                        now_timestamp(),
                    )
                    journal.append(record)
                    records.append(record)
                    verdict = self.config.rule.judge([r.result for r in records])
                    self._report(done, len(journal.records), record)
                done.append(SetResult(index, self.config.phase(index), x, verdict, tuple(records)))
                self._report(done, len(journal.records), None)
            all_records = journal.records
        return CampaignSummary(
            config=self.config,
            sets=tuple(done),
            best=best_set(done),
            n_tests=len(all_records),
            tests_run=len(all_records) - n_tests,
            wall_s=time.monotonic() - started,
            test_wall_s=sum(r.result.wall_s for r in all_records),
        )

    @property
    def _space(self) -> ParameterSpace:
        return self.config.space

    def _suggest(self, done: list[SetResult], index: int) -> tuple[float, ...]:
        X = np.array([s.x for s in done], dtype=float).reshape(len(done), self._space.dim)
        Y = np.array([[s.value] for s in done], dtype=float).reshape(len(done), 1)
        sampler = self._init_sampler if self.config.phase(index) == PHASE_INIT else self._bo_sampler
        return sampler.suggest(self._space, X, Y, index)

    def _report(self, done: list[SetResult], tests_done: int, last: TestRecord | None) -> None:
        if self.on_progress is not None:
            self.on_progress(Progress(len(done), self.config.total_sets, tests_done, best_set(done), last))

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

    def _replay(self, records: list[TestRecord]) -> tuple[list[SetResult], list[TestRecord]]:
        """The decided sets in the journal, and the tests of an undecided last set (empty if none)."""
        done: list[SetResult] = []
        current: list[TestRecord] = []
        for r in records:
            if r.set_index != len(done):
                raise JournalError(f"test of set {r.set_index} found where set {len(done)} was expected")
            if current and r.params != current[0].params:
                raise JournalError(f"set {r.set_index} has tests with different parameters")
            try:
                x = self._space.from_named(r.params)
            except KeyError as e:
                raise JournalError(f"set {r.set_index} lacks parameter {e}") from None
            current.append(r)
            verdict = self.config.rule.judge([t.result for t in current])
            if verdict.decided:
                done.append(SetResult(r.set_index, r.phase, x, verdict, tuple(current)))
                current = []
        return done, current
