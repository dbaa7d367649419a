"""`hako course`: a team's own mat as a course folder, and a course drawn for a person to check.

`hako course new --image mat.png --size 5.46x3.64` writes a folder with the image and a course.toml that
knows its scale and origin, with a start pose, one gate and the sensor calibration to edit; `hako course show
COURSE --png course.png` draws a course (built-in or a folder) with its gates, zones, objects and start,
after the checks a bench makes before any test (a start off the mat, a gate outside it, an object in a wall:
one line each). Nothing heavy is imported until a command runs.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import click

from hakoniwa.conventions import HELP, OneLineErrorsGroup, writable_file
from hakoniwa.wire.errors import HakoError

ASPECT_TOLERANCE = 0.01  # an image and a size whose shapes differ by more than 1% are not one mat


class MatError(HakoError, ValueError):
    """The image or the size given for a new course is unusable; the message says why."""


@click.group(cls=OneLineErrorsGroup, context_settings=HELP)
def course() -> None:
    """A team's own mat as a course (new), and any course drawn to check it (show)."""


def parse_size(text: str) -> tuple[float, float]:
    """`5.46x3.64` in metres: width (x) by height (y)."""
    parts = text.lower().replace("×", "x").split("x")
    try:
        width, height = (float(p) for p in parts)
    except ValueError:
        raise MatError(f"--size {text!r}: give the mat's width and height in metres, as 5.46x3.64") from None
    if not (0 < width < 100 and 0 < height < 100):
        raise MatError(f"--size {text!r}: a mat's sides are between 0 and 100 m")
    return width, height


@course.command(context_settings=HELP)
@click.option("--image", "image", type=click.Path(dir_okay=False, path_type=Path), required=True,
              help="The mat's picture, seen from above, its edges the mat's (a PNG or JPEG).")
@click.option("--size", "size", required=True, help="The mat's width x height in metres, e.g. 5.46x3.64.")
@click.option("--out", "out", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="The course folder to write [default: the image's name, in this folder].")
def new(image: Path, size: str, out: Path | None) -> None:
    """Write a course folder for a mat: the image, and a course.toml with its scale and origin (the mat's
    centre at (0, 0)), a start pose, one gate and the sensors' calibration to edit."""
    width_m, height_m = parse_size(size)
    from hakoniwa.physics.course import open_floor_image

    with open_floor_image(image, f"--image {image}") as img:
        width_px, height_px = img.size
    image_aspect, mat_aspect = width_px / height_px, width_m / height_m
    if abs(image_aspect / mat_aspect - 1) > ASPECT_TOLERANCE:
        raise MatError(f"--image {image} is {width_px} x {height_px} px (aspect {image_aspect:.3f}) but --size "
                       f"{width_m:g} x {height_m:g} m is {mat_aspect:.3f}: crop the image to the mat, or give the "
                       "mat's size")
    folder = out or Path(image.stem)
    if (folder / "course.toml").exists():
        raise MatError(f"{folder} already holds a course.toml; choose another --out")
    folder.mkdir(parents=True, exist_ok=True)
    writable_file(folder / "course.toml", "--out")
    if (folder / image.name).resolve() != image.resolve():
        shutil.copyfile(image, folder / image.name)
    (folder / "course.toml").write_text(course_toml(folder.name, image.name, width_m / width_px, width_m, height_m))
    click.echo(f"wrote {folder / 'course.toml'} ({width_m:g} x {height_m:g} m, {width_m / width_px * 1000:.2f} mm a "
               f"pixel): edit its start, gates and calibration, then look at it with hako course show {folder} "
               "--png course.png")


def course_toml(name: str, image: str, mpp: float, width_m: float, height_m: float) -> str:
    """A new mat's course file: the facts the image gives, and placeholders a person edits."""
    return f"""# A course for the mat in {image}, written by `hako course new`: its scale and origin are the
# image's. Edit the start, the gates and the calibration, then check it: hako course show . --png course.png
name = "{name}"
floor_image = "{image}"
meters_per_pixel = {mpp!r}
origin = [{-width_m / 2!r}, {-height_m / 2!r}]  # the image's bottom-left corner: the mat's centre is (0, 0)
time_limit_s = 120               # ET Robocon's maximum measuring time (regulation 5.4.7)

[sensor.ev3]                     # what an EV3 colour sensor reads on this mat's white and black: measure it
reflect_white = 23               # (these are ET Robocon's simulator's, for HackEV)
reflect_black = 0

[sensor.spike]                   # a SPIKE colour sensor's 10-bit r, g, b on white, black and each colour
white = [1000, 1000, 1000]       # (these are one team's published measurement of ET Robocon's mat)
black = [50, 50, 50]

[start]                          # EDIT: the robot's axle centre [m] and heading [deg, counter-clockwise from +x]
x = 0.0
y = 0.0
yaw_deg = 0

[[checkpoint]]                   # EDIT: the gates, in the order the robot passes them; the last ends a lap
name = "gate1"                   # (under --objective etrobocon it is the LAP gate)
x = 0.5
y = 0.0
hx = 0.04
hy = 0.25

# Zones and objects, if the mat has them (docs/DESIGN-NOTES.md, "Course and robot"):
# [[zone]]  name, x, y and radius (a ring) or hx, hy (a box, such as the garage)
# [[object]]  name, shape ("cylinder": radius; "box": length, width), height, mass, friction, color, x, y
# [score]  class ("basic" or "applied"), garage, sumo_ring, sumo_bottle: what --objective etrobocon scores
# [course_out]  margin_m: how far past the mat's edge the axle may go before the run ends COURSE_OUT (default 0);
#   [[course_out.area]]  name, x, y, hx, hy: a box on the mat that is out of bounds too
"""


@course.command(context_settings=HELP)
@click.argument("course_name", metavar="COURSE")
@click.option("--png", "png", type=click.Path(dir_okay=False, path_type=Path), required=True,
              help="Where to draw it.")
@click.option("--robot", default=None, help="The robot the checks place on it [default: the default robot].")
def show(course_name: str, png: Path, robot: str | None) -> None:
    """Draw COURSE (a built-in name or a course folder) with its gates, zones, objects and start, after the
    checks a bench makes before any test."""
    from hakoniwa.physics.course import course_file, load_course
    from hakoniwa.physics.course_check import check_course
    from hakoniwa.physics.robots import load_robot
    from hakoniwa.pictures.plot import draw_course

    writable_file(png, "--png")
    loaded = load_course(course_name)
    check_course(loaded, load_robot(robot).body, course_file(course_name))
    draw_course(loaded, png)
    xmin, xmax, ymin, ymax = loaded.extent
    counts = ", ".join(f"{len(items)} {word}{'' if len(items) == 1 else 's'}" for word, items in
                       (("gate", loaded.checkpoints), ("zone", loaded.zones), ("object", loaded.objects)))
    click.echo(f"wrote {png}: {loaded.name}, {xmax - xmin:g} x {ymax - ymin:g} m, {counts}")
