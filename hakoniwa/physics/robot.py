"""The EV3-like two-wheel robot: its dimensions, motors and where its sensors sit.

The motors are velocity-servo actuators with a torque limit, which is the steady-state behaviour of a DC
motor under a speed controller (EV3RT's `ev3_motor_set_power` regulates speed): power p commands a wheel
speed of p% of `MAX_WHEEL_SPEED`, reached through the wheel's inertia and the limited torque. Sizes are
tuned so that a lap of the oval at power 15 takes about half a minute, like the paper's 32 s. The wheels
collide as spheres: one contact each with the floor instead of a cylinder's several, which makes a physics
step about a third cheaper and rolls the same way on a flat floor.
"""

from __future__ import annotations

from dataclasses import dataclass

WHEEL_RADIUS = 0.05  # m
TRACK_WIDTH = 0.13  # m, between the wheel centres
MAX_WHEEL_SPEED = 29.0  # rad/s at power 100
MOTOR_GAIN = 0.6  # N m per rad/s of speed error (the servo's kv)
MOTOR_TORQUE_LIMIT = 0.6  # N m
CHASSIS_HALF = (0.07, 0.055, 0.03)  # m, half sizes of the body box
CHASSIS_MASS = 0.6  # kg
COLOR_SENSOR_FORWARD = 0.08  # m ahead of the axle centre, looking down
ULTRASONIC_FORWARD = 0.075  # m ahead of the axle centre, looking forward
ULTRASONIC_MAX_MM = 2550  # reading when nothing is in range (EV3RT: 255 cm)


@dataclass(frozen=True)
class Wiring:
    """Which motor ports (A = 0 .. D = 3) drive the wheels; a course's `[robot]` table may change it."""

    left: int
    right: int


# The TOPPERS samples' wiring, and that of the paper authors' program: left wheel on A, right wheel on B.
DEFAULT_WIRING = Wiring(left=0, right=1)


def robot_mjcf(x: float, y: float, yaw_deg: float) -> str:
    """The robot body as an MJCF fragment placed at the start pose."""
    hx, hy, hz = CHASSIS_HALF
    r = WHEEL_RADIUS
    half_track = TRACK_WIDTH / 2
    caster = 0.012
    body_z = r
    return f"""
    <body name="robot" pos="{x} {y} {body_z}" euler="0 0 {yaw_deg}">
      <freejoint name="robot_root"/>
      <geom name="chassis" type="box" size="{hx} {hy} {hz}" pos="-0.01 0 {hz}" mass="{CHASSIS_MASS}" rgba=".9 .5 .1 1"/>
      <geom name="caster" type="sphere" size="{caster}" pos="{-hx + 0.005} 0 {caster - body_z}" condim="1"
            mass="0.02" rgba=".3 .3 .3 1"/>
      <site name="color_sensor" pos="{COLOR_SENSOR_FORWARD} 0 {-body_z + 0.01}" size="0.006" rgba="1 0 0 1"/>
      <site name="ultrasonic" pos="{ULTRASONIC_FORWARD} 0 {hz}" size="0.008" rgba="0 0 1 1"/>
      <body name="wheel_left" pos="0 {half_track} 0">
        <joint name="wheel_left" type="hinge" axis="0 1 0" damping="0.001"/>
        <geom name="wheel_left" type="sphere" size="{r}" mass="0.05" rgba=".1 .1 .1 1"/>
      </body>
      <body name="wheel_right" pos="0 {-half_track} 0">
        <joint name="wheel_right" type="hinge" axis="0 1 0" damping="0.001"/>
        <geom name="wheel_right" type="sphere" size="{r}" mass="0.05" rgba=".1 .1 .1 1"/>
      </body>
    </body>"""


def actuators_mjcf() -> str:
    limit = MOTOR_TORQUE_LIMIT
    return f"""
    <velocity name="motor_left" joint="wheel_left" kv="{MOTOR_GAIN}" forcelimited="true" forcerange="{-limit} {limit}"/>
    <velocity name="motor_right" joint="wheel_right" kv="{MOTOR_GAIN}" forcelimited="true" forcerange="{-limit} {limit}"/>"""
