"""The built-in ET Robocon-style courses: both lanes as scripts/make_etrobocon_course.py draws them, at the
mat's size, with their calibration, gates, zones and bottle, mirror images of each other."""

from __future__ import annotations

import pytest

from hakoniwa.physics.course import load_course
from hakoniwa.wire.protocol import ColorId


def test_the_etrobocon_lanes_are_mirror_images_and_pass_the_course_check():
    from hakoniwa.physics.course_check import check_course
    from hakoniwa.physics.robot import EV3_BODY, HACKSPI_BODY

    left, right = load_course("etrobocon-l"), load_course("etrobocon-r")
    assert (left.reflect_white, left.reflect_black) == (23, 0) and left.spike == right.spike
    # one team's published measurement of the real mat (docs/DESIGN-NOTES.md, "The ET Robocon-style course")
    assert (left.spike.white, left.spike.black) == ((1000, 1000, 1000), (50, 50, 50))
    assert dict(left.spike.colours)["blue"] == (70, 200, 400) and dict(left.spike.colours)["red"] == (800, 300, 350)
    for a, b in zip(left.checkpoints, right.checkpoints):
        assert (a.x, a.y, a.hx, a.hy) == pytest.approx((-b.x, b.y, b.hx, b.hy))
    for a, b in zip(left.zones, right.zones):
        assert (a.x, a.y) == pytest.approx((-b.x, b.y))
    assert left.extent == pytest.approx((-2.73, 2.73, -1.82, 1.82))  # ET Robocon's mat, 5.46 x 3.64 m
    for course in (left, right):
        for body in (EV3_BODY, HACKSPI_BODY):
            check_course(course, body, course.folder / "course.toml")


def test_the_lanes_have_blue_sections_a_yellow_ring_red_gates_and_a_bottle_to_read():
    course = load_course("etrobocon-l")
    reads = [course.reading_at(x, y) for x, y in ((-1.1, 1.15), (-0.45, 0.0), (-0.8, 0.25), (-0.3, -0.5))]
    assert [r.color for r in reads] == [ColorId.BLUE, ColorId.BLACK, ColorId.BLUE, ColorId.WHITE]
    ring = course.zone("ring")
    assert course.reading_at(ring.x - ring.radius, ring.y).color == ColorId.YELLOW
    cp1 = course.checkpoints[0]
    assert course.reading_at(cp1.x + 0.1, cp1.y).color == ColorId.RED  # a gate line, short of the black line
    assert course.reading_at(cp1.x + 0.03, cp1.y).color == ColorId.WHITE
    bottle = course.objects[0]
    assert (bottle.name, bottle.shape, (bottle.x, bottle.y)) == ("bottle", "cylinder", (ring.x, ring.y))
    assert course.score.garage == "garage" and course.time_limit_us == 120_000_000


def test_the_script_draws_the_shipped_image(tmp_path):
    import subprocess
    import sys

    import numpy as np
    from PIL import Image

    from tests.helpers.paths import REPO

    r = subprocess.run([sys.executable, str(REPO / "scripts" / "make_etrobocon_course.py"), "--out", str(tmp_path)],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    shipped = load_course("etrobocon-l").folder
    assert np.array_equal(np.asarray(Image.open(tmp_path / "etrobocon-l" / "floor.png")),
                          np.asarray(Image.open(shipped / "floor.png")))
    for lane in ("etrobocon-l", "etrobocon-r"):
        assert (tmp_path / lane / "course.toml").read_text() == (shipped.parent / lane / "course.toml").read_text()
