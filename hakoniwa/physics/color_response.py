"""How each kind of colour sensor turns the colour under it into what it reads.

The floor (or an object under the sensor) is measured as channels in the EV3 sensor's reflect units (the
course's `[sensor.ev3]` white and black): the red channel, which an EV3 sensor's reflect mode reads (it lights
the floor with its red LED), and, where the floor has colour, green, blue and their mean. On a grey floor the
channels are one number, so a grey course keeps a single channel and reads exactly what it always read. The
seeded noise shifts every channel by the same amount: it models the room's light and the sensor's height,
which brighten or darken all colours alike.

- EV3: reflect is the red channel; raw RGB each channel's place between the course's black and white, 0..255;
  the colour id the classification below.
- SPIKE: the sensor lights the floor white and reads 10-bit RGB. The course says what a SPIKE sensor reads on
  its white and black, channel by channel (`[sensor.spike]`, `SpikeFloor`), and each channel reads its place
  between the two; the robot says how its own sensor responds (`Robot.reflection`: its reflection on the
  course's white and black, which depends on how high it sits), a gain and an offset on every channel. What the
  hub makes of that RGB (reflection, HSV, the colour) is `spike_hub.py`'s.

The EV3's colour id: EV3RT hands on the id the sensor computes (ev3api_sensor.c reads the COL-COLOR mode over
UART), and LEGO's rule is not published. A grey keeps the bench's rule (the darkest third BLACK, the lightest
WHITE, the line's edge between them no colour, as a real sensor half over a line often says); a colour is the
nearest of EV3RT's hues by the cost SPIKE-RT uses (Pybricks' `pbio_get_hsv_cost`), and a dark one is BLACK.
docs/DESIGN-NOTES.md ("Colour floors") says why.
"""

from __future__ import annotations

import colorsys
import functools
from dataclasses import dataclass

from hakoniwa.physics import spike_hub
from hakoniwa.physics.spike_hub import REFLECTION_SCALE, RGB_FULL, Hsv, Rgb, hsv_cost
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


@dataclass(frozen=True)
class Calibration:
    """What a sensor reads on the course's white and black: an EV3's reflect (`[sensor.ev3]`), or a SPIKE
    robot's reflection (`Robot.reflection`)."""

    white: float
    black: float


# The SPIKE colour sensor on HackSPi: the official sample's calibration (RasPike-ART sample_c5_spike,
# LineTracer/LineTracer.h: WHITE_BRIGHTNESS 40, BLACK_BRIGHTNESS 10).
SPIKE_DEFAULT = Calibration(white=40, black=10)

Channels = tuple[float, float, float]


@dataclass(frozen=True)
class SpikeFloor:
    """What a SPIKE colour sensor reads on the course's white and black, channel by channel (10-bit, at the
    height of the sensor that measured them), and on each other colour the course uses, by name."""

    white: Channels
    black: Channels
    colours: tuple[tuple[str, Channels], ...] = ()


# A course that gives no `[sensor.spike]`: one team's published measurement (docs/DESIGN-NOTES.md, "The ET
# Robocon-style course"): white about 1000 on every channel, black about 50.
SPIKE_FLOOR = SpikeFloor(white=(1000.0, 1000.0, 1000.0), black=(50.0, 50.0, 50.0))


@dataclass(frozen=True)
class ColorReading:
    """An EV3 colour sensor's reading of one spot: reflect, colour id and raw RGB."""

    reflect: int
    color: ColorId
    rgb: tuple[int, int, int]


@dataclass(frozen=True)
class SpikeReading:
    """What SPIKE-RT on the hub answers for a SPIKE colour sensor over one spot (`spike_hub.py`)."""

    rgb: Rgb  # pup_color_sensor_rgb, 0..1024
    reflection: int
    hsv: Hsv  # pup_color_sensor_hsv(surface = true)
    color: Hsv  # pup_color_sensor_color: the detectable colour, as SPIKE-RT returns it


def fraction(channel: float, ev3: Calibration) -> float:
    """A channel's place between the course's black (0) and white (1), unclamped."""
    return (channel - ev3.black) / (ev3.white - ev3.black)


def fractions(red: float, colour: tuple[float, float, float] | None, ev3: Calibration) -> Channels:
    """Each of red, green and blue's place between the course's black and white: `colour` is (green, blue,
    mean), None on a grey."""
    g, b = (red, red) if colour is None else colour[:2]
    return fraction(red, ev3), fraction(g, ev3), fraction(b, ev3)


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


@functools.cache
def _response(floor: SpikeFloor, robot: Calibration) -> tuple[float, float]:
    """The gain and offset that turn the course's channels into what the robot's sensor reads: its
    reflection on the course's white and black falls in the middle of the robot's figures' steps (so white
    reads `robot.white` and black `robot.black`, after the hub's truncating division, with room either side)."""
    white, black = ((figure + 0.5) * REFLECTION_SCALE / 100 for figure in (robot.white, robot.black))
    gain = (white - black) / (sum(floor.white) - sum(floor.black))
    return gain, (black - gain * sum(floor.black)) / 3


def spike_rgb(place: Channels, floor: SpikeFloor, robot: Calibration) -> Rgb:
    """The 10-bit RGB a SPIKE sensor reads where each channel is at `place` between the course's black and
    white (`fractions`)."""
    gain, offset = _response(floor, robot)
    rgb = tuple(min(max(round(gain * (b + (w - b) * f) + offset), 0), RGB_FULL)
                for f, w, b in zip(place, floor.white, floor.black))
    return rgb[0], rgb[1], rgb[2]


def spike_reading(place: Channels, floor: SpikeFloor, robot: Calibration) -> SpikeReading:
    """What the hub answers for the sensor over that spot: its RGB, and SPIKE-RT's meanings of it."""
    rgb = spike_rgb(place, floor, robot)
    hsv = spike_hub.hsv(rgb)
    return SpikeReading(rgb, spike_hub.reflection(rgb), hsv, spike_hub.color(hsv))
