"""One test as the robot experiences it, with no files and no processes: the world, the task, the sensor and
actuator model, and the physics clock with what is due on it (event checks, trajectory samples).

This is dm_control's environment: `World` is the physics and the task (`task.Task`, the lap or another
objective) is given to it as an argument, as dm_control's `Environment(physics, task)`; this class steps them
together. The physics server (`server.py`) is a thin shell around it that moves its inputs and outputs
through the mapped files; a test of the physics alone can drive it directly.
"""

from __future__ import annotations

from collections.abc import Sequence

from hakoniwa.physics.course import Course
from hakoniwa.physics.noise import NoiseDraw, StartOffset
from hakoniwa.physics.placing import placements
from hakoniwa.physics.replay import Replay, RobotLook, State
from hakoniwa.physics.robots import DEFAULT_ROBOT, Robot
from hakoniwa.physics.scenario import Scenario
from hakoniwa.physics.sensors import SensorModel, Sensors
from hakoniwa.physics.task import Task
from hakoniwa.physics.world import World
from hakoniwa.wire.etrobocon_rules import Score
from hakoniwa.wire.protocol import MOTOR_PORTS, NEVER_WAKES, Event
from hakoniwa.wire.timebase import EVENT_CHECK_PERIOD_US, PHYSICS_STEP_US, TRACE_PERIOD_US, Scheduler

Pose = tuple[int, float, float, float]  # time [us], x, y [m], yaw [rad]
EXACT = StartOffset(0.0, 0.0, 0.0)  # where the noise-free bench's person puts the robot: on the spot


class Environment:
    def __init__(self, world: World, task: Task, robot: Robot = DEFAULT_ROBOT,
                 scenario: Scenario = Scenario()) -> None:
        """`world` holds `robot`'s body on its course; `task` scores the tests on that course."""
        self.course: Course = world.course
        self.robot = robot
        self.world = world
        self.task = task
        self.sensors = SensorModel(self.course, robot, scenario)
        self.scheduler = Scheduler(PHYSICS_STEP_US)
        # A place happens at the first physics step at or after its time, which the world steps to exactly.
        self.places = tuple((self.scheduler.quantize(at_us), pose)
                            for at_us, pose in placements(self.course, robot.body, scenario))
        self.scheduler.add("event-check", EVENT_CHECK_PERIOD_US, self._check_events)
        self.scheduler.add("trace", TRACE_PERIOD_US, self._trace)
        self._clear(None)

    def _clear(self, noise: NoiseDraw | None) -> None:
        self.now_us = 0
        self.event, self.event_us = Event.NONE, 0
        self.completed_us: int | None = None
        self.sensors.begin(noise)
        self.noise = noise
        self.next_place = 0
        self.place_us = self.places[0][0] if self.places else NEVER_WAKES  # when the next place happens
        self.trajectory: list[Pose] = []
        self.states: list[tuple[int, State]] = []  # the replay's samples: at the trajectory's, and at the end
        self.object_states: list[tuple[float, ...]] = []  # the course's objects at the same samples

    def begin(self, noise: NoiseDraw | None) -> None:
        """A new test with this noise: the robot put down (with the test's start jitter), the clock at 0."""
        if noise is not None:
            self.world.put_down(noise.start)
        self.task.reset(self.world.position())
        self._clear(noise)
        self._trace(0)
        self._place_due()

    def reset(self) -> None:
        """Back to the state saved at start-up, between tests (the paper saves Robot and env once)."""
        self.world.reset()
        self.task.reset()
        self.scheduler.reset()

    def advance_to(self, target_us: int) -> bool:
        """Step the world to `target_us`, stopping at every tick where something is due on the way (event
        checks, trajectory samples) to run it, and at the first tick that raises an event; True once the
        test has one. MuJoCo steps each stretch between two such ticks in one call, and a whole control
        period is one call from the sync loop: the Python work per physics step is what the test needs."""
        sched, step = self.scheduler, self.world.step
        while self.now_us < target_us and self.event == Event.NONE:
            tick = min(sched.next_tick(), self.place_us)
            if tick > target_us:
                tick = target_us
            step((tick - self.now_us) // PHYSICS_STEP_US)
            self.now_us = tick
            sched.advance_to(tick)
            if tick == self.place_us and self.event == Event.NONE:
                self._place_due()
        return self.event != Event.NONE

    def _place_due(self) -> None:
        """Carry out the places due now, after the tick's event check and trajectory sample: the replay shows
        the robot where it was lifted and where it was set down at the same instant, a jump."""
        places = self.places
        while self.place_us == self.now_us:
            pose = places[self.next_place][1]
            self.next_place += 1
            self.place_us = places[self.next_place][0] if self.next_place < len(places) else NEVER_WAKES
            lifted = self.world.position()
            if self.trajectory[-1][0] < self.now_us:
                self._trace(self.now_us)
            self.sensors.follow_turn(self.world)
            self.world.place(pose, EXACT if self.noise is None else self.noise.placement())
            self.sensors.follow_turn(self.world)
            self.task.carried(lifted, self.world.position())
            self._trace(self.now_us)

    def end(self, event: Event) -> None:
        """End the test now with `event` (a crash, which the task cannot see)."""
        self.event, self.event_us = event, self.now_us

    def complete(self) -> None:
        """The program said its run is over (ET Robocon's completion notice), now: the task hears it at the
        next event check (which ends the test as COMPLETED, unless the task raises its own event then)."""
        if self.completed_us is None:
            self.completed_us = self.now_us

    def score(self) -> Score | None:
        """ET Robocon's result points as they stand (None under another objective)."""
        return self.task.score(self.world, self.robot.competition_class)

    def read_sensors(self) -> Sensors:
        return self.sensors.read(self.world, self.now_us)

    def drive(self, powers: Sequence[int], directions: Sequence[int] = (0,) * MOTOR_PORTS) -> None:
        self.sensors.drive(self.world, powers, directions)

    def reset_motor_angle(self, port: int) -> None:
        self.sensors.reset_motor_angle(self.world, port)

    def reset_gyro(self) -> None:
        self.sensors.reset_gyro(self.world, self.now_us)

    def _check_events(self, now_us: int) -> None:
        if self.event == Event.NONE:
            self.event = self.task.check(self.world, now_us, completed=self.completed_us is not None)
            self.event_us = now_us

    def _trace(self, now_us: int) -> None:
        self.trajectory.append((now_us, *self.world.pose()))
        self.states.append((now_us, self.world.state()))
        if self.course.objects:
            self.object_states.append(self.world.object_states())

    def replay(self, objective: str) -> Replay:
        """The test so far as a replay under the bench's `objective` (by its key): its samples, and the state now
        if the test ended between two."""
        states, objects = self.states, self.object_states
        if states[-1][0] < self.now_us:
            states = [*states, (self.now_us, self.world.state())]
            objects = [*objects, self.world.object_states()] if objects else objects
        r = self.robot
        look = RobotLook(r.name, r.hub, r.body, tuple(k for _, k in r.sensors))
        score = self.score()
        return Replay(str(self.course.folder.resolve()), look,
                      objective, len(self.course.checkpoints), self.event.name, self.event_us,
                      tuple(self.task.passed_us), self.completed_us, tuple(t for t, _ in states),
                      tuple(s for _, s in states), tuple(objects), None if score is None else score.to_dict())
