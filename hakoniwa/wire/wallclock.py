"""Wall-clock bounds on waits that count simulated time: a clock that stands still, or creeps, must end in
a clear word, never in a hang.

Everything the bench waits for is measured in simulated time (a test's time limit, the image check's first
200 ms), and simulated time moves only as fast as the program lets it: an emulated clock that never
advances (a v850 image whose start-up blocks) made `hako try` wait for ever with empty logs. So each such
wait gets a ceiling in wall time, derived from how far simulated time must get and the rate this machine
is measured to run it at over the wait's first MEASURE_S (sim-s per wall-s), times a generous FACTOR, and
never below FLOOR_S: a loaded machine slows a run down a few times, not a hundred. A clock that has not
moved at all by then is past its ceiling at the floor.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from hakoniwa.wire.timebase import US_PER_S

MEASURE_S = 2.0  # the early part of a wait whose rate sets its ceiling
FACTOR = 10.0  # how much slower than that the rest may run
FLOOR_S = 60.0  # the least ceiling: start-up, a slow first test, a busy machine


class WallCeiling:
    """A wall-clock ceiling for getting `target_us` of simulated time, started now."""

    def __init__(self, target_us: int, *, floor_s: float = FLOOR_S, factor: float = FACTOR,
                 measure_s: float = MEASURE_S, clock: Callable[[], float] = time.monotonic) -> None:
        self.target_us = target_us
        self.floor_s = floor_s
        self.factor = factor
        self.measure_s = measure_s
        self._clock = clock
        self._start = clock()
        self.rate: float | None = None  # sim-s per wall-s over the first measure_s, once measured
        self.ceiling_s = floor_s

    def exceeded(self, sim_us: int) -> str | None:
        """Why the wait is over its ceiling with simulated time at `sim_us`, or None while it is not."""
        elapsed = self._clock() - self._start
        if self.rate is None and elapsed >= self.measure_s:
            self.rate = sim_us / US_PER_S / elapsed
            if self.rate > 0:
                self.ceiling_s = max(self.floor_s, self.factor * self.target_us / US_PER_S / self.rate)
        if elapsed <= self.ceiling_s:
            return None
        if not self.rate:
            return f"simulated time did not move from {sim_us / US_PER_S:g} s in {elapsed:.0f} s of wall time"
        return (f"simulated time reached {sim_us / US_PER_S:.2f} of {self.target_us / US_PER_S:g} s in {elapsed:.0f} s "
                f"of wall time, past its ceiling of {self.ceiling_s:.0f} s ({self.factor:g} x the "
                f"{self.rate:.3g} sim-s per wall-s of its first {self.measure_s:g} s)")
