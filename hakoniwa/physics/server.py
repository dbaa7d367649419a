"""The physics process's loop: owns the mapped files, runs tests on start = 1, resets on start = 0 (paper
Fig. 4). It is a thin shell: the test itself is `environment.py`'s, the slots `slots.py`'s, the noise and
sensor state `sensors.py`'s; this class starts Athrill, runs the sync loop, and logs. What Athrill runs is
not its business: it is given a `hakoniwa.wire.launch.Launcher` by whoever builds the bench.

Physics time is the master. The world advances in whole 1 ms MuJoCo steps, batched up to the next moment
anything has to happen: an event check, a trajectory sample, or (depending on the sync mode, see
`sync.py`) Athrill's next wake-up or the edge of the allowed time difference. Nothing here depends on
wall time except the watchdog that declares a silent or dead Athrill a crash, and each test's wall-clock
ceiling (`hakoniwa.wire.wallclock`), past which a test whose simulated time crept is the bench's fault.

Each test may carry seeded noise (`noise.py`): the controller's seed and scale are read at the test's
start, the robot is put down with that test's start-pose jitter, and sensor snapshots and motor commands
draw from that test's generators. Scale 0 draws nothing, and the code paths are the noise-free ones.

The mapped files belong to this process: it checks them (size, magic, version) at every test's start and
end and repairs them if someone damaged them, so a damaged file never turns into a string of crashed tests
that would be charged to the parameters under test; the test it touched is a bench fault (`FILE_DAMAGED`),
run again.
"""

from __future__ import annotations

import csv
import functools
import io
import math
import subprocess
import threading
import time
from pathlib import Path

from hakoniwa.physics.course import Course
from hakoniwa.physics.environment import Environment
from hakoniwa.physics.hub_relay import HubRelay
from hakoniwa.physics.lcd import draw_screen, forget_screen
from hakoniwa.physics.noise import NoiseDraw
from hakoniwa.physics.raspike_hub import hub_kinds
from hakoniwa.physics.relay import MappedFiles, Transport, UdpRelay
from hakoniwa.physics.replay import REPLAY_FILE, write_replay
from hakoniwa.physics.robots import DEFAULT_ROBOT, Robot
from hakoniwa.physics.scenario import Scenario
from hakoniwa.physics.slots import Slots
from hakoniwa.physics.sync import SYNC_LOOPS, AthrillCrash, snapshot_end_us, unity_time_us
from hakoniwa.physics.world import World
from hakoniwa.wire.launch import Launcher, ProgramRefused
from hakoniwa.wire.objective import DEFAULT, Objective, objective_named
from hakoniwa.wire.processes import kill
from hakoniwa.wire.protocol import BenchCause, CrashKind, Event
from hakoniwa.wire.result import TestResult
from hakoniwa.wire.rundir import PHYSICS_LOG, RESULT_FILE, SERIAL_INPUT, TRAJECTORY_FILE
from hakoniwa.wire.timebase import Scheduler
from hakoniwa.wire.wallclock import WallCeiling

IDLE_POLL_S = 0.0005
PROGRAM_OUTPUT_LINES = 6  # of a crashed program's output, for the user: a traceback's last frame and its error


class ControllerGone(Exception):
    """The controller died during a test."""


