"""The campaign's progress line: sets decided, benches busy, tests per second and an honest time left
(`testctl.time_left`: the tests the sets left will take, at the recent rate).

Off a terminal (a CI log, a file) the bar draws nothing after its label, so the same status also goes out
as a plain line every PLAIN_EVERY_TESTS tests or PLAIN_EVERY_S seconds, whichever comes first.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from hakoniwa.wire.measure import LAP_TIME, Measure
from testctl.campaign.loop import Progress
from testctl.campaign.repetition import RepetitionRule
from testctl.time_left import RecentRate, expected_tests_left, time_left

PLAIN_EVERY_TESTS = 10
PLAIN_EVERY_S = 60.0


class ProgressLine:
    """Feeds a click progress bar (over sets) with a status text; call it with every `Progress`."""

    def __init__(self, bar, clock=time.monotonic, plain: Callable[[str], None] | None = None,
                 measure: Measure = LAP_TIME, repeats: int = RepetitionRule.repeats) -> None:
        self.bar = bar
        self.measure = measure
        self.repeats = repeats  # a set's most tests: what a set is counted as before any is decided
        self.clock = clock
        self.plain = plain  # where plain lines go when no terminal shows the bar
        self.shown = 0
        self._rate: RecentRate | None = None  # from the first report (the journal loaded) on
        self._plain_at: tuple[float, int] | None = None  # (time, tests done) of the last plain line

    def __call__(self, p: Progress) -> None:
        now = self.clock()
        if self._rate is None:
            self._rate = RecentRate(self.clock)
        elif p.last_test is not None:
            self._rate.finished()
        status = self.status(p, now)
        self.bar.update(p.sets_done - self.shown, current_item=status)
        self.shown = p.sets_done
        if self.plain is not None and (self._plain_at is None or p.tests_done - self._plain_at[1] >= PLAIN_EVERY_TESTS
                                       or now - self._plain_at[0] >= PLAIN_EVERY_S):
            self._plain_at = (now, p.tests_done)
            self.plain(f"sets {p.sets_done}/{p.sets_total}, tests {p.tests_done}, {status}")

    def rate(self) -> float | None:
        """Tests per second over the recent window (None until two tests have finished)."""
        return self._rate.rate() if self._rate is not None else None

    def status(self, p: Progress, now: float) -> str:
        parts = [f"benches {p.running}/{p.benches} busy"]
        left = time_left(expected_tests_left(p.sets_total - p.sets_done, p.sets_done, p.tests_done, self.repeats),
                         self.rate())
        if left is not None:
            parts.append(left)
        m = self.measure
        parts.append(f"best {m.format(p.best.value)} (set {p.best.number})" if p.best else f"no {m.word} yet")
        return ", ".join(parts)
