"""ET Robocon's score: the regulation's numbers, the run task (gates, finish in the garage, the sumo bottle,
the time limit) and objects in the world (pushed, seen, read, never a wall)."""

from __future__ import annotations

import dataclasses
import math
import shutil

import numpy as np
import pytest

from hakoniwa.physics.course import COURSES_DIR, Pose, load_course
from hakoniwa.physics.etrobocon_task import EtRoboconTask
from hakoniwa.physics.robot import ULTRASONIC_MAX_MM
from hakoniwa.physics.robots import BUILT_IN, DEFAULT_ROBOT, RobotError, parse_robot
from hakoniwa.physics.world import ObjectState
from hakoniwa.wire.etrobocon_rules import Score, result_points, run_points
from hakoniwa.wire.protocol import ColorId, Event
from tests.helpers.environments import environment


@pytest.mark.parametrize("lap_us, points", [(12_340_000, 22.7), (12_399_999, 22.7), (0, 35.0), (34_950_000, 0.1),
                                            (35_000_000, 0.0), (80_000_000, 0.0), (None, 0.0)])
def test_run_points_are_35_less_the_run_time_in_tenths(lap_us, points):
    assert run_points(lap_us) == points


def test_result_points_add_the_tasks_and_never_go_below_zero():
    assert result_points(22.7, 12) == pytest.approx(34.7) and result_points(0.0, -35) == 0.0
    applied = Score.of("applied", 20_000_000, 3, True, True)
    assert (applied.run_points, applied.task_points, applied.total) == (15.0, 2 * 3 + 3 + 3 + 5, 32.0)
    basic = Score.of("basic", None, 2, False, None)
    assert (basic.run_points, basic.task_points, basic.total, basic.lap_gate) == (0.0, 8, 8.0, False)
    assert Score.from_dict(applied.to_dict()) == applied
    assert applied.describe() == "score 32: run 15 (LAP 20.00 s), 3 checkpoints, LAP gate, finish, sumo (applied class)"


class FakeWorld:
    """What the task looks at: where the robot is, whether it moves, walls and the bottle."""

    body = BUILT_IN["hackspi"].body

    def __init__(self) -> None:
        self.xy, self.yaw, self.moving, self.wall = (0.0, 0.0), 0.0, True, False
        self.bottle = ObjectState(0.0, 0.0, True, 0.0)

    def position(self):
        return self.xy

    def pose(self):
        return (*self.xy, self.yaw)

    def touching_wall(self):
        return self.wall

    def wheel_speeds(self):
        return (5.0, 5.0) if self.moving else (0.0, 0.0)

    def object_state(self, name):
        return self.bottle


def lane():
    return load_course("etrobocon-l")


def test_checkpoints_count_once_in_any_order_before_the_lap_gate_which_does_not_end_the_run():
    course = lane()
    task, world = EtRoboconTask(course, 120_000_000), FakeWorld()
    cp1, cp2, cp3, lap = course.checkpoints
    for t, (gate, backwards) in enumerate(((cp2, False), (cp2, False), (cp1, True), (cp1, False), (lap, True),
                                           (lap, False), (cp3, False)), 1):
        world.xy = (gate.x, gate.y)
        world.yaw = math.radians(gate.heading_deg + (180 if backwards else 0))  # against its arrow: no gate
        assert task.check(world, t * 10_000) == Event.NONE
    score = task.score(world)
    assert (score.checkpoints, score.lap_gate, score.lap_time_s) == (2, True, 0.06)  # cp3 came after the LAP
    assert task.passed_us == [10_000, 40_000, 60_000]


def test_the_finish_is_three_seconds_stopped_in_the_garage_and_a_stop_begun_in_time_is_waited_out():
    course = lane()
    garage = course.zone("garage")
    task, world = EtRoboconTask(course, 2_000_000), FakeWorld()
    world.xy = (garage.x, garage.y + garage.hy + 0.05)  # the axle outside, the chassis's front corners in
    world.yaw = -math.pi / 2
    world.moving = False
    assert first_event(task, world) == (Event.FINISH, 3_010_000)  # past the 2 s limit
    assert task.score(world).finish
    world.xy = (garage.x, garage.y + garage.hy + 0.2)  # wholly outside: the limit ends the run
    task.reset()
    assert first_event(task, world) == (Event.TIME_OVER, 2_000_000) and not task.score(world).finish


