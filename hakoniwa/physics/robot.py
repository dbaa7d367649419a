"""The two-wheel robots' bodies: their dimensions, motors and where their sensors sit.

The motors are velocity-servo actuators with a torque limit, which is the steady-state behaviour of a DC
motor under a speed controller (EV3RT's `ev3_motor_set_power` regulates speed): power p commands a wheel
speed of p% of the body's `max_wheel_speed`, reached through the wheel's inertia and the limited torque.
The EV3 body's sizes are tuned so that a lap of the oval at power 15 takes about half a minute, like the
paper's 32 s. The wheels collide as spheres: one contact each with the floor instead of a cylinder's
several, which makes a physics step about a third cheaper and rolls the same way on a flat floor.

HackSPi's body (ET Robocon's SPIKE Prime robot) is sized from LEGO SPIKE Prime parts: docs/DESIGN-NOTES.md
("The HackSPi robot") says where each number comes from and which are estimates.
"""

from __future__ import annotations

from dataclasses import dataclass

CHASSIS_BACK_M = 0.01  # the chassis box's centre sits this far behind the axle
# The tyres' contact with the floor, stiff as a tyre on a mat is: MuJoCo's default contact (a 20 ms time
# constant) let the wheels sink 0.4 mm and roll on a smaller radius than their counts say (issue 45,
# scripts/benchmark_wheel_roll.py). 2 ms is the stiffest time constant the 1 ms physics step integrates stably
# (MuJoCo asks for at least two steps); the impedance 0.99 makes the contact hard from its first 1 mm.
TYRE_SOLREF = "0.002 1"
TYRE_SOLIMP = "0.99 0.99 0.001"
ULTRASONIC_MAX_MM = 2550  # the EV3 sensor's reading when nothing is in range (EV3RT: 255 cm); the world's
# "no echo"


@dataclass(frozen=True)
class Body:
    """A two-wheel robot's body: what the MuJoCo model is built from."""

    wheel_radius: float  # m
    track_width: float  # m, between the wheel centres
    max_wheel_speed: float  # rad/s at power 100
    motor_gain: float  # N m per rad/s of speed error (the servo's kv)
    motor_torque_limit: float  # N m
    chassis_half: tuple[float, float, float]  # m, half sizes of the body box
    chassis_mass: float  # kg
    color_sensor_forward: float  # m ahead of the axle centre, looking down
    ultrasonic_forward: float  # m ahead of the axle centre, looking forward


# The EV3-like robot every EV3 result was measured on.
EV3_BODY = Body(wheel_radius=0.05, track_width=0.13, max_wheel_speed=29.0, motor_gain=0.6, motor_torque_limit=0.6,
                chassis_half=(0.07, 0.055, 0.03), chassis_mass=0.6, color_sensor_forward=0.08,
                ultrasonic_forward=0.075)
# HackSPi: SPIKE Prime's 56 mm wheels on its medium motors (about 1000 deg/s unloaded, 0.18 N m stall), the
# hub, a Raspberry Pi and its battery on top; track, lengths and mass estimated (DESIGN-NOTES.md).
HACKSPI_BODY = Body(wheel_radius=0.028, track_width=0.12, max_wheel_speed=17.5, motor_gain=0.2,
                    motor_torque_limit=0.18, chassis_half=(0.065, 0.045, 0.045), chassis_mass=0.55,
                    color_sensor_forward=0.07, ultrasonic_forward=0.07)


@dataclass(frozen=True)
class Wiring:
    """Which motor ports (A = 0 .. D = 3) drive the wheels, and how each motor is mounted: +1 where positive
    power drives the robot forward, -1 where the motor is mounted mirror-wise and negative power does (its
    encoder then counts down as the robot drives forward). A course's `[robot]` table may change the ports."""

    left: int
    right: int
    left_forward: int = 1
    right_forward: int = 1


# The TOPPERS samples' wiring, and that of the paper authors' program: left wheel on A, right wheel on B.
DEFAULT_WIRING = Wiring(left=0, right=1)


def robot_mjcf(x: float, y: float, yaw_deg: float, body: Body = EV3_BODY, imu: bool = False,
               sleeps: bool = True) -> str:
    """The robot body as an MJCF fragment placed at the start pose; with `imu`, a site at the hub for the
    accelerometer `imu_sensor_mjcf` declares; without `sleeps`, a robot MuJoCo never puts to sleep (in a world
    that lets resting bodies sleep, a robot waiting for its start must still feel its motors)."""
    hx, hy, hz = body.chassis_half
    r = body.wheel_radius
    half_track = body.track_width / 2
    caster = 0.012
    # A geom's priority makes its own contact parameters those of its contacts (MuJoCo otherwise mixes the
    # two geoms' and takes the larger condim, which gave the caster the floor's friction).
    tyre = f' priority="1" solref="{TYRE_SOLREF}" solimp="{TYRE_SOLIMP}"'
    body_z = r
    hub = f'''
      <site name="imu" pos="-0.01 0 {hz}" size="0.006" rgba="0 1 0 1"/>''' if imu else ""
    return f"""
    <body name="robot" pos="{x} {y} {body_z}" euler="0 0 {yaw_deg}"{"" if sleeps else ' sleep="never"'}>
      <freejoint name="robot_root"/>
      <geom name="chassis" type="box" size="{hx} {hy} {hz}" pos="{-CHASSIS_BACK_M} 0 {hz}" mass="{body.chassis_mass}"
            rgba=".9 .5 .1 1"/>
      <geom name="caster" type="sphere" size="{caster}" pos="{-hx + 0.005} 0 {caster - body_z}" condim="1"
            priority="1" mass="0.02" rgba=".3 .3 .3 1"/>
      <site name="color_sensor" pos="{body.color_sensor_forward} 0 {-body_z + 0.01}" size="0.006" rgba="1 0 0 1"/>
      <site name="ultrasonic" pos="{body.ultrasonic_forward} 0 {hz}" size="0.008" rgba="0 0 1 1"/>{hub}
      <body name="wheel_left" pos="0 {half_track} 0">
        <joint name="wheel_left" type="hinge" axis="0 1 0" damping="0.001"/>
        <geom name="wheel_left" type="sphere" size="{r}" mass="0.05"{tyre} rgba=".1 .1 .1 1"/>
      </body>
      <body name="wheel_right" pos="0 {-half_track} 0">
        <joint name="wheel_right" type="hinge" axis="0 1 0" damping="0.001"/>
        <geom name="wheel_right" type="sphere" size="{r}" mass="0.05"{tyre} rgba=".1 .1 .1 1"/>
      </body>
    </body>"""


def imu_sensor_mjcf() -> str:
    """The hub's accelerometer: the specific force at the `imu` site in the robot's frame [m/s^2] (at rest
    +g up, as a real accelerometer reads it)."""
    return '''
    <accelerometer name="imu_accel" site="imu"/>'''


def actuators_mjcf(body: Body = EV3_BODY) -> str:
    limit = body.motor_torque_limit
    kv = body.motor_gain
    return f"""
    <velocity name="motor_left" joint="wheel_left" kv="{kv}" forcelimited="true" forcerange="{-limit} {limit}"/>
    <velocity name="motor_right" joint="wheel_right" kv="{kv}" forcelimited="true" forcerange="{-limit} {limit}"/>"""
