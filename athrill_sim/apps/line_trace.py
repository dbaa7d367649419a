"""The line tracer of the paper's Fig. 7, as its C source computes it.

Kp, Ki, Kd and the motor power are read through guest memory at 0x090F0000 + 540.. on every loop, as the
C code dereferences its pointers; the test controller writes them into unity_mmap.bin before the start.
The C variables are floats: every arithmetic result is rounded to float32 exactly where C rounds it (float
operations round each result; `integral * 0.01` is a double expression, rounded once on assignment), so
this program and `athrill_sim/apps/line_trace.c` compute bit for bit the same steering.
"""

from __future__ import annotations

import math
import struct

from athrill_sim.mock.ev3api import COLOR_SENSOR, EV3_PORT_1, EV3_PORT_A, EV3_PORT_B, LARGE_MOTOR, Ev3Api, rx
from hakoniwa.wire.protocol import Rx
from hakoniwa.wire.timebase import CONTROL_PERIOD_US

WHITE = 100
BLACK = 50
LEFT_MOTOR = EV3_PORT_A
RIGHT_MOTOR = EV3_PORT_B
COLOR_PORT = EV3_PORT_1

Kp = rx(Rx.KP)
Ki = rx(Rx.KI)
Kd = rx(Rx.KD)
MOTOR_POWER = rx(Rx.MOTOR_POWER)

_F32 = struct.Struct("<f")


INT_MIN = -(2**31)


def f32(x: float) -> float:
    """Round a double to the nearest float32, as a C float assignment or float operation does: a result
    beyond float32's range is ±inf (valid gains such as Kp = 3e38 overflow so), not an error."""
    try:
        return _F32.unpack(_F32.pack(x))[0]
    except OverflowError:  # struct refuses exactly what rounds to infinity
        return math.copysign(math.inf, x)


def c_int(x: float) -> int:
    """C's float-to-int conversion (truncation toward zero), as the C tracer compiles it on x86-64
    (cvttss2si): NaN, or a value outside int's range, gives INT_MIN."""
    if math.isnan(x) or not INT_MIN <= x < 2**31:
        return INT_MIN
    return int(x)


def motor_steer(api: Ev3Api, left: int, right: int, power: float, steer: float) -> None:
    """The sample's wrapper: the turn ratio is clamped first (EV3RT caps it at 100 anyway; in C a float beyond
    int's range would not convert) and both arguments are converted to int, truncating."""
    turn = 100 if steer > 100 else -100 if steer < -100 else c_int(steer)
    api.ev3_motor_steer(left, right, c_int(power), turn)


def main_task(api: Ev3Api) -> None:
    api.ev3_sensor_config(COLOR_PORT, COLOR_SENSOR)
    api.ev3_motor_config(LEFT_MOTOR, LARGE_MOTOR)
    api.ev3_motor_config(RIGHT_MOTOR, LARGE_MOTOR)
    read = api.bus.read_f32
    lasterror = 0.0
    integral = 0.0
    mid = f32((WHITE - BLACK) // 2 + BLACK)
    while True:
        error = f32(mid - api.ev3_color_sensor_get_reflect(COLOR_PORT))
        integral = f32(error + integral * 0.01)
        p = f32(read(Kp) * error)
        i = f32(read(Ki) * integral)
        d = f32(read(Kd) * f32(error - lasterror))
        steer = f32(f32(p + i) + d)
        motor_steer(api, LEFT_MOTOR, RIGHT_MOTOR, read(MOTOR_POWER), steer)
        lasterror = error
        api.tslp_tsk(CONTROL_PERIOD_US)  # tslp_tsk(100000): 100 ms
