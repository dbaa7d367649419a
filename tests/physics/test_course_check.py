"""A course the robot cannot run is refused before any test, in one line naming the course file: a start in or
touching a wall, off the floor image, or checkpoints it cannot reach. Likewise a scenario whose stimuli come
after the time limit."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from hakoniwa.physics.course import COURSES_DIR, CourseError, load_course
from hakoniwa.physics.course_check import check_course
from hakoniwa.physics.robot import EV3_BODY, HACKSPI_BODY
from hakoniwa.physics.scenario import ScenarioError
from testctl.bench_options import BenchOptions, load_bench
from tests.helpers.commands import one_line_error

START = "[start]                        # the robot's axle centre; its color sensor sits on the line's outer edge\n" \
        "x = -0.38\ny = -0.52\nyaw_deg = 0\n"
# The EV3 body's right wheel (a sphere of 5 cm, 6.5 cm right of the axle) reaches 11.5 cm right of the axle;
# the south wall's top edge is at y = -0.85.
SOUTH_TOUCH_Y = -0.85 + 0.065 + 0.05


def course_with(tmp_path: Path, edit) -> Path:
    folder = tmp_path / "mycourse"
    shutil.copytree(COURSES_DIR / "oval", folder)
    toml = folder / "course.toml"
    text = toml.read_text()
    assert START in text
    toml.write_text(edit(text))
    return folder


def start_at(x: float, y: float, yaw: float = 0):
    return lambda t: t.replace(START, f"[start]\nx = {x}\ny = {y}\nyaw_deg = {yaw}\n")


def checkpoint_2_at(x: float, y: float, hx: float = 0.1, hy: float = 0.3):
    old = '[[checkpoint]]\nname = "cp2-north"\nx = 0.0\ny = 0.5\nhx = 0.1\nhy = 0.3\n'
    return lambda t: t.replace(old, f'[[checkpoint]]\nname = "cp2-north"\nx = {x}\ny = {y}\nhx = {hx}\nhy = {hy}\n')


def check(folder: Path, body=EV3_BODY) -> None:
    check_course(load_course(folder), body, folder / "course.toml")


@pytest.mark.parametrize("body", [EV3_BODY, HACKSPI_BODY])
def test_the_oval_passes_for_both_bodies(body):
    check_course(load_course("oval"), body, COURSES_DIR / "oval" / "course.toml")


@pytest.mark.parametrize("edit, words", [
    (start_at(0.0, 0.0), ["inside or touching wall 'island'", "HIT_WALL at 0.00 m"]),
    (start_at(-0.38, SOUTH_TOUCH_Y), ["touching wall 'south'"]),  # the wheel just touches it
    (start_at(-0.38, SOUTH_TOUCH_Y + 0.0005), ["touching wall 'south'"]),  # within the contact margin
    (start_at(-0.38, -0.82, 90), ["touching wall 'south'"]),  # turned: the chassis's back reaches the wall
    (start_at(-1.6, -0.52), ["the start pose (-1.600, -0.520) is off the floor image"]),
    (start_at(1.39, 0.0, 0), ["touching wall 'east'"]),  # the chassis's front
    (checkpoint_2_at(0.0, 0.0, 0.05, 0.05), ["checkpoint 2 ('cp2-north') cannot be reached", "inside a wall"]),
    (checkpoint_2_at(1.485, 0.0, 0.005, 0.05), ["checkpoint 2 ('cp2-north') cannot be reached"]),  # beyond the wall
    (checkpoint_2_at(2.0, 0.0), ["checkpoint 'cp2-north' at (2, 0) is outside the floor image"]),
])
def test_a_course_the_robot_cannot_run_is_one_line_naming_the_file(tmp_path, edit, words):
    folder = course_with(tmp_path, edit)
    with pytest.raises(CourseError) as e:
        check(folder)
    message = str(e.value)
    assert message.startswith(f"{folder / 'course.toml'}: ") and "\n" not in message
    for w in words:
        assert w in message


def test_a_colour_sensor_off_the_floor_image_is_refused(tmp_path):
    west = '[[wall]]\nname = "west"\nx = -1.47\ny = 0.0\nhx = 0.02\nhy = 0.85\n'
    folder = course_with(tmp_path, lambda t: start_at(-1.45, 0.0, 180)(t.replace(west, "")))
    with pytest.raises(CourseError, match=r"the colour sensor at the start \(-1.530, 0.000\) is off the floor image"):
        check(folder)


def test_a_start_clear_of_the_wall_passes(tmp_path):
    check(course_with(tmp_path, start_at(-0.38, SOUTH_TOUCH_Y + 0.01)))


def test_a_gap_narrower_than_the_robot_walls_the_checkpoints_off(tmp_path):
    """Walls from the island towards the outer walls, east of the start, leaving gaps of 16 cm: narrower than
    the EV3 robot's 23 cm (and than the check's leniency of one grid square), wider than HackSPi's 17.6 cm
    less that square."""
    def wall(name: str, x: float, y: float, hy: float) -> str:
        return f'\n[[wall]]\nname = "{name}"\nx = {x}\ny = {y}\nhx = 0.02\nhy = {hy}\n'

    gaps = wall("gate-n", 0.5, 0.47, 0.22) + wall("gate-s", 0.5, -0.47, 0.22)  # y 0.69..0.85 and -0.85..-0.69 free
    folder = course_with(tmp_path, lambda t: t.replace("[[checkpoint]]", gaps.lstrip() + "\n[[checkpoint]]", 1))
    with pytest.raises(CourseError, match=r"checkpoint 1 \('cp1-east'\) cannot be reached.*\(230 mm\)"):
        check(folder)
    check(folder, HACKSPI_BODY)


def test_hako_try_refuses_the_course_before_any_test(tmp_path):
    folder = course_with(tmp_path, start_at(0.0, 0.0))
    run_dir = tmp_path / "run"
    r = subprocess.run([sys.executable, "-m", "testctl.hako", "try", "--course", str(folder), "--run-dir",
                        str(run_dir)], capture_output=True, text=True, timeout=120)
    one_line_error(r, str(folder / "course.toml"), "wall 'island'")
    assert not (run_dir / "unity_mmap.bin").exists()  # no bench was started


@pytest.mark.parametrize("table", ['[[press]]\nbutton = "ENTER"\nat_s = 60\n',
                                   '[[press]]\nsensor = "touch"\nport = 3\nat_s = 75.5\n',
                                   '[[serial]]\ntext = "go"\nat_s = 61\n'])
def test_a_stimulus_after_the_time_limit_is_refused(tmp_path, table):
    scenario = tmp_path / "late.toml"
    scenario.write_text(table)
    with pytest.raises(ScenarioError, match=r"late.toml (press|serial) 1: at_s = [\d.]+ is not before the time "
                                            r"limit \(60 s\): no test would get there"):
        load_bench(BenchOptions(scenario=str(scenario)))
    load_bench(BenchOptions(scenario=str(scenario), time_limit_s=90))  # a longer test gets there
