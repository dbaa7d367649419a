"""Seeded noise in the physics: what makes two repetitions of one parameter set differ, as on a real EV3.

The paper repeats every parameter set because its Unity bench is not repeatable; ours is, to the
microsecond, so without noise a repetition says nothing. Noise here is *seeded*: the controller writes a
seed and a scale for each test (`Rx.NOISE_SEED`, `Rx.NOISE_SCALE`), and everything random in that test is
drawn from generators made from that seed, in a fixed order, at instants the lockstep fixes (test start,
sensor snapshots, motor commands, a scenario's places). So the same (parameters, seed, scale) still give the
same event and goal time to the microsecond under any machine load, and scale 0 draws nothing at all: the
bench is the noise-free bench, bit for bit.

Every source is zero-mean Gaussian with a standard deviation from the course's `[noise]` table
(`NoiseLevels`), multiplied by the scale. Draws happen outside MuJoCo's stepping, so the hot loop costs the
same with noise on. See docs/NOISE.md for the model, the default levels and why they are realistic.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from hakoniwa.physics.robot import ULTRASONIC_MAX_MM

REFLECT_RANGE = (0.0, 100.0)  # what the colour sensor's reflect mode can report


@dataclass(frozen=True)
class NoiseLevels:
    """One standard deviation of each noise source at scale 1: the course TOML's `[noise]` table.

    "Per test" draws are made once when a test starts (a sensor's offset, a motor's gain, where the robot is
    put down); "per reading" at each sensor snapshot; "per command" each time motor powers are applied. The
    defaults are the oval's levels; docs/NOISE.md says where each number comes from.
    """

    reflect_sd: float = 0.5  # colour sensor reflect, per reading [reflect units, 0..100 scale]
    reflect_offset_sd: float = 1.0  # colour sensor reflect, per test: room light, sensor height [units]
    gyro_rate_sd_dps: float = 1.0  # gyro rate, per reading [deg/s]
    gyro_bias_sd_dps: float = 0.1  # gyro bias, per test: adds to the rate and drifts the angle [deg/s]
    ultrasonic_sd_mm: float = 5.0  # ultrasonic distance, per reading [mm]
    motor_gain_sd: float = 0.02  # wheel speed per unit of power, per test and wheel [fraction of 1]
    motor_jitter_sd: float = 0.01  # wheel speed per unit of power, per command and wheel [fraction of 1]
    start_xy_sd_mm: float = 3.0  # start position, per test, in x and in y [mm]
    start_yaw_sd_deg: float = 1.0  # start heading, per test [deg]

    @classmethod
    def keys(cls) -> tuple[str, ...]:
        """The `[noise]` keys a course may set, in declaration order."""
        return tuple(f.name for f in fields(cls))

    def scaled(self, scale: float) -> NoiseLevels:
        """Every level multiplied by `scale` (the controller's `Rx.NOISE_SCALE`)."""
        return NoiseLevels(**{k: getattr(self, k) * scale for k in self.keys()})


DEFAULT_NOISE = NoiseLevels()


@dataclass(frozen=True)
class StartOffset:
    """How far the robot is put down from the course's start pose: metres, and degrees counter-clockwise
    (the world's convention, as `World.pose`)."""

    dx_m: float
    dy_m: float
    dyaw_deg: float


class _Normals:
    """One stream's standard normals, drawn from its generator in blocks and handed out in order.

    A generator draws a block of n normals one after another, exactly as n draws of one would come, so
    `take(3)` gives the values `standard_normal(3)` would have, in the same order; a block costs one numpy
    call where a draw per snapshot cost one each, several microseconds at every handshake. What a test leaves
    undrawn of its last block is never used: every test makes its generators afresh from its seed.
    """

    BLOCK = 384

    def __init__(self, rng: np.random.Generator) -> None:
        self._rng = rng
        self._values: list[float] = []
        self._next = 0

    def take(self, n: int) -> list[float]:
        if self._next + n > len(self._values):
            self._values = self._values[self._next:] + self._rng.standard_normal(self.BLOCK).tolist()
            self._next = 0
        start = self._next
        self._next += n
        return self._values[start:self._next]


class NoiseDraw:
    """One test's noise, drawn from its seed.

    Three independent streams are spawned from the seed, so that the number of draws one kind of event
    makes never shifts another's: per-test values (drawn here, in the order of `NoiseLevels`' per-test fields,
    then one put-down per scenario place as it happens), sensor readings (three normals per snapshot: reflect,
    gyro rate, ultrasonic) and motor commands (two normals per command: left, right). Draws are made even where
    a level is 0, so changing one level leaves the others' draws as they were.
    """

    def __init__(self, levels: NoiseLevels, seed: int, scale: float) -> None:
        if not (math.isfinite(scale) and scale >= 0):
            raise ValueError(f"noise scale must be a finite number >= 0, got {scale!r}")
        self.seed = seed
        self.scale = scale
        lv = self.levels = levels.scaled(scale)
        per_test, readings, motors = (np.random.default_rng(s) for s in np.random.SeedSequence(seed).spawn(3))
        self._per_test, self._readings, self._motors = per_test, _Normals(readings), _Normals(motors)
        z = per_test.standard_normal(7).tolist()
        self.reflect_offset = lv.reflect_offset_sd * z[0]
        self.gyro_bias_dps = lv.gyro_bias_sd_dps * z[1]
        # A wheel cannot turn backwards for a forward command: however large the scale, a gain stays >= 0.
        self.motor_gain = (max(0.0, 1.0 + lv.motor_gain_sd * z[2]), max(0.0, 1.0 + lv.motor_gain_sd * z[3]))
        self.start = self._put_down(z[4:7])
        self._reflect_flicker = 0.0  # the last reading's reflect flicker (`shift_reflect`)

    def _put_down(self, z: list[float]) -> StartOffset:
        lv = self.levels
        return StartOffset(lv.start_xy_sd_mm / 1000 * z[0], lv.start_xy_sd_mm / 1000 * z[1], lv.start_yaw_sd_deg * z[2])

    def placement(self) -> StartOffset:
        """Where the person who put the robot down at the start puts it down again, off the spot aimed at (a
        scenario's `[[place]]`): as noisy as the start, drawn from the per-test stream after the start's
        values, one place after another, so a test's places never shift its other draws."""
        return self._put_down(self._per_test.standard_normal(3).tolist())

    def reading(self, reflect: float, rate_dps: float, ultrasonic_mm: int) -> tuple[float, float, int]:
        """Noisy (reflect, gyro rate, ultrasonic distance) for one snapshot of the true values.

        The reflect stays in the sensor's 0..100 range and is left unrounded, so that the colour id and raw
        RGB derived from it agree with the reflect the program reads. The rate includes the test's gyro
        bias. An ultrasonic "no echo" stays exactly that: noise does not invent an obstacle.
        """
        lv = self.levels
        z_reflect, z_rate, z_sonar = self._readings.take(3)
        lo, hi = REFLECT_RANGE
        self._reflect_flicker = lv.reflect_sd * z_reflect
        noisy_reflect = min(max(reflect + self.reflect_offset + self._reflect_flicker, lo), hi)
        noisy_rate = rate_dps + self.gyro_bias_dps + lv.gyro_rate_sd_dps * z_rate
        if ultrasonic_mm >= ULTRASONIC_MAX_MM:
            noisy_mm = ultrasonic_mm
        else:
            noisy_mm = min(max(round(ultrasonic_mm + lv.ultrasonic_sd_mm * z_sonar), 0), ULTRASONIC_MAX_MM - 1)
        return noisy_reflect, noisy_rate, noisy_mm

    def shift_reflect(self, channels: tuple[float, ...]) -> tuple[float, ...]:
        """The floor's other colour channels with the last reading's reflect noise: light and sensor height
        brighten or darken every colour alike, so one draw shifts them all."""
        lo, hi = REFLECT_RANGE
        return tuple(min(max(c + self.reflect_offset + self._reflect_flicker, lo), hi) for c in channels)

    def gyro_drift_deg(self, time_us: int) -> float:
        """What the gyro angle has drifted by at `time_us`: the test's rate bias, integrated from the start
        (the EV3 gyro's angle is its own integral of the rate it measures)."""
        return self.gyro_bias_dps * time_us / 1e6

    def motor_factors(self) -> tuple[float, float]:
        """(left, right) multipliers of the commanded wheel speeds for one motor command: the test's gain
        of each wheel times this command's jitter."""
        jl, jr = self._motors.take(2)
        sd = self.levels.motor_jitter_sd
        return (max(0.0, self.motor_gain[0] * (1.0 + sd * jl)), max(0.0, self.motor_gain[1] * (1.0 + sd * jr)))

    def describe(self) -> str:
        """One line for the physics log."""
        s = self.start
        return (f"noise seed {self.seed} scale {self.scale:g}: reflect offset {self.reflect_offset:+.2f}, "
                f"gyro bias {self.gyro_bias_dps:+.3f} deg/s, motor gain {self.motor_gain[0]:.4f}/"
                f"{self.motor_gain[1]:.4f}, start {s.dx_m * 1000:+.1f} mm, {s.dy_m * 1000:+.1f} mm, "
                f"{s.dyaw_deg:+.2f} deg")
