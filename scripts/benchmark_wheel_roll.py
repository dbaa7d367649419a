"""How far the bench's robots roll for what their wheel counts say (issue 45): a program that measures distance by
its counts and the nominal wheel size must drive that far, as on the real robot (within 1-2% on the mat).

For each body and power it prints, at steady speed on a straight: the effective rolling radius (the axle
centre's speed over the wheels' turning speed) against the nominal one; how deep the wheels sink into the floor
(MuJoCo's soft contact); the caster's drag along the heading, which the wheels' traction must balance, with the
friction dimension MuJoCo gave the caster's contact (the caster asks for condim 1, frictionless; a contact
takes the larger condim of its two geoms where neither has priority, and the floor's is 3). Then, over a 3 s
straight from rest, the path the axle centre drove against the counts' distance, and the part of the shortfall
lost in the first 0.5 s, while the servo's torque exceeds the tyres' grip and the wheels spin.

Usage: python scripts/benchmark_wheel_roll.py [--course NAME]
"""

from __future__ import annotations

import math

import click
import mujoco
import numpy as np

from hakoniwa.physics.course import CourseError, load_course
from hakoniwa.physics.robots import BODIES
from hakoniwa.physics.world import World
from hakoniwa.wire.timebase import PHYSICS_STEP_US

POWERS = (20, 40, 70, 100)
SETTLE_MS, STEADY_MS = 2000, 1000  # to steady speed, then averaged over
RUN_MS, LAUNCH_MS = 3000, 500


def _steps(ms: int) -> int:
    return ms * 1000 // PHYSICS_STEP_US


def _contacts(world: World) -> dict[str, tuple[float, float, int]]:
    """The robot's floor contacts by geom: (sinking depth [m], force along the heading [N], friction dimension)."""
    m, d = world.model, world.data
    _, _, yaw = world.pose()
    heading = np.array([math.cos(yaw), math.sin(yaw), 0.0])
    found = {}
    force = np.zeros(6)
    for i in range(d.ncon):
        c = d.contact[i]
        names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g) for g in c.geom]
        if "floor" in names:
            mujoco.mj_contactForce(m, d, i, force)
            along = float(c.frame.reshape(3, 3).T @ force[:3] @ heading)  # the contact frame's rows are its axes
            found[next(n for n in names if n != "floor")] = (-float(c.dist), along, int(c.dim))
    return found


def _driven(world: World, ms: int) -> tuple[float, float]:
    """Step `ms`: the axle centre's path and the counts' distance (mean wheel angle by the nominal radius) [m]."""
    x0, y0 = world.position()
    start = np.array(world.wheel_angles_deg())
    world.step(_steps(ms))
    x1, y1 = world.position()
    turned = math.radians(float(np.mean(np.array(world.wheel_angles_deg()) - start)))
    return math.hypot(x1 - x0, y1 - y0), turned * world.body.wheel_radius


def _steady(world: World, power: int) -> str:
    world.set_motor_power(power, power)
    world.step(_steps(SETTLE_MS))
    speed = turning = sink = drag = 0.0
    dim = 0
    samples = _steps(STEADY_MS)
    for _ in range(samples):
        world.step(1)
        speed += math.hypot(*world.data.qvel[:2].tolist()) / samples  # a free joint's linear velocity: world axes
        turning += float(np.mean(world.wheel_speeds())) / samples
        contacts = _contacts(world)
        sink += float(np.mean([contacts[w][0] for w in ("wheel_left", "wheel_right")])) / samples
        drag += contacts.get("caster", (0.0, 0.0, 0))[1] / samples
        dim = max(dim, contacts.get("caster", (0.0, 0.0, 0))[2])
    radius = world.body.wheel_radius
    rolling = speed / turning
    return (f"rolling radius {rolling * 1000:6.2f} mm ({rolling / radius:.4f} of {radius * 1000:g})  sink "
            f"{sink * 1000:.3f} mm  caster drag {drag:+.2f} N (condim {dim})")


def _straight(world: World, power: int) -> str:
    world.set_motor_power(power, power)
    launch_driven, launch_counted = _driven(world, LAUNCH_MS)
    driven, counted = _driven(world, RUN_MS - LAUNCH_MS)
    driven, counted = driven + launch_driven, counted + launch_counted
    if world.touching_wall():
        raise click.ClickException(f"the robot met a wall on its straight: pick a course with {counted:.1f} m free")
    return (f"{RUN_MS / 1000:g} s from rest: driven {driven:.3f} m, counts {counted:.3f} m "
            f"({driven / counted - 1:+.2%}; of which {(launch_driven - launch_counted) * 1000:+.1f} mm in the first "
            f"{LAUNCH_MS} ms)")


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--course", default="etrobocon-l", show_default=True, help="Built-in course name or course folder.")
def main(course: str) -> None:
    """Print how far each body rolls for its wheel counts, straight ahead at several powers."""
    try:
        floor = load_course(course)
    except CourseError as e:
        raise click.ClickException(str(e)) from None
    for name, body in BODIES.items():
        for power in POWERS:
            # With its IMU the robot rests on its wheels before it starts (World's settling), as a robot set down.
            steady, straight = (World(floor, body, imu=True) for _ in range(2))
            print(f"{name:7} power {power:3}: {_steady(steady, power)}; {_straight(straight, power)}")


if __name__ == "__main__":
    main()