def first_event(task: EtRoboconTask, world: FakeWorld, start_us: int = 10_000) -> tuple[Event, int]:
    """Check every 10 ms, as the bench does, until the task raises an event."""
    t = start_us
    while (event := task.check(world, t)) == Event.NONE:
        t += 10_000
    return event, t


def test_moving_in_the_garage_restarts_the_count():
    course = lane()
    garage = course.zone("garage")
    task, world = EtRoboconTask(course, 120_000_000), FakeWorld()
    world.xy, world.moving = (garage.x, garage.y), False
    assert all(task.check(world, t) == Event.NONE for t in range(10_000, 2_000_000, 10_000))
    world.moving = True
    task.check(world, 2_000_000)
    world.moving = False
    assert first_event(task, world, 2_010_000) == (Event.FINISH, 5_010_000)


@pytest.mark.parametrize("robot_in_ring, upright, speed, scored", [
    (True, True, 0.0, True), (False, True, 0.0, False), (True, False, 0.0, False), (True, True, 0.1, False)])
def test_the_bottle_counts_out_of_the_ring_standing_still_with_the_robot_left_inside(robot_in_ring, upright,
                                                                                     speed, scored):
    course = lane()
    ring = course.zone("ring")
    task, world = EtRoboconTask(course, 120_000_000), FakeWorld()
    world.xy = (ring.x, ring.y) if robot_in_ring else (ring.x + 1.0, ring.y)
    world.bottle = ObjectState(ring.x, ring.y, True, 0.0)
    task.check(world, 10_000)
    assert task.score(world).sumo is False
    world.bottle = ObjectState(ring.x + ring.radius + 0.04, ring.y, True, 0.0)  # its edge 7.5 mm outside
    task.check(world, 20_000)
    world.bottle = dataclasses.replace(world.bottle, upright=upright, speed=speed)
    assert task.score(world).sumo is scored
    assert EtRoboconTask(load_course("oval"), 1).score(world).sumo is None  # no ring, no bottle: not scored


def course_with_objects(tmp_path, objects: str, start: str = "x = -0.38\ny = -0.52\nyaw_deg = 0"):
    folder = tmp_path / "c"
    shutil.copytree(COURSES_DIR / "oval", folder)
    toml = folder / "course.toml"
    text = toml.read_text().replace("x = -0.38\ny = -0.52\nyaw_deg = 0", start)
    toml.write_text(text.replace("[noise]", objects + "\n[noise]"))
    return load_course(folder)


def test_pushing_an_object_is_no_wall_and_the_ultrasonic_sensor_sees_it(tmp_path):
    course = course_with_objects(tmp_path, '[[object]]\nname = "bottle"\nshape = "cylinder"\nradius = 0.0325\n'
                                           'height = 0.205\nmass = 0.3\nfriction = 0.3\ncolor = "black"\n'
                                           'x = 0.2\ny = -0.52\n')
    env = environment(course, 10_000_000, DEFAULT_ROBOT)
    env.begin(None)
    assert env.read_sensors().ultrasonic_mm == round((0.2 - 0.0325 - (-0.38 + 0.075)) * 1000)
    for t in range(1, 21):
        env.drive([40, 40, 0, 0])
        assert not env.advance_to(t * 100_000), env.event  # no HIT_WALL
    bottle = env.world.object_state("bottle")
    assert bottle.x > 0.5 and bottle.upright and abs(bottle.y + 0.52) < 0.1
    assert env.read_sensors().ultrasonic_mm < 100  # the bottle, just ahead of the robot that pushes it
    replay = env.replay("lap")
    assert len(replay.object_states) == len(replay.times_us) and replay.object_states[0][:2] == (0.2, -0.52)


def test_the_colour_sensor_reads_an_object_under_it(tmp_path):
    tile = ('[[object]]\nname = "tile"\nshape = "box"\nlength = 0.06\nwidth = 0.06\nheight = 0.004\nmass = 0.02\n'
            'friction = 1.0\ncolor = "red"\nx = -0.30\ny = -0.52\n')
    course = course_with_objects(tmp_path, tile)
    env = environment(course, 10_000_000, BUILT_IN["hackspi"])
    env.begin(None)
    s = env.read_sensors()  # the sensor, 7 cm ahead of the axle, is over the tile
    # The red tile's channels (220, 0, 0 of 255) on HackSPi's sensor: 10-bit RGB, the hub's HSV of it
    # (RGB >> 2 = (93, 27, 27): pbio s 70, v 36, corrected to 91 and 59) and its colour, red.
    assert (s.color, s.rgb) == (ColorId.RED, (373, 108, 108))
    assert (s.spike.hsv, s.spike.color) == ((0, 91, 59), (0, 100, 100))
    assert env.world.measure().colour == pytest.approx((50.0, 50.0, 50 + 50 * 220 / 255 / 3))


