"""Event detection on the default course, with the robot placed by hand (no Athrill needed)."""

import math

import mujoco
import pytest

from hakoniwa.physics.course import load_course
from hakoniwa.physics.task import LapTask
from hakoniwa.physics.world import World
from hakoniwa.wire.protocol import Event
from testctl.bench_options import DEFAULT_COURSE


@pytest.fixture(scope="module")
def world():
    return World(load_course(DEFAULT_COURSE))


def place(world: World, x: float, y: float, yaw_deg: float = 0.0) -> None:
    world.reset()
    q = world.data.qpos
    q[0], q[1] = x, y
    q[3], q[4], q[5], q[6] = math.cos(math.radians(yaw_deg) / 2), 0, 0, math.sin(math.radians(yaw_deg) / 2)
    mujoco.mj_forward(world.model, world.data)


def test_goal_needs_all_checkpoints_in_order(world):
    course = world.course
    task = LapTask(course, course.time_limit_us)
    last = course.checkpoints[-1]
    place(world, last.x, last.y)
    assert task.check(world, 1_000) == Event.NONE  # the finish first does not count
    events = []
    for i, cp in enumerate(course.checkpoints):
        place(world, cp.x, cp.y)
        events.append(task.check(world, 1_000_000 * (i + 1)))
    assert events == [Event.NONE] * (len(course.checkpoints) - 1) + [Event.GOAL]
    assert task.passed_us == [1_000_000, 2_000_000, 3_000_000, 4_000_000]


def test_skipping_a_checkpoint_is_no_goal(world):
    course = world.course
    task = LapTask(course, course.time_limit_us)
    for cp in (course.checkpoints[0], course.checkpoints[2], course.checkpoints[3]):
        place(world, cp.x, cp.y)
        assert task.check(world, 1_000) == Event.NONE
    assert task.next_checkpoint == 1


def test_wall_contact_is_hit_wall(world):
    task = LapTask(world.course, world.course.time_limit_us)
    east = next(w for w in world.course.walls if w.name == "east")
    place(world, east.x - east.hx - 0.08, 0.4)  # nose against the east wall
    world.set_motor_power(30, 30)
    # Pushed by its motors, the robot rebounds from the wall and meets it again: look when it first meets it.
    ms = 0
    while not world.touching_wall() and ms < 300:
        world.step(1)
        ms += 1
    assert world.touching_wall()
    assert task.check(world, ms * 1000) == Event.HIT_WALL


def test_checkpoint_volumes_are_not_walls(world):
    task = LapTask(world.course, world.course.time_limit_us)
    cp = world.course.checkpoints[1]
    place(world, cp.x, cp.y)
    world.set_motor_power(20, 20)
    world.step(200)
    assert not world.touching_wall()
    assert task.check(world, 200_000) != Event.HIT_WALL


def test_time_limit_is_time_over(world):
    task = LapTask(world.course, world.course.time_limit_us)
    place(world, world.course.start.x, world.course.start.y)
    limit = world.course.time_limit_us
    assert task.check(world, limit - 10_000) == Event.NONE
    assert task.check(world, limit) == Event.TIME_OVER


def test_color_sensor_reads_the_floor(world):
    course = world.course
    assert course.reflect_at(0.0, -0.5) < 65  # line centre: dark (the edges are soft ramps)
    assert course.reflect_at(0.0, -0.3) == pytest.approx(100)  # well off the line: white
    place(world, course.start.x, course.start.y)
    assert 65 <= world.measure().reflect <= 85  # the start puts the sensor on the line's edge


def test_reset_restores_the_start(world):
    world.reset()
    start = world.pose()
    world.set_motor_power(50, 20)
    world.step(1000)
    assert world.pose() != start
    world.reset()
    assert world.pose() == start
