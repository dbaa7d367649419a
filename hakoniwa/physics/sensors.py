"""The robot's sensors and motors as the program sees them: the one owner of a test's noise and of every
piece of sensor state.

The world (`world.py`) measures the truth; this model turns it into what EV3RT's drivers (or ET Robocon's
SPIKE SDK) report. It adds the test's seeded noise (`noise.py`) to the readings and the motor commands,
derives the colour id and raw RGB from the same noisy channels as the reflect (so they agree, as on a real
sensor), counts the gyro's whole turns and its drift, and keeps the zeros that `ev3_motor_reset_counts` and
`ev3_gyro_sensor_reset` set. Nothing else in the physics side touches a `NoiseDraw`, so a test's draws happen
in one fixed order: sensor readings at each snapshot, motor factors at each command.

A robot's sensors have the response of their kind (`color_response.py`): an EV3 colour sensor reads the
floor's red channel as its reflect, a SPIKE one 10-bit RGB (the course's `[sensor.spike]` channels through the
robot's own response). A SPIKE robot's readings are what SPIKE-RT on the hub answers (`spike_hub.py`): counts
in the direction the program set each motor up with (the hub applies it to the power too), the reflection,
HSV and colour of that RGB, each motor's power as the hub reports it; it also gets its hub IMU, its force
sensor in touch slot 0 and the SPIKE ultrasonic sensor's range. An EV3 robot's readings are what they always
were.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from hakoniwa.physics import spike_hub
from hakoniwa.physics.course import Course
from hakoniwa.physics.noise import NoiseDraw
from hakoniwa.physics.robots import DEFAULT_ROBOT, Robot
from hakoniwa.physics.scenario import Scenario
from hakoniwa.physics.world import Inertial, World
from hakoniwa.wire.protocol import FORCE_PRESSED_N, MOTOR_PORTS, TOUCH_PRESSED, ColorId

# What the bench's SPIKE colour sensor's SHSV mode (its light off) reads: the bench has no room light.
DARK_SHSV = (0, 0, 0)
# The SPIKE ultrasonic sensor's reading with nothing in range (Pybricks' UltrasonicSensor.distance: 2000 mm);
# ET Robocon's SDK hands the slot's mm on unchanged (raspike_ultrasonicsensor.c).
SPIKE_ULTRASONIC_MAX_MM = 2000


@dataclass(frozen=True)
class HubReadings:
    """What SPIKE-RT on the hub answers beyond the SDK's slots (`spike_hub.py`)."""

    hsv: tuple[int, int, int]  # pup_color_sensor_hsv(surface = true)
    ambient_hsv: tuple[int, int, int]  # pup_color_sensor_hsv(surface = false)
    color: tuple[int, int, int]  # pup_color_sensor_color(), the detectable colour
    powers: tuple[int, ...]  # pup_motor_get_power() of motor ports A..D


