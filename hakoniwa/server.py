"""The physics process: owns the mapped files, runs tests on start = 1, resets on start = 0 (paper Fig. 4).

Physics time is the master. Between Athrill's wake-ups the world advances in batches of whole 1 ms steps
inside MuJoCo; at a wake-up the sensor snapshot for exactly that instant is published and the world waits
until Athrill has answered with its motor powers and its next wake-up time. Nothing here depends on wall
time except the watchdog that declares a silent or dead Athrill a crash.
"""

from __future__ import annotations

import csv
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from hakoniwa import robot
from hakoniwa.course import Course
from hakoniwa.protocol import (Athrill, Event, MappedFile, Unity, goal_time_words, open_athrill, open_unity)
from hakoniwa.task import LapTask
from hakoniwa.waiting import wait_for
from hakoniwa.timebase import (ALLOWED_TIME_DIFF_US, EVENT_CHECK_PERIOD_US, PHYSICS_STEP_US, TRACE_PERIOD_US,
                               Scheduler)
from hakoniwa.world import World

TRAJECTORY_FILE = "trajectory.csv"
ATHRILL_LOG = "athrill.log"
PHYSICS_LOG = "physics.log"  # one line per test: what the physics process saw
IDLE_POLL_S = 0.0005


@dataclass(frozen=True)
class TestOutcome:
    __test__ = False  # not a pytest class

    seq: int
    event: Event
    time_us: int
    wall_s: float


class AthrillLost(Exception):
    """Athrill died or stopped answering: the test ends as a crash."""


class AthrillLauncher:
    """Starts a fresh `athrill-sim` for every test, one test ahead, so its start-up overlaps the current test."""

    def __init__(self, run_dir: Path, app: str) -> None:
        self.run_dir = run_dir
        self.app = app
        self._spare: tuple[int, subprocess.Popen] | None = None
        self._log = open(run_dir / ATHRILL_LOG, "ab")

    def _spawn(self, seq: int) -> subprocess.Popen:
        cmd = [sys.executable, "-m", "athrill_sim.main", "--run-dir", str(self.run_dir), "--app", self.app,
               "--test", str(seq)]
        return subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=self._log, stderr=self._log)

    def take(self, seq: int) -> subprocess.Popen:
        proc = None
        if self._spare is not None:
            spare_seq, spare = self._spare
            if spare_seq == seq and spare.poll() is None:
                proc = spare
            else:
                _kill(spare)
        proc = proc or self._spawn(seq)
        self._spare = (seq + 1, self._spawn(seq + 1))
        return proc

    def close(self) -> None:
        if self._spare is not None:
            _kill(self._spare[1])
            self._spare = None
        self._log.close()


