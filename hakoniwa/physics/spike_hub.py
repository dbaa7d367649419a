"""What SPIKE-RT on the hub answers, from what its devices measure: the one definition of the hub's meanings.

The physics process plays the hub: it turns the truth (a wheel's angle, the light a colour sensor gets back)
into the numbers SPIKE-RT's drivers return, and hands them on as the hub does. Today it writes them into the
mapped files for the native runtime, which only reads them, as libraspike-art only reads the hub's status;
a hub played over a pseudo-terminal (RasPike-ART's protocol) answers with these same functions. Keeping them
here, and not in the runtime's C, means the two paths cannot disagree. docs/DESIGN-NOTES.md ("The hub's
meanings") says why.

Sources, in ../shared/third_party/raspike-art (the commits its README names):
- spike-rt-hub/drivers/spike/pup/motor.c: `pup_motor_setup` hands the direction to pbio's servo, which applies
  it to the duty and to the count (angle = (raw - zero) * direction); `pup_motor_get_power` (116-124) reports
  the cached voltage as a duty rounded to 0..100, negated for a counter-clockwise motor.
- spike-rt-hub/drivers/spike/pup/colorsensor.c: RGB is the sensor's 10-bit RGB_I mode (120-132), reflection
  (r + g + b) * 100 / 3072 (232-242), hsv(surface = true) pbio's conversion of RGB >> 2 with SPIKE-RT's
  corrections (33-64), hsv(surface = false) and ambient the SHSV mode's data scaled (154-175, 244-255), and
  color() the detectable colour of least cost (66-118, the default set 19-26).
- pbio's `pbio_color_rgb_to_hsv` (pybricks-micropython lib/pbio/src/color/conversion.c, not in the folder):
  integer HSV of 8-bit RGB, v = 101 * max / 256.
"""

from __future__ import annotations

from collections import deque

PBIO_CLOCKWISE, PBIO_COUNTERCLOCKWISE = 0, 1  # pbio_direction_t, as pup_motor_setup takes it
RGB_FULL = 1024  # the top of the colour sensor's RGB_I channels (colorsensor.c 36-38 maps it to 255)
REFLECTION_SCALE = 3072  # colorsensor.c 241: (r + g + b) * 100 / 3072
DUTY_STEPS = 10  # pbio's duty is 0..1000; motor.c 119 rounds it to 0..100

# SPIKE-RT's detectable colours by default (colorsensor.c 19-26: cb_color_map_default), in its order: the
# first of two equal costs wins. PBIO_COLOR_HUE_RED .. _BLUE are 0, 60, 120, 240.
DEFAULT_COLORS: tuple[tuple[int, int, int], ...] = (
    (0, 100, 100), (60, 100, 100), (120, 100, 100), (240, 100, 100), (0, 0, 100), (0, 0, 0))

Rgb = tuple[int, int, int]
Hsv = tuple[int, int, int]


def direction_sign(direction: int) -> int:
    """The factor pbio applies to a motor's duty and count: -1 for PUP_DIRECTION_COUNTERCLOCKWISE."""
    return -1 if direction == PBIO_COUNTERCLOCKWISE else 1


