"""Colour floors: each kind of sensor's response to a colour, calibrated per course, the EV3's and SPIKE-RT's
classification of what is measured, and a grey course reading exactly what it always read."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from PIL import Image

from hakoniwa.physics import color_response as cr
from hakoniwa.physics.color_response import Calibration, hsv_cost, spike_color
from hakoniwa.physics.course import COURSES_DIR, load_course
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
    f = (reflect - 50) / 50
    assert cr.spike_reflect(reflect, OVAL_EV3, cr.SPIKE_DEFAULT) == min(max(round(10 + 30 * f), 0), 100)


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


def test_each_kind_reads_a_colour_floor_in_its_own_scale(tmp_path):
    course = colour_course(tmp_path, stripes((255, 255, 255), (0, 0, 0), (0, 70, 170), (220, 30, 30)),
                           "\n[sensor.spike]\nreflect_white = 44\nreflect_black = 8\n")
    centres = [-1.5 + (i + 0.5) * 0.75 for i in range(4)]
    ev3 = [course.reading_at(x, 0.0) for x in centres]
    spike = [course.reading_at(x, 0.0, spike=True) for x in centres]
    assert [r.color for r in ev3] == [ColorId.WHITE, ColorId.BLACK, ColorId.BLUE, ColorId.RED]
    # The EV3 lights the floor red: blue reads as dark as black, red as light as white.
    assert [r.reflect for r in ev3] == [23, 0, 0, round(23 * 220 / 255)]
    # The SPIKE lights it white: the mean of the channels, on its own white 44 and black 8.
    assert [r.reflect for r in spike] == [44, 8, round(8 + 36 * 80 / 255), round(8 + 36 * 280 / 3 / 255)]
    assert [r.rgb for r in ev3] == [(255, 255, 255), (0, 0, 0), (0, 70, 170), (220, 30, 30)]
    assert spike[2].hsv == (215, 100, 67) and [spike_color(r.hsv) for r in spike] == \
        [ColorId.WHITE, ColorId.NONE, ColorId.BLUE, ColorId.RED]


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


def test_spike_rts_cost_and_its_order_decide_the_spike_colour():
    """cb_get_hsv_cost, worked by hand: pure hues are themselves, a grey is white or none by its value,
    and the hue is ignored against an unsaturated colour."""
    assert hsv_cost((240, 100, 100), (240, 100, 100)) == 0
    assert hsv_cost((200, 100, 100), (240, 100, 100)) == 40 * 40
    assert hsv_cost((0, 0, 100), (0, 0, 100)) == 5 * 50 * 50  # the pale-colour penalty: (100 - 0) / 2
    assert hsv_cost((120, 3, 80), (240, 100, 100)) == 5 * 97 * 97 + 2 * 20 * 20  # s <= 5: no hue error
    assert spike_color((0, 0, 70)) == ColorId.WHITE and spike_color((0, 0, 20)) == ColorId.NONE
    assert spike_color((55, 90, 90)) == ColorId.YELLOW and spike_color((215, 100, 67)) == ColorId.BLUE


def test_noise_shifts_every_channel_alike(tmp_path):
    course = colour_course(tmp_path, stripes((0, 70, 170)))
    env = environment(course, course.time_limit_us, BUILT_IN["hackspi"])
    env.begin(NoiseDraw(course.noise, 3, 5.0))
    truth = env.world.measure()
    s = env.read_sensors()
    shift = env.sensors.noise.reflect_offset + env.sensors.noise._reflect_flicker
    g, b, mean = (min(max(c + shift, 0.0), 100.0) for c in truth.colour)
    assert s.reflect == cr.spike_reflect(mean, course.ev3, course.spike)
    assert s.rgb == cr.raw_rgb(min(max(truth.reflect + shift, 0), 100), (g, b, mean), course.ev3)