@dataclass(frozen=True)
class Sensors:
    """What the robot's sensors read at one instant, in the units EV3RT's drivers expect."""

    reflect: int  # 0..100 (a SPIKE robot's: the hub's reflection of `rgb`)
    ambient: int
    color: ColorId
    rgb: tuple[int, int, int]  # an EV3's RGB-RAW: the course's white 255, up to 1020 (`color_response.raw_rgb`);
    # a SPIKE robot's: the hub's 10-bit RGB
    ultrasonic_mm: int
    gyro_angle_deg: int  # whole turns counted, clockwise positive seen from above, from the last reset
    gyro_rate_dps: int
    touch: tuple[int, int]  # touch slots 0 and 1 (the bumper touching a wall, or the scenario pressing): 0,
    # TOUCH_PRESSED for an EV3 touch sensor, FORCE_PRESSED_N for a SPIKE force sensor
    buttons: int  # the EV3 buttons the scenario holds down, as RX BUTTONS' bitmask
    buttons_until_us: int  # when the scenario next presses or releases a button (`Scenario.buttons_until`)
    motor_angles_deg: dict[int, int]  # the wheel ports' counts from their last reset, in each one's direction
    spike: HubReadings | None = None  # a SPIKE hub's
    imu: Inertial | None = None  # a SPIKE hub's IMU


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
        self._powers: tuple[int, ...] = (0,) * MOTOR_PORTS
        self._directions: tuple[int, ...] = (spike_hub.PBIO_CLOCKWISE,) * MOTOR_PORTS
        self._gyro_zero = 0.0
        self._yaw = (0.0, 0.0)  # (last wrapped reading, unwrapped angle): a gyro counts whole turns

    def read(self, world: World, now_us: int) -> Sensors:
        truth = world.measure()
        reflect, colour, rate_dps, ultrasonic_mm = truth.reflect, truth.colour, truth.rate_dps, truth.ultrasonic_mm
        hand_mm = self.scenario.hand_mm(now_us)
        if hand_mm is not None:  # the sensor hears the nearer echo: the hand, or a wall in front of it
            ultrasonic_mm = min(ultrasonic_mm, hand_mm)
        if self.noise is not None:
            reflect, rate_dps, ultrasonic_mm = self.noise.reading(reflect, rate_dps, ultrasonic_mm)
            if colour is not None:
                g, b, mean = self.noise.shift_reflect(colour)
                colour = g, b, mean
        color, rgb = self.course.color_at(*truth.sensor_xy, reflect, colour)
        wiring = self.course.wiring
        wheels = ((wiring.left, wiring.left_forward, truth.wheel_angles_deg[0]),
                  (wiring.right, wiring.right_forward, truth.wheel_angles_deg[1]))
        spike, hub, reflect_now = self.robot.spike, None, round(reflect)
        if spike:
            seen = self.course.spike_reading(*truth.sensor_xy, reflect, colour, self.robot.reflection)
            rgb, reflect_now = seen.rgb, seen.reflection
            hub = HubReadings(seen.hsv, spike_hub.ambient_hsv(DARK_SHSV), seen.color,
                              tuple(spike_hub.power_report(p, d) for p, d in zip(self._powers, self._directions)))
        return Sensors(
            reflect=reflect_now,
            ambient=spike_hub.ambient(DARK_SHSV) if spike else 0,
            color=color,
            rgb=rgb,
            ultrasonic_mm=min(ultrasonic_mm, SPIKE_ULTRASONIC_MAX_MM) if spike else ultrasonic_mm,
            gyro_angle_deg=round(self._gyro_reading(truth.gyro_angle_deg, now_us) - self._gyro_zero),
            gyro_rate_dps=round(rate_dps),
            touch=self._touch(truth.touch, now_us),
            buttons=self.scenario.buttons(now_us),
            buttons_until_us=self.scenario.buttons_until(now_us),
            motor_angles_deg={port: spike_hub.direction_sign(self._directions[port])
                              * round(forward * (angle - self._angle_zero[port])) for port, forward, angle in wheels},
            spike=hub,
            # The z rate is the gyro's (counter-clockwise positive, as the IMU's right-handed z), noise and all.
            imu=self._imu(world, -rate_dps) if spike else None,
        )

    @staticmethod
    def _imu(world: World, yaw_rate_dps: float) -> Inertial:
        true = world.inertial()
        wx, wy, _ = true.angular_velocity_dps
        return Inertial((wx, wy, yaw_rate_dps), true.acceleration_mm_s2)

    def _touch(self, bumped: bool, now_us: int) -> tuple[int, int]:
        slots = [False, False]
        if self.robot.bumper:
            slots[0] = bumped
        for press in self.scenario.sensor_presses(now_us):
            if press.sensor is not None and (slot := self.robot.press_slot(press.sensor, press.port)) is not None:
                slots[slot] = True
        first = FORCE_PRESSED_N if self.robot.spike else TOUCH_PRESSED  # the SDK reads slot 0 as the force
        return first if slots[0] else 0, TOUCH_PRESSED if slots[1] else 0

    def drive(self, world: World, powers: Sequence[int], directions: Sequence[int]) -> None:
        """Apply the motor powers of all ports, each in the direction its program set it up with (as pbio
        applies it to the duty): the wheel ports drive the wheels, each the way its motor is mounted, with this
        command's noise."""
        self._powers, self._directions = tuple(powers), tuple(directions)
        wiring = self.course.wiring
        duty = [spike_hub.direction_sign(d) * p for p, d in zip(powers, directions)]
        gains = None if self.noise is None else self.noise.motor_factors()
        world.set_motor_power(wiring.left_forward * duty[wiring.left], wiring.right_forward * duty[wiring.right],
                              gains)

    def reset_motor_angle(self, world: World, port: int) -> None:
        left, right = world.wheel_angles_deg()
        wiring = self.course.wiring
        self._angle_zero[port] = {wiring.left: left, wiring.right: right}.get(port, 0.0)

    def reset_gyro(self, world: World, now_us: int) -> None:
        self._gyro_zero = self._gyro_reading(world.gyro_angle_deg(), now_us)

    def follow_turn(self, world: World) -> None:
        """Count the gyro's turn to the world's heading now. Called on both sides of a place: the drive before
        it counts as driven, and the person's turn as the gyro would integrate it, the short way round."""
        self._count_turn(world.gyro_angle_deg())

    def _count_turn(self, wrapped_deg: float) -> float:
        """The heading's whole-turn angle, counted from the wrapped one (`World.gyro_angle_deg`)."""
        last, total = self._yaw
        total += (wrapped_deg - last + 180.0) % 360.0 - 180.0
        self._yaw = (wrapped_deg, total)
        return total

    def _gyro_reading(self, wrapped_deg: float, now_us: int) -> float:
        """The gyro's whole-turn angle now, with the drift of this test's gyro bias."""
        total = self._count_turn(wrapped_deg)
        return total if self.noise is None else total + self.noise.gyro_drift_deg(now_us)

