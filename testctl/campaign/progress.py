"""The campaign's progress line: sets decided, benches busy, tests per second and an honest time left.

Time left is (tests still to run) / (recent test rate): both taken from recent work, not from the average
since the start, because a campaign's tests do not all cost the same (a start-up, a round of slow sets, a
machine that got busy), and an estimate from the whole past runs low by as much.

Off a terminal (a CI log, a file) the bar draws nothing after its label, so the same status also goes out
as a plain line every PLAIN_EVERY_TESTS tests or PLAIN_EVERY_S seconds, whichever comes first.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable

from testctl.campaign.loop import Progress
from testctl.campaign.measure import LAP_TIME, Measure

RECENT_TESTS = 30  # the window the rate is measured over
DEFAULT_TESTS_PER_SET = 3.0  # before any set is decided: the paper's first-to-3
PLAIN_EVERY_TESTS = 10
PLAIN_EVERY_S = 60.0


def format_duration(seconds: float) -> str:
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


class ProgressLine:
    """Feeds a click progress bar (over sets) with a status text; call it with every `Progress`."""

    def __init__(self, bar, clock=time.monotonic, plain: Callable[[str], None] | None = None,
                 measure: Measure = LAP_TIME) -> None:
        self.bar = bar
        self.measure = measure
        self.clock = clock
        self.plain = plain  # where plain lines go when no terminal shows the bar
        self.shown = 0
        self._finished: deque[float] = deque(maxlen=RECENT_TESTS + 1)
        self._tests_at_start: int | None = None
        self._plain_at: tuple[float, int] | None = None  # (time, tests done) of the last plain line

    def __call__(self, p: Progress) -> None:
        now = self.clock()
        if self._tests_at_start is None:
            self._tests_at_start = p.tests_done
            self._finished.append(now)
        elif p.last_test is not None:
            self._finished.append(now)
        status = self.status(p, now)
        self.bar.update(p.sets_done - self.shown, current_item=status)
        self.shown = p.sets_done
        if self.plain is not None and (self._plain_at is None or p.tests_done - self._plain_at[1] >= PLAIN_EVERY_TESTS
                                       or now - self._plain_at[0] >= PLAIN_EVERY_S):
            self._plain_at = (now, p.tests_done)
            self.plain(f"sets {p.sets_done}/{p.sets_total}, tests {p.tests_done}, {status}")

    def rate(self) -> float | None:
        """Tests per second over the recent window (None until two tests have finished)."""
        if len(self._finished) < 3:
            return None
        return (len(self._finished) - 1) / max(self._finished[-1] - self._finished[0], 1e-9)

    def status(self, p: Progress, now: float) -> str:
        parts = [f"benches {p.running}/{p.benches} busy"]
        rate = self.rate()
        if rate is not None:
            per_set = p.tests_done / p.sets_done if p.sets_done else DEFAULT_TESTS_PER_SET
            left = max(p.sets_total - p.sets_done, 0) * per_set
            parts += [f"{rate:.2f} tests/s", f"~{format_duration(left / rate)} left"]
        m = self.measure
        parts.append(f"best {m.format(p.best.value)} (set {p.best.number})" if p.best else f"no {m.word} yet")
        return ", ".join(parts)
