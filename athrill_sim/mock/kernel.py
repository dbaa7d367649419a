"""The virtual clock of the mock EV3RT kernel and its lockstep with the physics process.

Athrill's time does not run on its own: it is the wake-up time of the robot task. `tslp_tsk` is where time
passes. It publishes the task's outputs together with the time it will wake up (`Tx.NEXT_WAKE`, then
`Tx.ANSWER_SEQ`), then waits until the physics process has published the sensor snapshot for exactly that
instant (the unity time in the RX header reaches it). Computation takes zero simulated time, except that each
call reading a clock or a device spends `CALL_COST_US` (a loop that polls without sleeping then sees time pass,
and moves on to the next physics step once it has spent a whole one), so the result of a test depends only on
the parameters, never on how fast either process happens to run. This is the native runtime's clock
(runtime/src/sim_time.h, kernel.c), for one task. See `hakoniwa/physics/sync.py` for the physics side.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import NoReturn

from hakoniwa.wire.protocol import HEADER_SIZE, NEVER_WAKES, Header, MappedFile, Rx, Tx
from hakoniwa.wire.timebase import BUTTON_POLL_US, CALL_COST_US, PHYSICS_STEP_US
from hakoniwa.wire.waiting import futex_wake, pid_alive, wait_for, wait_word

TEST_WAIT_NAP_S = 0.005  # a spare Athrill waits a whole test, mostly for nothing


class KernelExit(Exception):
    """The physics process is gone, or this Athrill's test will never run; nothing left to do."""


def _watch(unity: MappedFile):
    physics_pid = unity.read_u32(Rx.PHYSICS_PID)

    def check() -> None:
        if not pid_alive(physics_pid):
            raise KernelExit(f"physics process {physics_pid} is gone")

    return check


class Kernel:
    def __init__(self, unity: MappedFile, athrill: MappedFile) -> None:
        self.unity = unity
        self.athrill = athrill
        self.now_us = unity.unity_time_us  # the tick: the time of the snapshot the program sees
        self.spent_us = 0  # what the program's calls spent since the tick, always below one step
        self._serving = False  # the snapshot's hooks run: a call there cannot move time on
        self._check_physics = _watch(unity)
        self._snapshot_address = unity.address(Header.UNITY_TIME)  # the physics side rings here
        self._answer_address = athrill.address(HEADER_SIZE + Tx.ANSWER_SEQ)
        athrill.write_u32(Tx.ATHRILL_PID, os.getpid())
        # Run at every new snapshot before the task goes on, as the C runtime's kernel polls the buttons.
        self.on_snapshot: list[Callable[[], None]] = []
        # While this says so, the kernel wakes at every multiple of BUTTON_POLL_US too, as EV3RT's button
        # cyclic runs whatever the task does (the hooks see each such snapshot).
        self.watch_buttons: Callable[[], bool] = lambda: False

    def now(self) -> int:
        """What the program's clocks read: the tick and what its calls spent since."""
        return self.now_us + self.spent_us

    def spend_call(self) -> None:
        """A call that reads a clock or a device: it takes `CALL_COST_US`; a step spent whole moves time on to
        the next physics step first."""
        self.spent_us += CALL_COST_US
        if self.spent_us < PHYSICS_STEP_US:
            return
        self.spent_us = PHYSICS_STEP_US - 1
        if not self._serving:
            self._await_snapshot(self.now_us + PHYSICS_STEP_US)

    def sleep(self, duration_us: int) -> None:
        """tslp_tsk: sleep at least `duration_us`, rounded up to whole physics steps."""
        if duration_us <= 0:
            return
        steps = -(-duration_us // PHYSICS_STEP_US)
        due = self.now_us + steps * PHYSICS_STEP_US
        while self.now_us < due:
            wake = due
            if self.watch_buttons():
                wake = min(due, self._next_button_poll())
            self._await_snapshot(wake)

    def _next_button_poll(self) -> int:
        return (self.now_us // BUTTON_POLL_US + 1) * BUTTON_POLL_US

    def _await_snapshot(self, wake: int) -> None:
        self._publish(wake)
        unity = self.unity
        wait_word(self._snapshot_address, lambda: unity.unity_time_us & 0xFFFFFFFF,
                  lambda: unity.unity_time_us >= wake, self._check_physics)
        self.now_us = wake
        self.spent_us = 0
        self._serving = True
        try:
            for hook in self.on_snapshot:
                hook()
        finally:
            self._serving = False

    def finish(self) -> None:
        """The task returned (or sleeps for good): while a click handler is set the kernel still wakes for the
        button cyclic, as on EV3RT; then outputs stay as they are and no wake-up will ever be due."""
        while self.watch_buttons():
            self._await_snapshot(self._next_button_poll())
        self._publish(NEVER_WAKES)

    def sleep_forever(self) -> NoReturn:
        """The task sleeps with no timeout: it waits until it is killed (or the physics process is gone)."""
        self.finish()
        wait_for(lambda: False, self._check_physics, spin_s=0.0, nap_s=TEST_WAIT_NAP_S)
        raise AssertionError("unreachable")

    def _publish(self, wake_us: int) -> None:
        a = self.athrill
        a.write("q", Tx.NEXT_WAKE, wake_us)
        a.athrill_time_us = self.now_us
        a.unity_time_us = self.unity.unity_time_us  # the echo the real Athrill writes too
        a.write_u32(Tx.ANSWER_SEQ, (a.read_u32(Tx.ANSWER_SEQ) + 1) & 0xFFFFFFFF)  # last
        futex_wake(self._answer_address)


def wait_for_test(unity: MappedFile, test_seq: int) -> None:
    """Block until the physics process starts test `test_seq`.

    The physics process launches the next test's Athrill while the current test still runs, so that its
    start-up cost overlaps useful work; that process must not touch anything until its own test begins.
    """
    check_physics = _watch(unity)

    def check() -> None:
        check_physics()
        if (current := unity.read_u32(Rx.TEST_SEQ)) > test_seq:
            raise KernelExit(f"test {test_seq} will not run (physics is at test {current})")

    wait_for(lambda: unity.read_u32(Rx.TEST_SEQ) == test_seq, check, spin_s=0.0, nap_s=TEST_WAIT_NAP_S)
