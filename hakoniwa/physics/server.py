"""The physics process: owns the mapped files, runs tests on start = 1, resets on start = 0 (paper Fig. 4).

Physics time is the master. The world advances in whole 1 ms MuJoCo steps, batched up to the next moment
anything has to happen: an event check, a trajectory sample, or (depending on the sync mode, see
`sync.py`) Athrill's next wake-up or the edge of the allowed time difference. Nothing here depends on
wall time except the watchdog that declares a silent or dead Athrill a crash.

Each test may carry seeded noise (`noise.py`): the controller's seed and scale are read at the test's
start, the robot is put down with that test's start-pose jitter, and sensor snapshots and motor commands
draw from that test's generators. Scale 0 draws nothing, and the code paths are the noise-free ones.

The mapped files belong to this process: it checks them (size, magic, version) at every test start and
repairs them if someone damaged them, so a damaged file never turns into a string of crashed tests that
would be charged to the parameters under test.
"""

from __future__ import annotations

import csv
import math
import os
import subprocess
import threading
import time
from dataclasses import dataclass
from pathlib import Path

from hakoniwa.physics.course import Course
from athrill_sim.launcher import AthrillLauncher, kill
from hakoniwa.physics.noise import NoiseDraw
from athrill_sim.programs import Program
from hakoniwa.wire.rundir import PHYSICS_LOG, TRAJECTORY_FILE
from hakoniwa.wire.protocol import (MOTOR_PORTS, RESET_ANGLE_PORTS, TOUCH_PRESSED, CrashKind, Event, Header, MappedFile,
                               Rx, SyncMode, Tx, goal_time_words, open_athrill, open_unity)
from hakoniwa.physics.sync import HAKONIWA_START_US, AthrillCrash, run_hakoniwa, run_lockstep
from hakoniwa.physics.task import LapTask
from hakoniwa.wire.timebase import EVENT_CHECK_PERIOD_US, PHYSICS_STEP_US, TRACE_PERIOD_US, Scheduler
from hakoniwa.wire.waiting import futex_wake
from hakoniwa.physics.world import World

IDLE_POLL_S = 0.0005
ACTUATORS_END = Tx.GYRO_RESET + 4  # TX body bytes a test starts with cleared
OUR_EXT = (Rx.TEST_SEQ, Rx.CRASH_DETAIL + 4)  # RX bytes of our extension the physics side writes


class ControllerGone(Exception):
    """The controller died during a test."""


@dataclass(frozen=True)
class TestOutcome:
    """What the physics process reports for one test (the controller reads the same through the files)."""

    __test__ = False  # not a pytest class

    seq: int
    event: Event
    time_us: int
    checkpoints: int
    distance_mm: int
    max_time_diff_us: int
    crash_kind: CrashKind
    crash_detail: int
    wall_s: float