class PhysicsServer:
    def __init__(self, run_dir: Path, course: Course, launcher: Launcher, *, athrill_timeout_s: float,
                 time_limit_us: int, robot: Robot = DEFAULT_ROBOT, scenario: Scenario = Scenario(),
                 objective: Objective | None = None) -> None:
        """The server owns `launcher` from here on: it closes it when it stops serving. `objective` gives the
        task that scores each test (None: the default, the lap)."""
        self.run_dir = Path(run_dir)
        self.course = course
        self.launcher = launcher
        self.athrill_timeout_s = athrill_timeout_s
        self.objective = objective or objective_named(DEFAULT)
        self.env = Environment(World(course, robot.body, imu=robot.spike),
                               self.objective.task(course, time_limit_us), robot, scenario)
        (self.run_dir / SERIAL_INPUT).write_text(scenario.serial_lines())
        self.slots = Slots(self.run_dir)
        self._log = open(self.run_dir / PHYSICS_LOG, "a")
        self.transport = self._transport(robot)
        self.answer_before_start = 0
        self.tests_run = 0
        self._program_output: list[str] = []  # a crashed program's last words, for the test's result
        self._max_diff_us = 0
        self._athrill_proc: subprocess.Popen | None = None
        self._ceiling = WallCeiling(self.env.task.time_limit_us)  # each test's own, from its start
        self._controller_gone = threading.Event()

    def _transport(self, robot: Robot) -> Transport:
        """How the program's devices reach the world: the mapped files, athrill2's UDP packets relayed into
        them, or the hub a program talks to over serial, played on a pty (`hub_relay`). LinkError (one line)
        for a UDP port in use."""
        if self.launcher.serial_hub:
            return HubRelay(self.slots, self.run_dir, hub_kinds(self.course.wiring, robot))
        if self.launcher.udp is not None:
            return UdpRelay(self.launcher.udp, self.slots, self.run_dir, self._note)
        return MappedFiles()

    # -- what the sync loops use (`hakoniwa.physics.sync.SyncServer`, with the attributes above) ----------
    @property
    def now_us(self) -> int:
        return self.env.now_us

    @property
    def scheduler(self) -> Scheduler:
        return self.env.scheduler

    def advance_to(self, target_us: int) -> bool:
        """Step the test to `target_us`; True once it has an event. Raises ControllerGone when the controller
        died: nobody would read this test's result."""
        if self._controller_gone.is_set():
            raise ControllerGone
        return self.env.advance_to(target_us)

    def check_ceiling(self) -> None:
        """Raise a bench fault once the test is past its wall-clock ceiling (`hakoniwa.wire.wallclock`): a
        clock that creeps would otherwise hold the bench for ever while never being silent."""
        why = self._ceiling.exceeded(self.env.now_us)
        if why is not None:
            raise AthrillCrash(CrashKind.BENCH, 0, why, BenchCause.TIME_STALLED)

    def note_time_diff(self, diff_us: int) -> None:
        self._max_diff_us = max(self._max_diff_us, abs(diff_us))

    def publish_sensors(self) -> None:
        """The snapshot of now. Its readings are taken once, and only where something reads them (Athrill, from
        the files; a hub the physics side plays, in its status): a reading costs more than a step, and draws
        its noise."""
        now = self.env.now_us
        read = functools.cache(self.env.read_sensors)
        self.transport.publishing(read, now)
        self.slots.publish(read() if self.transport.reads_files else None, unity_time_us(self.launcher.sync, now),
                           snapshot_end_us(now))
        self.transport.published()

    def apply_actuators(self) -> None:
        self.transport.answered(self.env.now_us)
        commands = self.slots.take_commands()
        self.env.drive(commands.powers, commands.directions)
        for port in commands.reset_angle_ports:
            self.env.reset_motor_angle(port)
        if commands.reset_gyro:
            self.env.reset_gyro()
        if commands.completed:
            self.env.complete()

    # -- one test ------------------------------------------------------------------------------------
    def check_files(self, when: str) -> AthrillCrash | None:
        """Repair the mapped files if anyone damaged them, say so in the log, and spoil the test: what it read
        or wrote through a damaged file (its parameters, its sensors, its report) cannot be trusted."""
        problems = self.slots.repair()
        for line in problems:
            self._note(f"repaired {line}")
        if not problems:
            return None
        return AthrillCrash(CrashKind.BENCH, 0, f"mapped file damaged {when}: {'; '.join(problems)}",
                            BenchCause.FILE_DAMAGED)

    def _note(self, line: str) -> None:
        self._log.write(line + "\n")
        self._log.flush()

    def _read_noise(self) -> NoiseDraw | None:
        """This test's noise from the seed and scale the controller wrote; None for scale 0 (or a scale that
        is not a finite number >= 0, which is logged: the controller's `TestRunner` never writes one)."""
        seed, scale = self.slots.noise_request()
        if scale == 0:
            return None
        if not (math.isfinite(scale) and scale > 0):
            self._log.write(f"noise scale {scale!r} is not a finite number >= 0: this test runs without noise\n")
            return None
        return NoiseDraw(self.course.noise, seed, scale)

    def _start_test(self, seq: int) -> tuple[NoiseDraw | None, AthrillCrash | None]:
        damaged = self.check_files("before the test")
        forget_screen(self.run_dir)
        (self.run_dir / RESULT_FILE).unlink(missing_ok=True)
        self._program_output = []
        noise = self._read_noise()
        self.env.begin(noise)
        self._max_diff_us = 0
        self.answer_before_start = self.slots.begin(self.course.info)
        self.publish_sensors()
        # before the announcement: a waiting Athrill reads its files after it
        crash = damaged or self._prepare_program(seq)
        self.slots.announce(seq)
        return noise, crash

    def _prepare_program(self, seq: int) -> AthrillCrash | None:
        """Have the launcher make this test's program; a crash (the program's or the bench's) if it cannot."""
        try:
            self.launcher.prepare(seq, self.slots.unity)
        except ProgramRefused as e:
            self._program_output = [str(e)]
            return AthrillCrash(CrashKind.PROGRAM, 0, str(e))
        except OSError as e:
            return AthrillCrash(CrashKind.BENCH, 0, str(e), BenchCause.ATHRILL_FAILED)
        return None

    def run_test(self) -> TestResult:
        """One test, from the start flag to its report; its result (the controller decodes the same from
        `RESULT_FILE`, but for `wall_s`, which it measures itself)."""
        wall_start = time.monotonic()
        seq = self.tests_run + 1
        noise, crash = self._start_test(seq)
        proc = None
        self._ceiling = WallCeiling(self.env.task.time_limit_us)
        try:
            if crash is None:
                self.transport.launching()
                proc = self._athrill_proc = self.launcher.take(seq)
        except OSError as e:
            crash = AthrillCrash(CrashKind.BENCH, 0, f"cannot start athrill: {e}", BenchCause.ATHRILL_FAILED)
        else:
            try:
                if proc is not None:
                    SYNC_LOOPS[self.launcher.sync](self, proc)
            except AthrillCrash as e:
                crash = e
        crash = self.check_files("during the test") or crash  # whatever else the damage made of the test
        env = self.env
        if crash is not None:
            env.end(Event.CRASH)
        out = env.event == Event.COURSE_OUT  # the world stopped at the check that saw it: it is where it left
        x, y = env.world.position()
        if crash is not None and crash.kind == CrashKind.PROGRAM and proc is not None and proc.poll() is not None:
            self._program_output = self.launcher.last_lines(proc, PROGRAM_OUTPUT_LINES)
        score = env.score()
        path = self._trajectory_csv()
        result = TestResult(env.event, env.event_us if env.event == Event.GOAL else 0, time.monotonic() - wall_start,
                            len(env.task.passed_us), env.task.distance_mm, self._max_diff_us, self.launcher.sync,
                            crash.kind if crash else CrashKind.NONE, crash.detail if crash else 0,
                            "\n".join(self._program_output).strip() if crash else "", env.completed_us or 0,
                            self.objective, crash.cause if crash else BenchCause.NONE, None if crash else score,
                            env.event_us if out else 0, (round(x * 1000), round(y * 1000)) if out else (0, 0),
                            path)
        draw_screen(self.run_dir)  # before the report: whoever sees the event sees the screen
        self._replace_file(TRAJECTORY_FILE, path)  # before the report too: whoever sees the event reads it
        write_replay(self.run_dir / REPLAY_FILE, self.env.replay(self.objective.key))
        self._replace_file(RESULT_FILE, result.encode())
        self.slots.publish_event(result.event, result.goal_time_us)
        self.tests_run += 1
        why = f" ({crash.kind.name.lower()}: {crash})" if crash else ""
        if noise is not None:
            self._log.write(f"test {seq}: {noise.describe()}\n")
        self._log.write(f"test {seq}: {result.event.name}{why} at {env.event_us} us, "
                        f"{result.checkpoints} checkpoints, {result.distance_mm} mm, "
                        f"max time diff {result.max_time_diff_us} us, wall {result.wall_s:.3f} s"
                        + ("" if env.completed_us is None else f", completed at {env.completed_us} us")
                        + (f", left the course at ({x:.3f}, {y:.3f}): {env.course.left_at(x, y)}" if out else "")
                        + ("" if score is None else f", {score.describe()}") + "\n")
        self._log.flush()
        return result

    def _replace_file(self, name: str, text: str) -> None:
        """Written beside and renamed into place: whoever reads the run directory sees a whole file or none."""
        tmp = self.run_dir / (name + ".tmp")
        tmp.write_text(text, newline="")
        tmp.replace(self.run_dir / name)

    def _trajectory_csv(self) -> str:
        """The test's path, for its run directory and its result."""
        out = io.StringIO()
        w = csv.writer(out)
        w.writerow(["time_us", "x", "y", "yaw"])
        w.writerows((t, f"{x:.5f}", f"{y:.5f}", f"{yaw:.5f}") for t, x, y, yaw in self.env.trajectory)
        return out.getvalue()

    def reset(self) -> None:
        """start = 0: stop Athrill, restore the saved initial state, clear event and goal time."""
        if self._athrill_proc is not None:
            self.launcher.end(self._athrill_proc)
            self._athrill_proc = None
        self.transport.ended()
        self.env.reset()
        self.slots.publish_event(Event.NONE, 0)

    # -- the process loop ----------------------------------------------------------------------------
    def _watch(self, controller: subprocess.Popen) -> None:
        """In a thread of its own: a controller's exit ends a test at once, not at the next poll."""
        controller.wait()
        self._controller_gone.set()

    def serve(self, controller: subprocess.Popen | None = None) -> int:
        """Poll the flags until end = 1 or the controller exits; returns the controller's exit status (0
        without a controller). A controller that dies mid-test ends the test at once."""
        in_test = False
        if controller is not None:
            threading.Thread(target=self._watch, args=(controller,), daemon=True).start()
        try:
            while True:
                if controller is not None and controller.poll() is not None:
                    return controller.returncode
                if self.slots.end_requested():
                    return controller.wait() if controller is not None else 0
                start = self.slots.start_flag()
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
            self.transport.close()
            self.launcher.close()
            self._log.close()
