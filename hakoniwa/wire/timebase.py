"""Simulation time constants and the tick-quantized scheduler.

Time is an integer number of microseconds everywhere, so that no float drift can make two runs of the same
test differ. The scheduler follows rcssserver's StandardTimer: a stream with period P fires at the first
tick whose elapsed time reaches P x count, so a 37.5 ms stream on a 10 ms tick fires at 40, 80, 120, 150,
190, 230, 270 and 300 ms of every 300 ms.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

US_PER_S = 1_000_000

PHYSICS_STEP_US = 1_000  # the paper's Unity simulation precision, 0.001 s
CONTROL_PERIOD_US = 100_000  # tslp_tsk(100000) in Fig. 7
ALLOWED_TIME_DIFF_US = 20_000  # the largest Unity-Athrill time difference the paper allows
EVENT_CHECK_PERIOD_US = 10_000  # goal, wall and time-limit checks
BUTTON_POLL_US = 10_000  # EV3RT's brick_button_cyc, which sees clicks (brick_dri.cfg: CRE_CYC(BRICK_BTN_CYC, 10000))
TRACE_PERIOD_US = 50_000  # trajectory samples
# A robot program's computation takes no simulated time, except that each call that reads a clock or uses a
# device (a sensor read, a motor command, a button, a yield) takes this much: a loop that polls without ever
# sleeping then advances simulated time, as on the robot, the same way on every machine (docs/NATIVE.md).
CALL_COST_US = 1
# What a native program's wall clock (CLOCK_REALTIME, std::chrono::system_clock, time()) reads when its test
# starts: 2026-01-01T00:00:00Z, so that the timestamps a program writes repeat from run to run.
CLOCK_EPOCH_S = 1_767_225_600



def on_tick_s(seconds: float) -> float:
    """A time in seconds on the bench's tick (the physics step): a mean of laps, 28.209999999999997 as its sum
    divided, read as 28.21, as every lap it is made of and as `hako try` prints one."""
    return round(seconds * US_PER_S / PHYSICS_STEP_US) * PHYSICS_STEP_US / US_PER_S

@dataclass
class Stream:
    name: str
    period_us: int
    callback: Callable[[int], None]
    start_us: int = 0
    count: int = 1  # the next firing is due at start + period x count

    def due_us(self) -> int:
        return self.start_us + self.period_us * self.count


@dataclass
class Scheduler:
    """Runs periodic streams on a fixed tick. `next_tick()` tells the caller how far it may batch work.

    The first tick any stream is due at is kept (`_due_us`) and recomputed only when a stream fires, is
    added or reset: the physics loop asks for it at every tick it stops at, and a tick where nothing is due
    then costs a comparison."""

    tick_us: int
    now_us: int = 0
    streams: list[Stream] = field(default_factory=list)
    _due_us: int = field(default=0, init=False, repr=False)

    def __post_init__(self) -> None:
        if self.tick_us <= 0:
            raise ValueError("tick must be positive")
        self._find_due()

    def _find_due(self) -> None:
        self._due_us = min((self.quantize(s.due_us()) for s in self.streams), default=self.now_us + self.tick_us)

    def add(self, name: str, period_us: int, callback: Callable[[int], None]) -> Stream:
        if period_us <= 0:
            raise ValueError(f"stream {name!r}: period must be positive")
        stream = Stream(name, period_us, callback, start_us=self.now_us)
        self.streams.append(stream)
        self._find_due()
        return stream

    def quantize(self, time_us: int) -> int:
        """The first tick at or after `time_us`: when something due at `time_us` actually happens."""
        return -(-time_us // self.tick_us) * self.tick_us

    def next_tick(self) -> int:
        """The next tick at which any stream fires (at least one tick ahead)."""
        return max(self._due_us, self.now_us + self.tick_us)

    def advance_to(self, time_us: int) -> None:
        """Move to tick `time_us` and fire every stream that is due there, in the order they were added."""
        if time_us % self.tick_us:
            raise ValueError(f"{time_us} us is not on the {self.tick_us} us tick")
        self.now_us = time_us
        if time_us < self._due_us:  # on the tick, so before every stream's quantized due time: none is due
            return
        for stream in self.streams:
            if time_us >= stream.due_us():  # at most once a tick, like rcssserver's timer
                stream.count += 1
                stream.callback(time_us)
        self._find_due()

    def reset(self) -> None:
        self.now_us = 0
        for stream in self.streams:
            stream.start_us = 0
            stream.count = 1
        self._find_due()
