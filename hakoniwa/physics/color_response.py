"""How each kind of colour sensor turns the colour under it into what it reads.

The floor (or an object under the sensor) is measured as channels in the EV3 sensor's reflect units (the
course's `[sensor.ev3]` white and black): the red channel, which an EV3 sensor's reflect mode reads (it lights
the floor with its red LED), and, where the floor has colour, green, blue and their mean, which a SPIKE
sensor's reflection reads (it lights the floor white; SPIKE-RT's `pup_color_sensor_reflection` is the mean of
its raw r, g and b). On a grey floor the four are one number, so a grey course keeps a single channel and
reads exactly what it always read. The seeded noise shifts every channel by the same amount: it models the
room's light and the sensor's height, which brighten or darken all colours alike.

- EV3: reflect is the red channel; raw RGB each channel's place between the course's black and white, 0..255;
  the colour id the classification below.
- SPIKE: reflection is the mean channel mapped from the EV3's scale onto the SPIKE sensor's (the course's
  `[sensor.spike]` white and black); RGB as the EV3's, HSV of that RGB. Its colour is SPIKE-RT's
  classification of that HSV (`spike_color`), which the program's own runtime makes, as on the robot.

The EV3's colour id: EV3RT hands on the id the sensor computes (ev3api_sensor.c reads the COL-COLOR mode over
UART), and LEGO's rule is not published. A grey keeps the bench's rule (the darkest third BLACK, the lightest
WHITE, the line's edge between them no colour, as a real sensor half over a line often says); a colour is the
nearest of EV3RT's hues by the cost SPIKE-RT uses (Pybricks' `pbio_get_hsv_cost`), and a dark one is BLACK.
docs/DESIGN-NOTES.md ("Colour floors") says why.
"""

from __future__ import annotations

import colorsys
from dataclasses import dataclass

from hakoniwa.wire.protocol import ColorId

# The grey rule: the darkest third of the way from black to white is BLACK, the lightest third WHITE.
BLACK_BELOW = 1 / 3
WHITE_ABOVE = 2 / 3
GREY_SATURATION = 0.25  # a colour at most this saturated (HSV s, 0..1) is a grey to the EV3's rule
RGB_WHITE = 255  # what each raw RGB channel reads on the course's white (the bench's calibration)
# The EV3 colour sensor's RGB-RAW full scale: 0..1020 on every channel (LEGO's mode table, as ev3dev's sensor
# page lists it); EV3RT hands the 16 bits on untouched (uart_dri.c, uart_dri_get_data_color).
RGB_RAW_MAX = 1020
# Raw RGB of each colour id (0..255): what a painted `[[area]]` of that colour reads.
COLOR_RGB = {ColorId.BLACK: (0, 0, 0), ColorId.BLUE: (0, 0, 255), ColorId.GREEN: (0, 160, 0),
             ColorId.YELLOW: (255, 220, 0), ColorId.RED: (220, 0, 0), ColorId.WHITE: (255, 255, 255),
             ColorId.BROWN: (130, 80, 30)}
# The hues an EV3 names (h degrees, s and v percent): pbio/color.h's PBIO_COLOR_HUE_*, and Pybricks' brown.
EV3_HUES: tuple[tuple[ColorId, tuple[int, int, int]], ...] = (
    (ColorId.RED, (0, 100, 100)), (ColorId.YELLOW, (60, 100, 100)), (ColorId.GREEN, (120, 100, 100)),
    (ColorId.BLUE, (240, 100, 100)), (ColorId.BROWN, (30, 100, 50)))
# SPIKE-RT's detectable colours by default (drivers/spike/pup/colorsensor.c, cb_color_map_default), in its
# order (the first of two equal costs wins), with the colour id each stands for.
SPIKE_COLORS: tuple[tuple[ColorId, tuple[int, int, int]], ...] = (
    (ColorId.RED, (0, 100, 100)), (ColorId.YELLOW, (60, 100, 100)), (ColorId.GREEN, (120, 100, 100)),
    (ColorId.BLUE, (240, 100, 100)), (ColorId.WHITE, (0, 0, 100)), (ColorId.NONE, (0, 0, 0)))


@dataclass(frozen=True)
class Calibration:
    """What one kind of sensor reads on the course's white and black (`[sensor.ev3]`, `[sensor.spike]`)."""

    white: float
    black: float