class PhysicsServer:
    def __init__(self, run_dir: Path, course: Course, program: Program, *, athrill_timeout_s: float,
                 time_limit_us: int) -> None:
        self.run_dir = Path(run_dir)
        self.course = course
        self.program = program
        self.athrill_timeout_s = athrill_timeout_s
        self.world = World(course)
        self.task = LapTask(course, time_limit_us)
        self.unity: MappedFile = open_unity(self.run_dir, create=True)
        self.athrill: MappedFile = open_athrill(self.run_dir, create=True)
        self.unity.write_u32(Rx.PHYSICS_PID, os.getpid())
        self._unity_time_address = self.unity.address(Header.UNITY_TIME)
        self.launcher = AthrillLauncher(self.run_dir, program)
        self.scheduler = Scheduler(PHYSICS_STEP_US)
        self.scheduler.add("event-check", EVENT_CHECK_PERIOD_US, self._check_events)
        self.scheduler.add("trace", TRACE_PERIOD_US, self._trace)
        self.answer_before_start = 0
        self.tests_run = 0
        self._noise: NoiseDraw | None = None  # this test's noise; None: the noise-free bench
        self._clear_test_state()
        self._athrill_proc = None
        self._controller_gone = threading.Event()
        self._log = open(self.run_dir / PHYSICS_LOG, "a")

    # -- streams -------------------------------------------------------------------------------------
    def _check_events(self, now_us: int) -> None:
        if self._event == Event.NONE:
            self._event = self.task.check(self.world, now_us)
            self._event_us = now_us

    def _trace(self, now_us: int) -> None:
        self._trajectory.append((now_us, *self.world.pose()))

    # -- what the sync loops use ---------------------------------------------------------------------
    def advance_to(self, target_us: int) -> bool:
        """Step the world to `target_us` and run what is due there; True once the test has an event.
        Raises ControllerGone when the controller died: nobody would read this test's result."""
        if self._controller_gone.is_set():
            raise ControllerGone
        self.world.step((target_us - self.now_us) // PHYSICS_STEP_US)
        self.now_us = target_us
        self.scheduler.advance_to(target_us)
        return self._event != Event.NONE

    def note_time_diff(self, diff_us: int) -> None:
        self._max_diff_us = max(self._max_diff_us, abs(diff_us))

    def publish_sensors(self) -> None:
        """The sensor snapshot for `now_us`, then the unity time (last: a reader that sees the new time sees
        the values it belongs to)."""
        s = self.world.sensors(self._noise)
        u = self.unity
        u.write_i32s(Rx.COLOR0_AMBIENT, [s.ambient, int(s.color), s.reflect, *s.rgb])
        u.write_i32s(Rx.GYRO_ANGLE, [round(self._gyro_reading(s.gyro_angle_deg) - self._gyro_zero), s.gyro_rate_dps])
        u.write_i32(Rx.ULTRASONIC_MM, s.ultrasonic_mm)
        u.write_i32(Rx.TOUCH0, TOUCH_PRESSED if s.touch else 0)
        wiring = self.course.wiring
        for port, angle in ((wiring.left, s.wheel_angles_deg[0]), (wiring.right, s.wheel_angles_deg[1])):
            u.write_i32(Rx.MOTOR_ANGLE + 4 * port, round(angle - self._angle_zero[port]))
        u.unity_time_us = max(self.now_us, HAKONIWA_START_US if self.program.sync == SyncMode.HAKONIWA else 0)
        futex_wake(self._unity_time_address)  # a lockstep Athrill sleeps on it

    def apply_actuators(self) -> None:
        """Motor powers of the wheel ports, and the reset requests, which are cleared once applied."""
        a = self.athrill
        powers = a.read_i32s(Tx.MOTOR_POWER, MOTOR_PORTS)
        wiring = self.course.wiring
        gains = None if self._noise is None else self._noise.motor_factors()
        self.world.set_motor_power(powers[wiring.left], powers[wiring.right], gains)
        for port in range(RESET_ANGLE_PORTS):
            if a.read_i32(Tx.MOTOR_RESET_ANGLE + 4 * port):
                left, right = self.world.wheel_angles_deg()
                self._angle_zero[port] = {wiring.left: left, wiring.right: right}.get(port, 0.0)
                a.write_i32(Tx.MOTOR_RESET_ANGLE + 4 * port, 0)
        if a.read_i32(Tx.GYRO_RESET):
            self._gyro_zero = self._gyro_reading(self.world.gyro_angle_deg())
            a.write_i32(Tx.GYRO_RESET, 0)

    def _gyro_angle(self, wrapped_deg: float) -> float:
        last, total = self._yaw
        total += (wrapped_deg - last + 180.0) % 360.0 - 180.0
        self._yaw = (wrapped_deg, total)
        return total

    def _gyro_reading(self, wrapped_deg: float) -> float:
        """The gyro's whole-turn angle now, with the drift of this test's gyro bias."""
        total = self._gyro_angle(wrapped_deg)
        return total if self._noise is None else total + self._noise.gyro_drift_deg(self.now_us)

    def _read_noise(self) -> NoiseDraw | None:
        """This test's noise from the seed and scale the controller wrote; None for scale 0 (or a scale that
        is not a finite number >= 0, which is logged: the controller's `TrialRunner` never writes one)."""
        seed, scale = self.unity.read_u32(Rx.NOISE_SEED), self.unity.read_f32(Rx.NOISE_SCALE)
        if scale == 0:
            return None
        if not (math.isfinite(scale) and scale > 0):
            self._log.write(f"noise scale {scale!r} is not a finite number >= 0: this test runs without noise\n")
            return None
        return NoiseDraw(self.course.noise, seed, scale)

    # -- one test ------------------------------------------------------------------------------------
    def check_files(self) -> None:
        """Repair the mapped files if anyone damaged them since the last test, and say so in the log."""
        for f in (self.unity, self.athrill):
            problem = f.repair()
            if problem is not None:
                self._log.write(f"repaired {f.path.name}: {problem}\n")
                self._log.flush()

    def _clear_test_state(self) -> None:
        self.now_us = 0
        self._event, self._event_us, self._max_diff_us = Event.NONE, 0, 0
        self._angle_zero = [0.0] * MOTOR_PORTS
        self._gyro_zero = 0.0
        self._yaw = (0.0, 0.0)  # (last wrapped reading, unwrapped angle): a gyro counts whole turns
        self._trajectory: list[tuple[int, float, float, float]] = []

    def _start_test(self, seq: int) -> None:
        self.check_files()
        self._noise = self._read_noise()
        if self._noise is not None:
            self.world.put_down(self._noise.start)
        self.task.reset(self.world.position())
        self._clear_test_state()
        a = self.athrill
        a.clear(0, ACTUATORS_END)
        a.athrill_time_us = 0  # a real Athrill's clock starts at 0; a stale one would let physics run ahead
        self.answer_before_start = a.read_u32(Tx.ANSWER_SEQ)
        self.unity.clear(*OUR_EXT)
        self.unity.write_u32(Rx.PHYSICS_PID, os.getpid())
        self.unity.write_u32(Rx.SYNC_MODE, int(self.program.sync))
        self.publish_sensors()
        self.unity.write_u32(Rx.TEST_SEQ, seq)  # last: a waiting Athrill starts when it sees its number
        self._trace(0)

    def run_test(self) -> TestOutcome:
        wall_start = time.monotonic()
        seq = self.tests_run + 1
        self._start_test(seq)
        crash: AthrillCrash | None = None
        try:
            proc = self._athrill_proc = self.launcher.take(seq)
        except OSError as e:
            crash = AthrillCrash(CrashKind.BENCH, 0, f"cannot start athrill: {e}")
        else:
            run = run_lockstep if self.program.sync == SyncMode.LOCKSTEP else run_hakoniwa
            try:
                run(self, proc)
            except AthrillCrash as e:
                crash = e
        if crash is not None:
            self._event, self._event_us = Event.CRASH, self.now_us
        outcome = TestOutcome(seq, self._event, self._event_us, self.task.passed, self.task.distance_mm,
                              self._max_diff_us, crash.kind if crash else CrashKind.NONE,
                              crash.detail if crash else 0, time.monotonic() - wall_start)
        self._finish(outcome)
        why = f" ({crash.kind.name.lower()}: {crash})" if crash else ""
        if self._noise is not None:
            self._log.write(f"test {seq}: {self._noise.describe()}\n")
        self._log.write(f"test {seq}: {outcome.event.name}{why} at {outcome.time_us} us, "
                        f"{outcome.checkpoints} checkpoints, {outcome.distance_mm} mm, "
                        f"max time diff {outcome.max_time_diff_us} us, wall {outcome.wall_s:.3f} s\n")
        self._log.flush()
        return outcome

    def _finish(self, o: TestOutcome) -> None:
        u = self.unity
        u.write_u32(Rx.CHECKPOINTS, o.checkpoints)
        u.write_u32(Rx.DISTANCE_MM, o.distance_mm)
        u.write_u32(Rx.MAX_TIME_DIFF_US, o.max_time_diff_us)
        u.write_i32(Rx.CRASH_KIND, int(o.crash_kind))
        u.write_i32(Rx.CRASH_DETAIL, o.crash_detail)
        self._publish_event(o.event, o.time_us)
        self._write_trajectory()
        self.tests_run += 1

    def _publish_event(self, event: Event, time_us: int) -> None:
        hi, lo = goal_time_words(time_us if event == Event.GOAL else 0)
        self.unity.write_u32(Rx.GOAL_TIME_HI, hi)
        self.unity.write_u32(Rx.GOAL_TIME_LO, lo)
        self.unity.write_i32(Rx.EVENT, int(event))  # last: the controller reads everything else after it

    def _write_trajectory(self) -> None:
        tmp = self.run_dir / (TRAJECTORY_FILE + ".tmp")
        with open(tmp, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["time_us", "x", "y", "yaw"])
            w.writerows((t, f"{x:.5f}", f"{y:.5f}", f"{yaw:.5f}") for t, x, y, yaw in self._trajectory)
        tmp.replace(self.run_dir / TRAJECTORY_FILE)

    def reset(self) -> None:
        """start = 0: stop Athrill, restore the saved initial state, clear event and goal time."""
        if self._athrill_proc is not None:
            kill(self._athrill_proc)
            self._athrill_proc = None
        self.world.reset()
        self.task.reset()
        self.scheduler.reset()
        self._publish_event(Event.NONE, 0)

    # -- the process loop ----------------------------------------------------------------------------
    def serve(self, controller: subprocess.Popen | None = None) -> int:
        """Poll the flags until end = 1 or the controller exits; returns the controller's exit status (0
        without a controller). A controller that dies mid-test ends the test at once."""
        a = self.athrill
        in_test = False
        if controller is not None:
            threading.Thread(target=lambda: (controller.wait(), self._controller_gone.set()), daemon=True).start()
        try:
            while True:
                if controller is not None and controller.poll() is not None:
                    return controller.returncode
                if a.read_i32(Tx.END) == 1:
                    return controller.wait() if controller is not None else 0
                start = a.read_i32(Tx.START)
                if start == 1 and not in_test:
                    try:
                        self.run_test()
                    except ControllerGone:
                        return controller.wait() if controller is not None else 0
                    in_test = True
                elif start == 0 and in_test:
                    self.reset()
                    in_test = False
                else:
                    time.sleep(IDLE_POLL_S)
        finally:
            if self._athrill_proc is not None:
                kill(self._athrill_proc)
            self.launcher.close()
            self._log.close()

