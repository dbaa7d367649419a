"""The time left on a progress line: the tests still to run, at the rate tests have recently finished.

The rate is taken over the last RECENT_TESTS tests, not from the start, because tests do not all cost the
same (a start-up, a round of slow sets, a machine that got busy) and an average over the whole past runs low
by as much. `hako run`, `hako test` and `--validate` all say it the same way, so a user can tell a slow
machine from a stuck run whichever command they started.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable

RECENT_TESTS = 30  # the window the rate is measured over


def format_duration(seconds: float) -> str:
    """A duration as a person reads it on a progress line: seconds, minutes or hours, never more digits
    than an estimate deserves."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


class RecentRate:
    """Tests per second over the last RECENT_TESTS finished tests, from when the count started."""

    def __init__(self, clock: Callable[[], float] = time.monotonic) -> None:
        self.clock = clock
        self._times: deque[float] = deque([clock()], maxlen=RECENT_TESTS + 1)

    def finished(self) -> None:
        """One more test finished now."""
        self._times.append(self.clock())

    def rate(self) -> float | None:
        """Tests per second (None until two tests have finished: one is no rate, only a start-up)."""
        if len(self._times) < 3:
            return None
        return (len(self._times) - 1) / max(self._times[-1] - self._times[0], 1e-9)


def expected_tests_left(sets_left: int, sets_done: int, tests_done: int, repeats: int) -> float:
    """The tests still to run for `sets_left` sets, each decided by the first to a majority of at most
    `repeats` tests (3 of 5). A set's count is known only once it is decided: from a majority (3) to
    `repeats` (5), and nearer 3 the more its tests agree. So this is an expected count, not a bound: the mean
    of the decided sets' tests (`tests_done / sets_done`, which includes the retries of crashed tests), and
    before any set is decided the upper count `repeats`, so the first estimate errs long, never short."""
    per_set = tests_done / sets_done if sets_done else float(repeats)
    return max(sets_left, 0) * per_set


def time_left(tests_left: float, rate: float | None) -> str | None:
    """`1.25 tests/s, ~3 min left`, or None while there is no rate yet."""
    if rate is None:
        return None
    return f"{rate:.2f} tests/s, ~{format_duration(tests_left / rate)} left"


class Countdown:
    """The time left of a known number of tests (`hako test`'s runs, `--validate`'s draws): call `finished`
    as each one finishes, and show what it says."""

    def __init__(self, total: int, clock: Callable[[], float] = time.monotonic) -> None:
        self.left = total
        self.rate = RecentRate(clock)

    def finished(self) -> str | None:
        """One test finished: the rate and time left now (None while there is no rate yet)."""
        self.left = max(self.left - 1, 0)
        self.rate.finished()
        return time_left(self.left, self.rate.rate())