# The SPIKE colour sensor on ET Robocon's course: the official sample's calibration (RasPike-ART sample_c5_spike,
# LineTracer/LineTracer.h: WHITE_BRIGHTNESS 40, BLACK_BRIGHTNESS 10), for a course that gives none.
SPIKE_DEFAULT = Calibration(white=40, black=10)


@dataclass(frozen=True)
class ColorReading:
    """A colour sensor's reading of one spot: reflect in its own kind's scale, the EV3's colour id and raw RGB,
    and (a SPIKE sensor's) HSV."""

    reflect: int
    color: ColorId
    rgb: tuple[int, int, int]
    hsv: tuple[int, int, int] | None = None


def fraction(channel: float, ev3: Calibration) -> float:
    """A channel's place between the course's black (0) and white (1), unclamped."""
    return (channel - ev3.black) / (ev3.white - ev3.black)


def raw_rgb(red: float, colour: tuple[float, float, float] | None, ev3: Calibration) -> tuple[int, int, int]:
    """The raw RGB of the channels: `colour` is (green, blue, mean), None on a grey. The course's white reads
    RGB_WHITE; a brighter spot (the room's light, in the noise) reads more, as on the sensor, up to the sensor's
    full scale RGB_RAW_MAX, not the course's white."""
    channels = (red,) if colour is None else (red, colour[0], colour[1])
    values = tuple(round(min(max(fraction(c, ev3), 0.0) * RGB_WHITE, RGB_RAW_MAX)) for c in channels)
    return (values[0],) * 3 if colour is None else (values[0], values[1], values[2])


def ev3_color(red: float, colour: tuple[float, float, float] | None, ev3: Calibration) -> ColorId:
    """The EV3's colour id of the channels (the module's rule)."""
    if colour is None:
        return _grey(fraction(red, ev3))
    fr, fg, fb = (min(max(fraction(c, ev3), 0.0), 1.0) for c in (red, colour[0], colour[1]))
    h, s, v = colorsys.rgb_to_hsv(fr, fg, fb)
    if s <= GREY_SATURATION:
        return _grey(v)
    if v < BLACK_BELOW:
        return ColorId.BLACK
    x = (round(h * 360) % 360, round(s * 100), round(v * 100))
    return min(EV3_HUES, key=lambda named: hsv_cost(x, named[1]))[0]


def _grey(f: float) -> ColorId:
    return ColorId.BLACK if f < BLACK_BELOW else ColorId.WHITE if f > WHITE_ABOVE else ColorId.NONE


def spike_reflect(channel: float, ev3: Calibration, spike: Calibration) -> int:
    """What a SPIKE colour sensor reads where the EV3-scale channel is `channel`: the course's black and white
    mapped onto the SPIKE sensor's."""
    f = fraction(channel, ev3)
    return min(max(round(spike.black + (spike.white - spike.black) * f), 0), 100)


def hsv_of(rgb: tuple[int, int, int]) -> tuple[int, int, int]:
    """HSV as SPIKE-RT's `pbio_color_hsv_t` holds it (h 0..359 degrees, s and v 0..100 percent), of the raw
    RGB (0..255) the same snapshot reports, so that `pup_color_sensor_hsv` and `pup_color_sensor_rgb` agree."""
    h, s, v = colorsys.rgb_to_hsv(*(c / 255 for c in rgb))
    return round(h * 360) % 360, round(s * 100), round(v * 100)


def hsv_cost(x: tuple[int, int, int], c: tuple[int, int, int]) -> int:
    """SPIKE-RT's `cb_get_hsv_cost` (Pybricks' `pbio_get_hsv_cost`): the hue error (ignored against a grey),
    the saturation error with a penalty for a pale colour, and the value error, squared and weighted 1, 5, 2."""
    hue = 0
    if c[1] > 5 and x[1] > 5:
        hue = abs(c[0] - x[0])
        if hue > 180:
            hue = 360 - hue
    saturation = abs(x[1] - c[1]) + (100 - c[1]) // 2
    value = abs(x[2] - c[2])
    return hue * hue + 5 * saturation * saturation + 2 * value * value


def spike_color(hsv: tuple[int, int, int]) -> ColorId:
    """What SPIKE-RT's `pup_color_sensor_color` answers for this HSV with its default detectable colours, as a
    colour id (its colourless {0, 0, 0}, which black reads as, is NONE)."""
    best, best_cost = SPIKE_COLORS[0][0], None
    for color, c in SPIKE_COLORS:
        cost = hsv_cost(hsv, c)
        if best_cost is None or cost < best_cost:
            best, best_cost = color, cost
    return best
