"""`hako course new` turns a team's mat image into a course folder; `hako course show` draws a course after the
bench's checks. Each bad input is one line."""

from __future__ import annotations

import struct
import zlib

import numpy as np
import pytest
from PIL import Image

from hakoniwa.physics.course import MAX_FLOOR_PIXELS, CourseError, load_course
from tests.helpers.commands import hako, one_line_error


@pytest.fixture
def mat(tmp_path):
    """A 546 x 364 px mat: a black line across a white floor."""
    img = np.full((364, 546, 3), 255, dtype=np.uint8)
    img[180:185, 50:500] = 0
    path = tmp_path / "mat.png"
    Image.fromarray(img).save(path)
    return path


def test_a_new_course_knows_its_scale_and_origin_and_shows(tmp_path, mat):
    out = tmp_path / "mycourse"
    r = hako("course", "new", "--image", str(mat), "--size", "5.46x3.64", "--out", str(out))
    assert r.returncode == 0, r.stderr
    course = load_course(out)
    assert course.meters_per_pixel == pytest.approx(0.01) and course.extent == pytest.approx((-2.73, 2.73, -1.82, 1.82))
    assert course.reading_at(0.0, 0.5).reflect == 23 and course.reading_at(0.0, 0.0).reflect == 0  # the line
    assert (out / "mat.png").is_file() and "EDIT" in (out / "course.toml").read_text()
    shown = hako("course", "show", str(out), "--png", str(tmp_path / "course.png"))
    assert shown.returncode == 0, shown.stderr
    assert "1 gate, 0 zones, 0 objects" in shown.stdout
    with Image.open(tmp_path / "course.png") as png:
        assert png.size[0] > 500


def test_show_draws_a_built_in_course(tmp_path):
    r = hako("course", "show", "etrobocon-l", "--png", str(tmp_path / "l.png"), "--robot", "hackspi")
    assert r.returncode == 0, r.stderr
    assert "etrobocon-l, 5.46 x 3.64 m, 4 gates, 2 zones, 1 object" in r.stdout


@pytest.mark.parametrize("size, words", [
    ("5.46x4", ["546 x 364 px (aspect 1.500)", "5.46 x 4 m is 1.365"]),
    ("5.46", ["--size '5.46'", "5.46x3.64"]),
    ("ax3", ["--size 'ax3'"]),
    ("0x3", ["between 0 and 100 m"]),
])
def test_an_image_and_a_size_that_disagree_are_one_line(tmp_path, mat, size, words):
    one_line_error(hako("course", "new", "--image", str(mat), "--size", size, "--out", str(tmp_path / "c")), *words)
    assert not (tmp_path / "c" / "course.toml").exists()


def test_an_unreadable_image_or_a_taken_folder_is_one_line(tmp_path, mat):
    bad = tmp_path / "bad.png"
    bad.write_text("not an image")
    one_line_error(hako("course", "new", "--image", str(bad), "--size", "1x1"), "not a readable image")
    out = tmp_path / "c"
    assert hako("course", "new", "--image", str(mat), "--size", "5.46x3.64", "--out", str(out)).returncode == 0
    one_line_error(hako("course", "new", "--image", str(mat), "--size", "5.46x3.64", "--out", str(out)),
                   "already holds a course.toml")


@pytest.mark.parametrize("edit, words", [
    (lambda t: t.replace("[start]                          # EDIT: the robot's axle centre [m] and heading [deg, "
                         "counter-clockwise from +x]\nx = 0.0", "[start]\nx = 3.5"),
     ["the start pose (3.500, 0.000) is off the floor image"]),
    (lambda t: t.replace('name = "gate1"                   # (under --objective etrobocon it is the LAP gate)\n'
                         "x = 0.5", 'name = "gate1"\nx = 3.0'),
     ["checkpoint 'gate1' at (3, 0) is outside the floor image"]),
    (lambda t: t + '[[wall]]\nname = "fence"\nx = 1.0\ny = 1.0\nhx = 0.1\nhy = 0.1\n[[object]]\nname = "bottle"\n'
                   'shape = "cylinder"\nradius = 0.03\nheight = 0.2\nmass = 0.3\nfriction = 0.3\ncolor = "black"\n'
                   "x = 1.0\ny = 1.05\n",
     ["object 'bottle' at (1, 1.05) stands inside wall 'fence'"]),
    (lambda t: t.replace("black = [50, 50, 50]", "black = 50"),
     ["[sensor.spike]: black must be three numbers 0..1024"]),
])
def test_show_refuses_a_course_no_test_could_run_on_in_one_line(tmp_path, mat, edit, words):
    out = tmp_path / "c"
    assert hako("course", "new", "--image", str(mat), "--size", "5.46x3.64", "--out", str(out)).returncode == 0
    toml = out / "course.toml"
    text = toml.read_text()
    assert edit(text) != text
    toml.write_text(edit(text))
    one_line_error(hako("course", "show", str(out), "--png", str(tmp_path / "c.png")), *words)
    assert not (tmp_path / "c.png").exists()


def png_header(path, width: int, height: int) -> None:
    """A PNG that says it is `width` x `height` (an RGB image) and holds almost nothing: opening it reads only
    the header, so the test costs no gigabytes."""
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(b"\0" * 16))
                     + chunk(b"IEND", b""))


@pytest.mark.parametrize("width, height", [(20000, 20000), (10000, 9000), (8000, 5001)])
def test_an_image_over_the_limit_is_one_line_saying_the_limit_and_no_pil_warning(tmp_path, mat, width, height):
    """20000 x 20000 gave PIL's DecompressionBombError as a traceback; over 89 Mpx PIL warned on every command."""
    big = tmp_path / "big.png"
    png_header(big, width, height)
    r = hako("course", "new", "--image", str(big), "--size", f"{width / 1000}x{height / 1000}")
    one_line_error(r, f"--image {big}: {width} x {height} px", f"limit of {MAX_FLOOR_PIXELS / 1e6:.0f} Mpx")
    assert "Warning" not in r.stderr
    course = tmp_path / "course"
    assert hako("course", "new", "--image", str(mat), "--size", "5.46x3.64", "--out", str(course)).returncode == 0
    (course / "big.png").write_bytes(big.read_bytes())
    toml = course / "course.toml"
    toml.write_text(toml.read_text().replace('floor_image = "mat.png"', 'floor_image = "big.png"'))
    with pytest.raises(CourseError, match=f"^big.png: {width} x {height} px .* limit of"):
        load_course(course)