def _kill(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        proc.kill()
    proc.wait()


class PhysicsServer:
    def __init__(self, run_dir: Path, course: Course, *, app: str = "line_trace",
                 athrill_timeout_s: float = 10.0) -> None:
        self.run_dir = Path(run_dir)
        self.course = course
        self.athrill_timeout_s = athrill_timeout_s
        self.world = World(course)
        self.task = LapTask(course)
        self.unity: MappedFile = open_unity(self.run_dir, create=True)
        self.athrill: MappedFile = open_athrill(self.run_dir, create=True)
        self.launcher = AthrillLauncher(self.run_dir, app)
        self.scheduler = Scheduler(PHYSICS_STEP_US)
        self.scheduler.add("event-check", EVENT_CHECK_PERIOD_US, self._check_events)
        self.scheduler.add("trace", TRACE_PERIOD_US, self._trace)
        self._event = Event.NONE
        self._event_us = 0
        self._trajectory: list[tuple[int, float, float, float]] = []
        self.tests_run = 0
        self._athrill_proc: subprocess.Popen | None = None
        self._log = open(self.run_dir / PHYSICS_LOG, "a")

    # -- streams -------------------------------------------------------------------------------------
    def _check_events(self, now_us: int) -> None:
        if self._event == Event.NONE:
            self._event = self.task.check(self.world, now_us)
            self._event_us = now_us

    def _trace(self, now_us: int) -> None:
        self._trajectory.append((now_us, *self.world.pose()))

    # -- one test ------------------------------------------------------------------------------------
    def _publish_sensors(self, now_us: int) -> None:
        s = self.world.sensors()
        u = self.unity
        counts = [0] * 4
        counts[robot.LEFT_MOTOR_PORT], counts[robot.RIGHT_MOTOR_PORT] = s.motor_counts
        u.write_i32s(Unity.COLOR_REFLECT, [s.reflect, s.ambient, *s.rgb, s.ultrasonic_cm, s.gyro_angle_deg,
                                           s.gyro_rate_dps, s.touch, *counts])
        u.write_i64(Unity.SNAPSHOT_TIME, now_us)  # last: a reader that sees this time sees the values above
        u.stamp(now_us)

    def _await_athrill(self, proc: subprocess.Popen, last_seq: int, now_us: int) -> int | None:
        """Wait for Athrill's answer to the snapshot at `now_us`; apply its motor powers and return its next
        wake-up time, or None if it died, went silent, or broke the time protocol."""
        a = self.athrill
        deadline = time.monotonic() + self.athrill_timeout_s

        def check() -> None:
            if proc.poll() is not None:
                raise AthrillLost(f"athrill exited with code {proc.returncode}")
            if time.monotonic() > deadline:
                raise AthrillLost(f"athrill silent for {self.athrill_timeout_s} s")

        try:
            wait_for(lambda: a.seq != last_seq, check)
        except AthrillLost:
            return None
        next_wake = a.read_i64(Athrill.NEXT_WAKE)
        if abs(a.time_us - now_us) > ALLOWED_TIME_DIFF_US or next_wake <= now_us:
            return None
        powers = a.read_i32s(Athrill.MOTOR_POWER, 4)
        self.world.set_motor_power(powers[robot.LEFT_MOTOR_PORT], powers[robot.RIGHT_MOTOR_PORT])
        return next_wake

    def run_test(self) -> TestOutcome:
        wall_start = time.monotonic()
        seq = self.tests_run + 1
        self._event, self._event_us = Event.NONE, 0
        self._trajectory = []
        self.athrill.clear_data(Athrill.MOTOR_POWER, Athrill.START)
        self._publish_sensors(0)
        last_seq = self.athrill.seq
        self.unity.write_i32(Unity.TEST_SEQ, seq)
        proc = self._athrill_proc = self.launcher.take(seq)
        self._trace(0)
        now = 0
        next_wake = self._await_athrill(proc, last_seq, now)
        sched, world = self.scheduler, self.world
        while next_wake is not None:
            target = min(sched.next_tick(), next_wake)
            world.step((target - now) // PHYSICS_STEP_US)
            now = target
            sched.advance_to(now)
            if self._event != Event.NONE:
                break
            if now == next_wake:
                last_seq = self.athrill.seq
                self._publish_sensors(now)
                next_wake = self._await_athrill(proc, last_seq, now)
        if next_wake is None:
            self._event, self._event_us = Event.CRASH, now
        self._finish()
        outcome = TestOutcome(seq, self._event, self._event_us, time.monotonic() - wall_start)
        self._log.write(f"test {seq}: {outcome.event.name} at {outcome.time_us} us, wall {outcome.wall_s:.3f} s\n")
        self._log.flush()
        return outcome

    def _publish_event(self, event: Event, time_us: int) -> None:
        hi, lo = goal_time_words(time_us if event == Event.GOAL else 0)
        self.unity.write_u32(Unity.GOAL_TIME_HI, hi)
        self.unity.write_u32(Unity.GOAL_TIME_LO, lo)
        self.unity.write_i32(Unity.EVENT, int(event))  # last: the controller reads the time after it
        self.unity.stamp(time_us)

    def _finish(self) -> None:
        self._publish_event(self._event, self._event_us)
        self._write_trajectory()
        self.tests_run += 1

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
            _kill(self._athrill_proc)
            self._athrill_proc = None
        self.world.reset()
        self.task.reset()
        self.scheduler.reset()
        self._publish_event(Event.NONE, 0)

    # -- the process loop ----------------------------------------------------------------------------
    def serve(self, controller: subprocess.Popen | None = None) -> int:
        """Poll the flags until end = 1 (exit code 0) or the controller exits (its exit code)."""
        a = self.athrill
        in_test = False
        try:
            while True:
                if a.read_i32(Athrill.END) == 1:
                    return 0
                if controller is not None and controller.poll() is not None:
                    return controller.returncode
                start = a.read_i32(Athrill.START)
                if start == 1 and not in_test:
                    self.run_test()
                    in_test = True
                elif start == 0 and in_test:
                    self.reset()
                    in_test = False
                else:
                    time.sleep(IDLE_POLL_S)
        finally:
            if self._athrill_proc is not None:
                _kill(self._athrill_proc)
            self.launcher.close()
            self._log.close()
