"""What SPIKE-RT on the hub answers (hakoniwa/physics/spike_hub.py), each expected value worked by hand from
the hub's sources in ../shared/third_party/raspike-art (the commits its README names):
- SPIKE-RT's spike-rt-hub/drivers/spike/pup/motor.c and colorsensor.c (file and line below);
- pbio's pbio_color_rgb_to_hsv (pybricks-micropython lib/pbio/src/color/conversion.c), which colorsensor.c 42
  calls: h = 60 (a - b) / chroma + c in C's integer division, s = 100 chroma / max, v = 101 max / 256.
None of these numbers was printed by the bench."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hakoniwa.physics import spike_hub as hub


def test_pbio_applies_the_direction_to_duty_and_count():
    # motor.c 57-59: pup_motor_setup hands positive_direction to pbio_servo_setup; pbio_direction_t's
    # PBIO_DIRECTION_CLOCKWISE is 0, COUNTERCLOCKWISE 1.
    assert hub.direction_sign(hub.PBIO_CLOCKWISE) == 1 and hub.direction_sign(hub.PBIO_COUNTERCLOCKWISE) == -1


@pytest.mark.parametrize("power, direction, report", [
    (50, hub.PBIO_CLOCKWISE, 50),  # (500 + 5) / 10 (motor.c 119)
    (50, hub.PBIO_COUNTERCLOCKWISE, -50),  # negated for a counter-clockwise motor (motor.c 120-122)
    (-50, hub.PBIO_CLOCKWISE, -49),  # (-500 + 5) / 10: C's division truncates toward zero
    (-50, hub.PBIO_COUNTERCLOCKWISE, 49),
    (0, hub.PBIO_COUNTERCLOCKWISE, 0),
    (100, hub.PBIO_CLOCKWISE, 100),
])
def test_get_power_is_the_duty_rounded_and_negated_for_counter_clockwise(power, direction, report):
    assert hub.power_report(power, direction) == report


@pytest.mark.parametrize("rgb, reflection", [
    ((1024, 1024, 1024), 100),  # 3072 * 100 / 3072 (colorsensor.c 241)
    ((415, 415, 415), 40),  # 124500 / 3072 = 40.5, truncated
    ((108, 108, 108), 10),  # 32400 / 3072 = 10.5
    ((1, 1, 0), 0),
    ((114, 156, 221), 15),  # 49100 / 3072 = 15.98
])
def test_reflection_is_the_sum_of_the_rgb_over_3072(rgb, reflection):
    assert hub.reflection(rgb) == reflection


@pytest.mark.parametrize("rgb8, hsv", [
    ((255, 0, 0), (0, 100, 100)),  # v = 101 * 255 / 256 = 100
    ((0, 0, 255), (240, 100, 100)),  # blue is max: a = r, b = g, c = 240
    ((28, 39, 55), (216, 49, 21)),  # h = 60 * (28 - 39) / 27 + 240 = -24 + 240; s = 2700 / 55; v = 5555 / 256
    ((0, 0, 0), (0, 0, 0)),  # chroma 0: h and s stay 0
])
def test_pbio_converts_8_bit_rgb_to_integer_hsv(rgb8, hsv):
    assert hub.pbio_rgb_to_hsv(rgb8) == hsv


@pytest.mark.parametrize("rgb, hsv", [
    # white at HackSPi's height: RGB >> 2 = 103 (36-38), pbio v = 10403 / 256 = 40, s 0 so h 0 (50-52); the low
    # hue shift keeps 0 (55-59: offset = (-20 << 8) / 20 = -256, 0 as a uint8_t, scale 200); v = 40 * 160 / 100
    ((415, 415, 415), (0, 0, 64)),
    ((1024, 1024, 1024), (0, 0, 100)),  # 1024 reads as 255 (36-38): v 100, 100 * 100 / 100
    ((8, 0, 0), (0, 0, 0)),  # RGB >> 2 = (2, 0, 0): v = 202 / 256 = 0 <= 3 zeroes s (45-47), then h (50-52)
    # h = 60 * 30 / 180 = 10 < 40 (55-59): offset = (-10 << 8) / 20 = -128, 128 as a uint8_t, scale =
    # 200 - (100 * 16384 >> 16) = 175, h = 10 * 175 / 100 = 17; s = 90 * 110 / 100 = 99; v = 78 * 122 / 100 = 95
    ((800, 200, 80), (17, 99, 95)),
    ((800, 440, 80), (52, 99, 95)),  # h = 30: offset (10 << 8) / 20 = 128, the same scale 175: h = 52
    # the blue of the team's measurement at HackSPi's height: pbio (216, 49, 21); s = 49 * 151 / 100 = 73,
    # v = 21 * 179 / 100 = 37 (62-63)
    ((114, 156, 221), (216, 73, 37)),
])
def test_hsv_is_spike_rts_conversion_with_its_corrections(rgb, hsv):
    assert hub.hsv(rgb) == hsv


@given(st.tuples(*[st.integers(0, 1024)] * 3))
def test_the_hsv_of_any_rgb_is_in_range(rgb):
    h, s, v = hub.hsv(rgb)
    assert 0 <= h < 360 and 0 <= s <= 100 and 0 <= v <= 100


def test_the_surface_off_hsv_and_ambient_are_the_shsv_mode_scaled():
    # colorsensor.c 165-173: h as read, s and v / 10 capped at 100; 254: ambient = v / 100
    assert hub.ambient_hsv((30, 1234, 560)) == (30, 100, 56)
    assert hub.ambient((30, 1234, 560)) == 5 and hub.ambient((0, 0, 99)) == 0


def test_spike_rts_cost_and_its_order_decide_the_colour():
    """cb_get_hsv_cost (colorsensor.c 66-91) and cb_color_map_get_color (94-118) with the default set (19-26)."""
    assert hub.hsv_cost((240, 100, 100), (240, 100, 100)) == 0
    assert hub.hsv_cost((200, 100, 100), (240, 100, 100)) == 40 * 40
    assert hub.hsv_cost((0, 0, 100), (0, 0, 100)) == 5 * 50 * 50  # the pale-colour penalty: (100 - 0) / 2
    assert hub.hsv_cost((120, 3, 80), (240, 100, 100)) == 5 * 97 * 97 + 2 * 20 * 20  # s <= 5: no hue error
    # white at HackSPi's height: white costs 12500 + 2 * 36 ** 2 = 15092, none 12500 + 2 * 64 ** 2 = 20692
    assert hub.color((0, 0, 64)) == (0, 0, 100) and hub.color((0, 0, 19)) == (0, 0, 0)
    # the team's blue: blue costs 24 ** 2 + 5 * 27 ** 2 + 2 * 63 ** 2 = 12159, green 96 ** 2 + .. = 20799
    assert hub.color((216, 73, 37)) == (240, 100, 100)
    assert hub.color((55, 90, 90)) == (60, 100, 100)
    assert hub.color((0, 0, 50), ((0, 0, 100), (0, 0, 0))) == (0, 0, 100)  # 12500 + 5000 against 12500 + 5000


def test_the_force_sensor_reads_whole_newtons_and_millimetres():
    # spike-rt-hub drivers/spike/pup/forcesensor.c 40-51, 74-81: 10000 mN and 6670 um at full travel, each
    # divided by 1000 as an integer; 89-91: touched once the button moves
    assert hub.force_report(10) == (10.0, 6.0, True)
    assert hub.force_report(5) == (5.0, 3.0, True)
    assert hub.force_report(0) == (0.0, 0.0, False)
    assert hub.force_report(25) == (10.0, 6.0, True)  # the sensor's range ends at 10 N


def test_the_hub_buttons_are_pbios_bits_of_the_ev3_buttons_a_scenario_holds():
    # button.h 51-54 (pbio's button.h: LEFT 1 << 4, CENTER 1 << 5, RIGHT 1 << 6, RIGHT_UP 1 << 9 as BT); the
    # scenario holds LEFT, RIGHT, CENTER, BT on the EV3 bits 0, 1, 4 (ENTER), 5 (BACK)
    assert hub.hub_buttons(0b000001) == 1 << 4
    assert hub.hub_buttons(0b000010) == 1 << 6
    assert hub.hub_buttons(0b010000) == 1 << 5
    assert hub.hub_buttons(0b100000) == 1 << 9
    assert hub.hub_buttons(0b001100) == 0  # UP and DOWN: no such buttons on the hub