def _c_div(a: int, b: int) -> int:
    """C's integer division, which truncates toward zero."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b > 0) else -q


def power_report(power: int, direction: int) -> int:
    """`pup_motor_get_power` on the hub of a motor driven at `power` (percent, the program's direction):
    the duty (pbio's 0..1000, the program's direction) rounded as motor.c 119 rounds it, then negated for a
    counter-clockwise motor (120-122). The battery's voltage-duty round trip is taken as exact."""
    duty = _c_div(power * DUTY_STEPS + 5, DUTY_STEPS)
    return -duty if direction == PBIO_COUNTERCLOCKWISE else duty


def reflection(rgb: Rgb) -> int:
    """`pup_color_sensor_reflection`: colorsensor.c 241, from the same RGB as `pup_color_sensor_rgb`."""
    return (rgb[0] + rgb[1] + rgb[2]) * 100 // REFLECTION_SCALE


def pbio_rgb_to_hsv(rgb8: Rgb) -> Hsv:
    """pbio's `pbio_color_rgb_to_hsv` of 8-bit RGB: integer hue (C's division), s = 100 chroma / max,
    v = 101 max / 256."""
    top, bottom = max(rgb8), min(rgb8)
    chroma = top - bottom
    h = s = 0
    if chroma > 0:
        r, g, b = rgb8
        a, c, base = (g, b, 0) if top == r else (b, r, 120) if top == g else (r, g, 240)
        h = _c_div(60 * (a - c), chroma) + base
        if h < 0:
            h += 360
        s = 100 * chroma // top
    return h, s, 101 * top // 256


def hsv(rgb: Rgb) -> Hsv:
    """`pup_color_sensor_hsv(surface = true)`: `cb_color_map_rgb_to_hsv` (colorsensor.c 33-64) of the RGB."""
    rgb8 = tuple(255 if c == RGB_FULL else c >> 2 for c in rgb)
    h, s, v = pbio_rgb_to_hsv((rgb8[0], rgb8[1], rgb8[2]))
    if v <= 3:  # 45-47: for very low values, saturation is not reliable
        s = 0
    if s <= 3:  # 50-52: nor hue
        h = 0
    if h < 40:  # 55-59: a shift of the low hues; offset is a uint8_t, so (h - 20) << 8 wraps below 20
        offset = _c_div((h - 20) * 256, 20) % 256
        h = h * (200 - ((100 * offset * offset) >> 16)) // 100
    return h, s * (200 - s) // 100, v * (200 - v) // 100  # 62-63: value and saturation corrected


def ambient_hsv(shsv: tuple[int, int, int]) -> Hsv:
    """`pup_color_sensor_hsv(surface = false)`: the SHSV mode's data, s and v scaled to percent and capped
    (colorsensor.c 165-173)."""
    return shsv[0], min(shsv[1] // 10, 100), min(shsv[2] // 10, 100)


def ambient(shsv: tuple[int, int, int]) -> int:
    """`pup_color_sensor_ambient`: the SHSV mode's v / 100 (colorsensor.c 254)."""
    return shsv[2] // 100


def hsv_cost(x: Hsv, c: Hsv) -> int:
    """`cb_get_hsv_cost` (colorsensor.c 66-91): the hue error (ignored against a grey), the saturation error
    with a penalty for a pale colour, and the value error, squared and weighted 1, 5, 2."""
    hue = 0
    if c[1] > 5 and x[1] > 5:
        hue = abs(c[0] - x[0])
        if hue > 180:
            hue = 360 - hue
    saturation = abs(x[1] - c[1]) + (100 - c[1]) // 2
    value = abs(x[2] - c[2])
    return hue * hue + 5 * saturation * saturation + 2 * value * value


def color(x: Hsv, colors: tuple[Hsv, ...] = DEFAULT_COLORS) -> Hsv:
    """`pup_color_sensor_color`: the detectable colour of least cost, the first of equals
    (`cb_color_map_get_color`, colorsensor.c 94-118)."""
    best, best_cost = colors[0], None
    for c in colors:
        cost = hsv_cost(x, c)
        if best_cost is None or cost < best_cost:
            best, best_cost = c, cost
    return best


# A SPIKE force sensor's full travel (spike-rt-hub drivers/spike/pup/forcesensor.c 40-51): raw readings map
# linearly to 0..10000 mN of force and 0..6670 um of distance, and the API divides each by 1000 as an integer
# (74-81), so the program sees whole newtons and whole millimetres.
FORCE_FULL_MN = 10000
FORCE_TRAVEL_UM = 6670


def force_report(force_n: int) -> tuple[float, float, bool]:
    """`pup_force_sensor_force`, `_distance` and `_touched` of a sensor pressed with `force_n` newtons (0:
    released): the force in whole newtons, the button's travel in whole millimetres for that force, touched
    once it moves at all (forcesensor.c 89-91: raw above the released reading)."""
    force_mn = min(max(force_n, 0) * 1000, FORCE_FULL_MN)
    return float(force_mn // 1000), float(FORCE_TRAVEL_UM * force_mn // FORCE_FULL_MN // 1000), force_mn > 0


# SPIKE-RT's hub buttons (drivers/include/spike/hub/button.h 51-54: pbio's PBIO_BUTTON_LEFT 1 << 4, CENTER
# 1 << 5, RIGHT 1 << 6, RIGHT_UP 1 << 9 as BT), each by the bit of the EV3 button a scenario holds it on
# (hakoniwa/physics/scenario.py SPIKE_BUTTONS: LEFT 0, RIGHT 1, ENTER 4 for CENTER, BACK 5 for BT).
HUB_BUTTON_BITS = ((0, 1 << 4), (1, 1 << 6), (4, 1 << 5), (5, 1 << 9))


def hub_buttons(ev3_bits: int) -> int:
    """`hub_button_is_pressed` of the buttons a scenario holds down, given as RX BUTTONS' EV3 bitmask."""
    return sum(hub for ev3, hub in HUB_BUTTON_BITS if ev3_bits >> ev3 & 1)


# pbio's measured speed and stall (Pybricks' control settings). The native runtime's motor.c computes them in C
# from its own samples; tests/athrill/test_spike_native.py checks its constants are these.
SPEED_WINDOW_US = 100_000  # PBIO_CONFIG_DIFFERENTIATOR_WINDOW_MS
STALL_SPEED_DPS = 20  # stall_speed_limit
STALL_TIME_US = 200_000  # stall_time


def speed_over(counts: deque[tuple[int, int]], window_us: int) -> int:
    """The count's change per second from the newest sample back to the newest one at least `window_us`
    older, or the oldest kept (motor.c's speed_over); 0 before two samples."""
    now, newest = counts[-1]
    then, oldest = counts[0]
    for t, c in reversed(counts):
        then, oldest = t, c
        if now - t >= window_us:
            break
    return 0 if now == then else int((newest - oldest) * 1_000_000 / (now - then))


def stalled(counts: deque[tuple[int, int]], driven_since_us: int | None, now_us: int) -> bool:
    """Driven (a power set) for STALL_TIME_US and slower than STALL_SPEED_DPS over them (motor.c's rule,
    Pybricks' stall tolerances)."""
    return (driven_since_us is not None and now_us - driven_since_us >= STALL_TIME_US
            and abs(speed_over(counts, STALL_TIME_US)) < STALL_SPEED_DPS)
