"""Colour floors: each kind of sensor's response to a colour, calibrated per course (and a SPIKE sensor's per
robot), the EV3's classification of what is measured, and a grey course reading exactly what it always read
to an EV3. What the hub makes of a SPIKE sensor's RGB is tests/physics/test_spike_hub.py's."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from PIL import Image

from hakoniwa.physics import color_response as cr
from hakoniwa.physics import spike_hub
from hakoniwa.physics.color_response import SPIKE_DEFAULT, Calibration
from hakoniwa.physics.course import COURSES_DIR, CourseError, load_course
from hakoniwa.physics.noise import NoiseDraw
from hakoniwa.physics.robots import BUILT_IN, DEFAULT_ROBOT
from hakoniwa.wire.protocol import ColorId
from tests.helpers.environments import environment

OVAL_EV3 = Calibration(100, 50)


def old_grey_reading(reflect: float, ev3: Calibration) -> tuple[ColorId, tuple[int, int, int]]:
    """The colour id and raw RGB the bench derived from a grey reflect before colour floors: the rule a grey
    course must keep, written out here as it was."""
    f = (reflect - ev3.black) / (ev3.white - ev3.black)
    grey = round(min(max(f, 0.0), 1.0) * 255)
    return (ColorId.BLACK if f < 1 / 3 else ColorId.WHITE if f > 2 / 3 else ColorId.NONE), (grey, grey, grey)


@given(st.floats(0, 100, allow_nan=False))
def test_a_grey_reads_as_it_always_did(reflect):
    assert (cr.ev3_color(reflect, None, OVAL_EV3), cr.raw_rgb(reflect, None, OVAL_EV3)) == \
        old_grey_reading(reflect, OVAL_EV3)
    r, g, b = cr.spike_rgb(cr.fractions(reflect, None, OVAL_EV3), cr.SPIKE_FLOOR, SPIKE_DEFAULT)
    assert r == g == b  # a grey reads grey to a SPIKE sensor too


def test_the_oval_is_a_grey_course_and_its_readings_are_unchanged():
    oval = load_course("oval")
    assert oval.colour is None
    env = environment(oval, oval.time_limit_us, DEFAULT_ROBOT)
    env.begin(NoiseDraw(oval.noise, 7, 1.0))
    for t in range(1, 40):
        env.drive([30, 32, 0, 0])
        env.advance_to(t * 50_000)
        s, truth = env.read_sensors(), env.world.measure()
        assert truth.colour is None
        # The colour id and RGB come from the same noisy reflect the program reads, by the grey rule.
        noise = env.sensors.noise
        noisy = min(max(truth.reflect + noise.reflect_offset + noise._reflect_flicker, 0.0), 100.0)
        assert (s.reflect, s.color, s.rgb) == (round(noisy), *old_grey_reading(noisy, oval.ev3))


def colour_course(tmp_path, pixels: np.ndarray, extra: str = ""):
    folder = tmp_path / "colour"
    shutil.copytree(COURSES_DIR / "oval", folder)
    Image.fromarray(pixels.astype(np.uint8), "RGB").save(folder / "floor.png")
    toml = folder / "course.toml"
    text = toml.read_text().replace("reflect_white = 100\nreflect_black = 50\n", "")
    toml.write_text(text + "\n[sensor.ev3]\nreflect_white = 23\nreflect_black = 0\n" + extra)
    return load_course(folder)


def stripes(*colours) -> np.ndarray:
    """The oval's 1500 x 900 image in vertical stripes of the given colours, left to right."""
    img = np.zeros((900, 1500, 3))
    for i, c in enumerate(colours):
        img[:, i * 1500 // len(colours):(i + 1) * 1500 // len(colours)] = c
    return img


# The course's [sensor.spike] as the built-in ET Robocon-style courses give it: one team's measurement
# (docs/DESIGN-NOTES.md, "The ET Robocon-style course"), and the image colours that read it (each channel's
# place between black and white).
MEASURED = "\n[sensor.spike]\nwhite = [1000, 1000, 1000]\nblack = [50, 50, 50]\nblue = [70, 200, 400]\n" \
    "red = [800, 300, 350]\n"
BLUE_PIXEL, RED_PIXEL = (5, 40, 94), (201, 67, 81)  # round(255 * (c - 50) / 950)


def test_each_kind_reads_a_colour_floor_in_its_own_scale(tmp_path):
    course = colour_course(tmp_path, stripes((255, 255, 255), (0, 0, 0), BLUE_PIXEL, RED_PIXEL), MEASURED)
    centres = [-1.5 + (i + 0.5) * 0.75 for i in range(4)]
    ev3 = [course.reading_at(x, 0.0) for x in centres]
    assert [r.color for r in ev3] == [ColorId.WHITE, ColorId.BLACK, ColorId.BLUE, ColorId.RED]
    # The EV3 lights the floor red: blue reads as dark as black, red as light as white.
    assert [r.reflect for r in ev3] == [23, 0, round(23 * 5 / 255), round(23 * 201 / 255)]
    assert [r.rgb for r in ev3] == [(255, 255, 255), (0, 0, 0), BLUE_PIXEL, RED_PIXEL]
    # The SPIKE lights it white and reads 10-bit RGB. HackSPi's sensor reads the reflection ET Robocon's
    # sample_c5_spike is tuned for (LineTracer.h: WHITE_BRIGHTNESS 40, BLACK_BRIGHTNESS 10); one that sits
    # lower, as the Basic class's robot's, reads more (80 and 10).
    for robot, white, black in ((SPIKE_DEFAULT, 40, 10), (Calibration(80, 10), 80, 10)):
        spike = [course.spike_reading(x, 0.0, course.reflect_at(x, 0.0), course.colour_at(x, 0.0), robot)
                 for x in centres]
        assert [r.reflection for r in spike[:2]] == [white, black]
        assert [r.reflection for r in spike] == [spike_hub.reflection(r.rgb) for r in spike]
        # Each channel keeps the course's colour's place between its black and white (to the image's step).
        measured = dict(course.spike.colours)
        for reading, name in ((spike[2], "blue"), (spike[3], "red")):
            for c in range(3):
                place = (reading.rgb[c] - spike[1].rgb[c]) / (spike[0].rgb[c] - spike[1].rgb[c])
                assert place == pytest.approx((measured[name][c] - 50) / 950, abs=0.01), (name, c)
        assert [r.color for r in spike] == [(0, 0, 100), (0, 0, 0), (240, 100, 100), (0, 100, 100)]
        assert [r.hsv == spike_hub.hsv(r.rgb) for r in spike] == [True] * 4


@pytest.mark.parametrize("table, error", [
    ("white = [1000, 1000]\nblack = [50, 50, 50]", r"\[sensor.spike\]: white must be three numbers 0..1024"),
    ("white = [1000, 1000, 1000]\nblack = [50, 50, 50]\nblue = 70", r"blue must be three numbers"),
    ("white = [1000, 1000, 2000]\nblack = [50, 50, 50]", r"white must be three numbers 0..1024"),
    ("white = [1000, 1000, 1000]", r"\[sensor.spike\]: missing 'black'"),
    ("white = [1000, 40, 1000]\nblack = [50, 50, 50]", r"white must read above black on every channel"),
])
def test_a_spike_colour_table_that_is_not_three_numbers_is_one_error(tmp_path, table, error):
    with pytest.raises(CourseError, match=error):
        colour_course(tmp_path, stripes((255, 255, 255)), "\n[sensor.spike]\n" + table + "\n")


def test_grey_pixels_of_a_colour_image_read_as_a_grey_course_reads_them(tmp_path):
    grey = np.repeat(np.linspace(0, 255, 1500)[None, :, None], 900, axis=0).repeat(3, axis=2).round()
    grey[:50] = (0, 0, 255)  # one blue band makes it a colour image
    course = colour_course(tmp_path, grey)
    assert course.colour is not None
    for x in np.linspace(-1.4, 1.4, 23):
        red = course.reflect_at(x, 0.0)
        g, b, mean = course.colour_at(x, 0.0)
        assert red == pytest.approx(g, abs=1e-5) == pytest.approx(b, abs=1e-5) == pytest.approx(mean, abs=1e-5)
        assert course.color_at(x, 0.0, red, (g, b, mean)) == old_grey_reading(red, course.ev3)


@pytest.mark.parametrize("rgb, ev3", [
    ((0, 70, 170), ColorId.BLUE), ((220, 30, 30), ColorId.RED), ((250, 215, 40), ColorId.YELLOW),
    ((30, 160, 60), ColorId.GREEN), ((130, 80, 30), ColorId.BROWN), ((0, 0, 60), ColorId.BLACK),
    ((200, 190, 200), ColorId.WHITE), ((120, 128, 125), ColorId.NONE)])
def test_the_ev3_names_the_measured_colour(rgb, ev3):
    channels = [23 * c / 255 for c in rgb]
    colour = (channels[1], channels[2], sum(channels) / 3)
    assert cr.ev3_color(channels[0], colour, Calibration(23, 0)) == ev3


def test_noise_shifts_every_channel_alike(tmp_path):
    course = colour_course(tmp_path, stripes((0, 70, 170)))
    env = environment(course, course.time_limit_us, BUILT_IN["hackspi"])
    env.begin(NoiseDraw(course.noise, 3, 5.0))
    truth = env.world.measure()
    s = env.read_sensors()
    shift = env.sensors.noise.reflect_offset + env.sensors.noise._reflect_flicker
    g, b, mean = (min(max(c + shift, 0.0), 100.0) for c in truth.colour)
    red = min(max(truth.reflect + shift, 0), 100)
    seen = course.spike_reading(*truth.sensor_xy, red, (g, b, mean), SPIKE_DEFAULT)
    assert (s.rgb, s.reflect, s.spike.hsv) == (seen.rgb, seen.reflection, seen.hsv)
