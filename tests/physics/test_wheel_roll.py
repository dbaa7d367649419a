"""The wheels roll as far as their counts say (issue 45): on the real robot a program that measures distance by
its wheel counts and the nominal wheel size drives that far, within 1-2%. scripts/benchmark_wheel_roll.py measures
the same at four powers; this checks one, in a second."""

import math

import mujoco
import numpy as np
import pytest

from hakoniwa.physics.course import load_course
from hakoniwa.physics.robots import BODIES
from hakoniwa.physics.world import World


@pytest.mark.parametrize("name", sorted(BODIES))
def test_at_steady_speed_the_axle_goes_what_the_counts_say_and_the_caster_drags_nothing(name):
    """The axle centre's speed over the wheels' turning speed is the nominal radius (the tyres do not sink
    into the floor), and the caster's floor contact is frictionless, condim 1 (without its priority MuJoCo
    takes the floor's condim 3 and friction 1, a drag the wheels creep under: 0.955-0.994 of the radius)."""
    world = World(load_course("etrobocon-l"), BODIES[name], imu=True)
    world.set_motor_power(40, 40)
    world.step(1500)
    x0, y0 = world.position()
    turned0 = float(np.mean(world.wheel_angles_deg()))
    world.step(500)
    x1, y1 = world.position()
    turned = math.radians(float(np.mean(world.wheel_angles_deg())) - turned0)
    assert math.hypot(x1 - x0, y1 - y0) / (turned * world.body.wheel_radius) == pytest.approx(1.0, abs=0.002)
    m, d = world.model, world.data
    caster = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "caster")
    dims = [int(d.contact[i].dim) for i in range(d.ncon) if caster in d.contact[i].geom]
    assert dims == [1]
