"""The robot's sensors and motors as the program sees them: the one owner of a test's noise and of every
piece of sensor state.

The world (`world.py`) measures the truth; this model turns it into what EV3RT's drivers report. It adds the
test's seeded noise (`noise.py`) to the readings and the motor commands, derives the colour id and raw RGB
from the noisy reflect (so the three agree, as on a real sensor), counts the gyro's whole turns and its drift,
and keeps the zeros that `ev3_motor_reset_counts` and `ev3_gyro_sensor_reset` set. Nothing else in the
physics side touches a `NoiseDraw`, so a test's draws happen in one fixed order: sensor readings at each
snapshot, motor factors at each command.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from hakoniwa.physics.course import Course
from hakoniwa.physics.noise import NoiseDraw
from hakoniwa.physics.robots import DEFAULT_ROBOT, Robot
from hakoniwa.physics.scenario import Scenario
from hakoniwa.physics.world import World
from hakoniwa.wire.protocol import MOTOR_PORTS, ColorId


@dataclass(frozen=True)
class Sensors:
    """What the robot's sensors read at one instant, in the units EV3RT's drivers expect."""

    reflect: int  # 0..100
    ambient: int
    color: ColorId
    rgb: tuple[int, int, int]
    ultrasonic_mm: int
    gyro_angle_deg: int  # whole turns counted, clockwise positive seen from above, from the last reset
    gyro_rate_dps: int
    touch: tuple[bool, bool]  # touch slots 0 and 1: the bumper touching a wall, or the scenario pressing
    buttons: int  # the EV3 buttons the scenario holds down, as RX BUTTONS' bitmask
    motor_angles_deg: dict[int, int]  # the wheel ports' encoders, from their last reset


class SensorModel:
    def __init__(self, course: Course, robot: Robot = DEFAULT_ROBOT, scenario: Scenario = Scenario()) -> None:
        self.course = course
        self.robot = robot
        self.scenario = scenario
        self.begin(None)

    def begin(self, noise: NoiseDraw | None) -> None:
        """A new test with this noise (None: the noise-free bench): every zero and turn count back to 0."""
        self.noise = noise
        self._angle_zero = [0.0] * MOTOR_PORTS
        self._gyro_zero = 0.0
        self._yaw = (0.0, 0.0)  # (last wrapped reading, unwrapped angle): a gyro counts whole turns

    def read(self, world: World, now_us: int) -> Sensors:
        truth = world.measure()
        reflect, rate_dps, ultrasonic_mm = truth.reflect, truth.rate_dps, truth.ultrasonic_mm
        if self.noise is not None:
            reflect, rate_dps, ultrasonic_mm = self.noise.reading(reflect, rate_dps, ultrasonic_mm)
        color, rgb = self.course.color_at(*truth.sensor_xy, reflect)
        wiring = self.course.wiring
        wheels = ((wiring.left, truth.wheel_angles_deg[0]), (wiring.right, truth.wheel_angles_deg[1]))
        return Sensors(
            reflect=round(reflect),
            ambient=0,
            color=color,
            rgb=rgb,
            ultrasonic_mm=ultrasonic_mm,
            gyro_angle_deg=round(self._gyro_reading(truth.gyro_angle_deg, now_us) - self._gyro_zero),
            gyro_rate_dps=round(rate_dps),
            touch=self._touch(truth.touch, now_us),
            buttons=self.scenario.buttons(now_us),
            motor_angles_deg={port: round(angle - self._angle_zero[port]) for port, angle in wheels},
        )

    def _touch(self, bumped: bool, now_us: int) -> tuple[bool, bool]:
        slots = [False, False]
        if self.robot.bumper:
            slots[0] = bumped
        for port in self.scenario.touch_ports_pressed(now_us):
            if (slot := self.robot.touch_slot(port)) is not None:
                slots[slot] = True
        return slots[0], slots[1]

    def drive(self, world: World, powers: Sequence[int]) -> None:
        """Apply the motor powers of all ports: the wheel ports drive the wheels, with this command's noise."""
        wiring = self.course.wiring
        gains = None if self.noise is None else self.noise.motor_factors()
        world.set_motor_power(powers[wiring.left], powers[wiring.right], gains)

    def reset_motor_angle(self, world: World, port: int) -> None:
        left, right = world.wheel_angles_deg()
        wiring = self.course.wiring
        self._angle_zero[port] = {wiring.left: left, wiring.right: right}.get(port, 0.0)

    def reset_gyro(self, world: World, now_us: int) -> None:
        self._gyro_zero = self._gyro_reading(world.gyro_angle_deg(), now_us)

    def _gyro_reading(self, wrapped_deg: float, now_us: int) -> float:
        """The gyro's whole-turn angle now, with the drift of this test's gyro bias."""
        last, total = self._yaw
        total += (wrapped_deg - last + 180.0) % 360.0 - 180.0
        self._yaw = (wrapped_deg, total)
        return total if self.noise is None else total + self.noise.gyro_drift_deg(now_us)
