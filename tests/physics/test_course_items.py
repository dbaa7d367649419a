"""Objects, zones, the score table and sensor calibrations in course files: what they hold, and a one-line
error for each bad one."""

from __future__ import annotations

import shutil

import pytest

from hakoniwa.physics.course import COURSES_DIR, CourseError, load_course
from tests.helpers.commands import hako

BOTTLE = ('[[object]]\nname = "bottle"\nshape = "cylinder"\nradius = 0.0325\nheight = 0.205\nmass = 0.3\n'
          'friction = 0.3\ncolor = [40, 40, 40]\nx = 1.2\ny = 0.5\n')
RING = '[[zone]]\nname = "ring"\nx = 1.2\ny = 0.5\nradius = 0.2\n'


def oval_with(tmp_path, extra: str):
    """The oval with `extra`: tables at the end, a top-level key at the top (where no table holds it)."""
    folder = tmp_path / "c"
    shutil.copytree(COURSES_DIR / "oval", folder)
    toml = folder / "course.toml"
    text = toml.read_text()
    toml.write_text(text + "\n" + extra if extra.startswith("[") else extra + text)
    return folder


def test_objects_zones_and_the_score_table_load(tmp_path):
    box = ('[[object]]\nname = "block"\nshape = "box"\nlength = 0.1\nwidth = 0.05\nheight = 0.04\nmass = 0.1\n'
           'friction = 0.5\ncolor = "blue"\nx = -1.2\ny = 0.5\nyaw_deg = 30\n')
    garage = '[[zone]]\nname = "garage"\nx = -1.0\ny = -0.7\nhx = 0.1\nhy = 0.1\n'
    course = load_course(oval_with(tmp_path, BOTTLE + box + RING + garage
                                   + '[score]\nclass = "basic"\ngarage = "garage"\nsumo_ring = "ring"\n'
                                     'sumo_bottle = "bottle"\n'))
    bottle, block = course.objects
    assert (bottle.shape, bottle.size, bottle.rgb) == ("cylinder", (0.0325, 0.0325, 0.205), (40, 40, 40))
    assert (block.size, block.rgb, block.yaw_deg) == ((0.1, 0.05, 0.04), (0, 0, 255), 30.0)
    ring, garage_zone = course.zones
    assert ring.contains(1.2, 0.69) and not ring.contains(1.2, 0.71) and garage_zone.contains(-0.91, -0.61)
    assert course.score.competition_class == "basic" and course.score.sumo_bottle == "bottle"


@pytest.mark.parametrize("extra, message", [
    (BOTTLE.replace('"cylinder"', '"sphere"'), r"object 1: 'shape' must be one of cylinder, box, got 'sphere'"),
    (BOTTLE.replace("radius = 0.0325", "radius = -1"), r"object 1: 'radius' must be positive"),
    (BOTTLE.replace("mass = 0.3", 'mass = "heavy"'), r"object 1: 'mass' must be a number"),
    (BOTTLE.replace("mass = 0.3\n", ""), r"object 1: missing 'mass'"),
    (BOTTLE.replace("friction = 0.3", "friction = -0.1"), r"'friction' must not be negative"),
    (BOTTLE.replace("[40, 40, 40]", '"plaid"'), r"'color' must be \[r, g, b\]"),
    (BOTTLE.replace("[40, 40, 40]", "[40, 300, 40]"), r"'color' must be \[r, g, b\]"),
    (BOTTLE.replace("height = 0.205", "height = 0.205\nwidth = 1"), r"unknown key 'width'"),
    (BOTTLE.replace('"bottle"', '"my bottle"'), r"'name' must be a word"),
    (BOTTLE + BOTTLE, r"two zones or objects named 'bottle'"),
    (BOTTLE.replace("x = 1.2", "x = 1.49"), r"object 'bottle' at \(1.49, 0.5\) stands off the floor image"),
    (BOTTLE.replace("x = 1.2\ny = 0.5", "x = 0.0\ny = 0.0"), r"object 'bottle' at \(0, 0\) stands inside wall "
                                                              r"'island'"),
    (BOTTLE.replace("x = 1.2\ny = 0.5", "x = 1.46\ny = 0.0"), r"stands inside wall 'east'"),
    (RING.replace("radius = 0.2", "radius = 0.2\nhx = 0.1"), r"a circle \(radius\) or a box \(hx, hy\), not both"),
    (RING.replace("y = 0.5", "y = 0.8"), r"zone 'ring' reaches off the floor image"),
    (RING.replace("radius = 0.2", "hx = 0.1"), r"zone 1: missing 'hy'"),
    ("zone = 3\n", r"'zone' must be an array of tables"),
    ('[score]\ngarage = "nowhere"\n', r"\[score\]: 'garage' names no zone of the course: 'nowhere'"),
    (BOTTLE + '[score]\nsumo_ring = "bottle"\n', r"'sumo_ring' names no zone"),
    ('[score]\nclass = "expert"\n', r"'class' must be one of basic, applied, got 'expert'"),
    ('[score]\nlane = "L"\n', r"\[score\]: unknown key 'lane'"),
    ("[sensor.ev3]\nreflect_white = 23\nreflect_black = 0\n", r"the EV3's reflect is given twice"),
    ("[sensor.spike]\nwhite = [50, 50, 50]\nblack = [1000, 1000, 1000]\n", r"\[sensor.spike\]: white must read above"),
    ("[sensor.spike]\nwhite = [1000, 1000, 1100]\nblack = [50, 50, 50]\n", r"three numbers 0..1024"),
    ("[sensor.spike]\nwhite = [1000, 1000, 1000]\nblack = [50, 50, 50]\nblue = 2\n", r"blue must be three numbers"),
    ("[sensor.spike]\nwhite = [1000, 1000, 1000]\nblack = [50, 50, 50]\ngain = 2\n", r"unknown key 'gain'"),
    ("[sensor.nxt]\nreflect_white = 40\nreflect_black = 10\n", r"\[sensor.nxt\]: no such sensor kind"),
    ("[sensor.spike]\nwhite = [1000, 1000, 1000]\n", r"\[sensor.spike\]: missing 'black'"),
    ('[[checkpoint]]\nname = "gate"\nx = 1.2\ny = 0\nhx = 0.1\nhy = 0.1\nheading_deg = "north"\n',
     r"checkpoint 4: 'heading_deg' must be a number"),
])
def test_bad_items_are_one_line_errors(tmp_path, extra, message):
    with pytest.raises(CourseError, match=message) as e:
        load_course(oval_with(tmp_path, extra))
    assert "\n" not in str(e.value)


def test_hako_try_says_a_bad_object_in_one_line(tmp_path):
    folder = oval_with(tmp_path, BOTTLE.replace("x = 1.2\ny = 0.5", "x = 0.0\ny = 0.0"))
    r = hako("try", "--course", str(folder), "--noise", "0", "--time-limit", "1")
    assert r.returncode != 0 and "Traceback" not in r.stderr
    assert r.stderr.strip().count("\n") == 0 and "stands inside wall 'island'" in r.stderr

