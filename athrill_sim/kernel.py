"""The virtual clock of the mock EV3RT kernel and its lockstep with the physics process.

Athrill's time does not run on its own: it is the wake-up time of the robot task. `tslp_tsk` is the only
place where time passes. It publishes the task's outputs together with the time it will wake up, then
waits until the physics process has published the sensor snapshot for exactly that instant. Computation
takes zero simulated time, so the result of a trial depends only on the parameters, never on how fast
either process happens to run.
"""

from __future__ import annotations

import time

from hakoniwa.protocol import NEVER_WAKES, Athrill, MappedFile, Unity
from hakoniwa.liveness import pid_alive
from hakoniwa.timebase import PHYSICS_STEP_US

ORPHAN_CHECK_S = 1.0  # how often a waiting Athrill checks that the physics process is still alive


class KernelExit(Exception):
    """The physics process is gone; Athrill has nothing left to do."""


class Kernel:
    def __init__(self, unity: MappedFile, athrill: MappedFile) -> None:
        self.unity = unity
        self.athrill = athrill
        self.now_us = unity.read_i64(Unity.SNAPSHOT_TIME)
        self._physics_pid = unity.pid

    def sleep(self, duration_us: int) -> None:
        """tslp_tsk: sleep at least `duration_us`, rounded up to whole physics steps."""
        if duration_us <= 0:
            return
        steps = -(-duration_us // PHYSICS_STEP_US)
        wake = self.now_us + steps * PHYSICS_STEP_US
        self._publish(wake)
        self._wait_for_snapshot(wake)
        self.now_us = wake

    def finish(self) -> None:
        """The task returned: outputs stay as they are and no wake-up will ever be due."""
        self._publish(NEVER_WAKES)

    def _publish(self, wake_us: int) -> None:
        self.athrill.write_i64(Athrill.NEXT_WAKE, wake_us)
        self.athrill.stamp(self.now_us)

    def _wait_for_snapshot(self, wake_us: int) -> None:
        unity = self.unity
        spins = 0
        next_check = time.monotonic() + ORPHAN_CHECK_S
        while unity.read_i64(Unity.SNAPSHOT_TIME) < wake_us:
            spins += 1
            if spins < 200:
                continue
            time.sleep(0.0001)
            if time.monotonic() > next_check:
                next_check = time.monotonic() + ORPHAN_CHECK_S
                if not pid_alive(self._physics_pid):
                    raise KernelExit(f"physics process {self._physics_pid} is gone")



def wait_for_test(unity: MappedFile, test_seq: int) -> None:
    """Block until the physics process starts test `test_seq`.

    The physics process launches the next test's Athrill while the current test still runs, so that its
    start-up cost overlaps useful work; that process must not touch anything until its own test begins.
    """
    physics_pid = unity.pid
    next_check = time.monotonic() + ORPHAN_CHECK_S
    while (current := unity.read_i32(Unity.TEST_SEQ)) != test_seq:
        if current > test_seq:
            raise KernelExit(f"test {test_seq} will not run (physics is at test {current})")
        time.sleep(0.0002)
        if time.monotonic() > next_check:
            next_check = time.monotonic() + ORPHAN_CHECK_S
            if not pid_alive(physics_pid):
                raise KernelExit(f"physics process {physics_pid} is gone")
