"""Turning repeated tests of one parameter set into the number the optimizer minimizes.

Paper, section 4.1: the same parameters may succeed or fail depending on the load of the machine, so each set
is tested repeatedly; whichever of success or failure reaches 3 first decides the set (at most 5 tests). A
successful set scores the mean lap time of its successes, a failed one the bench's time limit (60 s in the
paper), on the bench's tick; under ET Robocon's score, minus the mean score (the optimizers minimise) and 0
for a failed set: each objective says (its `set_value` and `failure_value`). Here that rule is generalized to
`repeats` tests with a strict majority `repeats // 2 + 1` needed for success.

A CRASH of the robot program (Athrill died or went silent) may or may not be the parameters' doing, unlike a
wall hit or a time-out, so it is not counted and the test is repeated. Parameters that make the program crash
every time (a NaN, a division by zero in the app) would then be retried forever, so only the first
`max_crashes` crashes of a set are forgiven; each later one counts as a failure of the parameters. A crash the
bench itself caused (`TestResult.bench_fault`) is no test of the parameters at all: it is ignored here, and
the campaign runs that repetition again.

Repetitions run in parallel without changing the verdict: `still_needed` is the number of further tests that
any continuation of the sequential rule must run, so launching exactly that many at once, judging them in
repetition order, and repeating gives the very verdict the one-at-a-time rule gives.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from hakoniwa.wire.objective import DEFAULT, Objective, objective_named
from hakoniwa.wire.protocol import Event
from hakoniwa.wire.result import TestResult

# The paper's time limit (section 4.1), what a failure scores where no bench says otherwise: a rule made
# without a bench, and a journal written before campaigns recorded their bench's limit (all were 60 s then).
PAPER_PENALTY_S = 60.0
# Under ET Robocon's score every one of these is a scored run (`TestResult.success`).
# Under the lap objective, COMPLETED is the program's own end of its run (ET Robocon's completion notice)
# before any lap: it ends the test early, as a program that stops driving ends it at the time limit, and
# scores as that would: a failure. Under the completed objective it is the success (`TestResult.success`),
# and a test that ends without it fails.
_OUTCOMES = (Event.GOAL, Event.TIME_OVER, Event.HIT_WALL, Event.COMPLETED, Event.FINISH, Event.COURSE_OUT)


@dataclass(frozen=True)
class Verdict:
    """The state of one parameter set after some tests. `value` is None until the set is decided."""

    successes: int
    failures: int  # including crashes beyond the allowance
    crashes: int  # all crashes, forgiven or not
    laps: tuple[float, ...]  # each success's cost: its lap time (minus its score under ET Robocon's)
    decided: bool
    success: bool
    value: float | None


@dataclass(frozen=True)
class RepetitionRule:
    """First to `needed` of at most `repeats` counted tests; CRASH retried up to `max_crashes` times."""

    repeats: int = 5
    max_crashes: int = 3
    penalty_s: float = PAPER_PENALTY_S  # the bench's time limit: a failure scores as a test that used it all
    objective: Objective = field(default_factory=lambda: objective_named(DEFAULT))  # values a set and a failure

    def __post_init__(self) -> None:
        if self.repeats < 1:
            raise ValueError(f"repeats must be at least 1, got {self.repeats}")
        if self.max_crashes < 0:
            raise ValueError(f"max_crashes must be at least 0, got {self.max_crashes}")
        if not self.penalty_s > 0:
            raise ValueError(f"penalty_s must be positive, got {self.penalty_s}")

    @property
    def failure_value(self) -> float:
        return self.objective.failure_value(self.penalty_s)

    @property
    def needed(self) -> int:
        return self.repeats // 2 + 1

    @property
    def failures_needed(self) -> int:
        return self.repeats - self.needed + 1

    def still_needed(self, results: Sequence[TestResult]) -> int:
        """How many more tests every way of finishing this set must run (0 once it is decided): so many can
        run at once. Until that many have come back, neither side can reach its count."""
        v = self.judge(results)
        return 0 if v.decided else min(self.needed - v.successes, self.failures_needed - v.failures)

    def judge(self, results: Sequence[TestResult]) -> Verdict:
        """The verdict on a set's results in repetition order (bench faults left out)."""
        successes = failures = crashes = 0
        laps: list[float] = []
        for r in results:
            if r.bench_fault:
                continue
            if r.event == Event.CRASH:
                crashes += 1
                failures += crashes > self.max_crashes
            elif r.success:
                assert r.cost is not None
                successes += 1
                laps.append(r.cost)
            elif r.event in _OUTCOMES:
                failures += 1
            else:
                raise ValueError(f"{r.event.name} is not the outcome of a finished test")
        success = successes >= self.needed
        # Failed once success can no longer be reached within `repeats` counted tests.
        failed = failures >= self.failures_needed
        mean = sum(laps) / len(laps) if laps else 0.0
        value = (self.objective.set_value(mean) if success else self.failure_value) \
            if success or failed else None
        return Verdict(successes, failures, crashes, tuple(laps), success or failed, success, value)