def test_the_etrobocon_objective_ends_at_the_finish_and_reports_the_score(tmp_path):
    course = load_course("etrobocon-l")
    garage = course.zone("garage")
    course = dataclasses.replace(course, start=Pose(garage.x, garage.y, 90.0))
    env = environment(course, 120_000_000, BUILT_IN["hackspi"], objective="etrobocon")
    env.begin(None)
    assert env.advance_to(10_000_000) and env.event == Event.FINISH and env.event_us == 3_010_000
    score = env.score()
    assert (score.finish, score.lap_gate, score.total, score.sumo) == (True, False, 3.0, False)
    assert env.replay("etrobocon").score == score.to_dict()
    assert environment(course, 1, BUILT_IN["hackspi"]).score() is None  # the lap objective has none


def test_a_course_without_objects_steps_as_before():
    env = environment(load_course("oval"), 60_000_000, DEFAULT_ROBOT)
    env.begin(None)
    assert env.world.object_states() == () and env.replay("lap").object_states == ()
    assert env.read_sensors().ultrasonic_mm < ULTRASONIC_MAX_MM  # the wall ahead, as always
    assert np.isfinite(env.world.measure().reflect)


def test_films_and_the_viewer_put_each_object_where_the_replay_has_it():
    import mujoco

    from hakoniwa.physics.replay import RobotLook
    from hakoniwa.pictures.scene import build_scene

    course = load_course("etrobocon-l")
    robot = BUILT_IN["hackev"]
    scene = build_scene(course, RobotLook(robot.name, robot.hub, robot.body, tuple(k for _, k in robot.sensors)))
    bottle = mujoco.mj_name2id(scene.model, mujoco.mjtObj.mjOBJ_BODY, "object_bottle")
    state = (0.0, 0.0, 0.05, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    scene.show(state, 0)  # no object states: where the course stands them
    assert tuple(scene.data.xpos[bottle]) == pytest.approx((course.objects[0].x, course.objects[0].y, 0.1025))
    lying = (1.5, -0.2, 0.0325, math.cos(math.pi / 4), math.sin(math.pi / 4), 0.0, 0.0)
    scene.show(state, 0, lying)
    assert tuple(scene.data.xpos[bottle]) == pytest.approx(lying[:3])
    assert scene.data.xmat[bottle][8] == pytest.approx(0.0, abs=1e-9)  # knocked over: its axis lies flat


@pytest.mark.parametrize("robot, competition_class, points", [("hackspi", "applied", 2), ("basic", "basic", 4),
                                                               ("default", "applied", 2)])
def test_a_run_is_scored_by_its_robots_class_and_a_robot_of_none_by_the_courses(robot, competition_class, points):
    """HackSPi competes in the applied class and SPIKE-RT on the hub in the basic class (regulation 3, 表 3-1),
    whose checkpoints are worth 2 and 4 points (7.4 表 7-3, 6.4 表 6-2); the built-in courses' `[score]` says
    applied, which is what an EV3 of no class gets."""
    env = environment(lane(), 120_000_000, BUILT_IN[robot], objective="etrobocon")
    cp1 = env.course.checkpoints[0]
    world = FakeWorld()
    world.xy, world.yaw = (cp1.x, cp1.y), math.radians(cp1.heading_deg)
    env.task.check(world, 10_000)
    score = env.score()
    assert score is not None and (score.competition_class, score.checkpoints) == (competition_class, 1)
    assert score.task_points == points


def test_a_robot_file_names_its_class_and_an_unknown_one_is_refused():
    assert parse_robot('class = "basic"\n', "r.toml").competition_class == "basic"
    assert parse_robot("", "r.toml").competition_class is None
    with pytest.raises(RobotError, match="r.toml: class must be one of basic, applied, got 'open'"):
        parse_robot('class = "open"\n', "r.toml")
