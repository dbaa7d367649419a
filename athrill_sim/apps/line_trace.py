"""The line tracer of the paper's Fig. 7, as close to its C source as Python allows.

Kp, Ki, Kd and the motor power are read through guest memory at 0x090F0000 + 540.. on every loop, as the
C code dereferences its pointers; the test controller writes them into unity_mmap.bin before the start.
"""

from __future__ import annotations

from hakoniwa.protocol import UNITY_GUEST_BASE, Unity
from hakoniwa.timebase import CONTROL_PERIOD_US
from athrill_sim.ev3api import COLOR_SENSOR_PORT, EV3_PORT_B, EV3_PORT_C, Ev3Api

WHITE = 100
BLACK = 50
LEFT_MOTOR = EV3_PORT_C
RIGHT_MOTOR = EV3_PORT_B

Kp = UNITY_GUEST_BASE + Unity.KP
Ki = UNITY_GUEST_BASE + Unity.KI
Kd = UNITY_GUEST_BASE + Unity.KD
MOTOR_POWER = UNITY_GUEST_BASE + Unity.MOTOR_POWER


def motor_steer(api: Ev3Api, left: int, right: int, power: float, steer: float) -> None:
    """The sample's wrapper: C converts the float arguments to int (truncating) and the wrapper clamps the
    turn ratio, which ev3_motor_steer would otherwise refuse."""
    api.ev3_motor_steer(left, right, int(power), max(-100, min(100, int(steer))))


def main_task(api: Ev3Api) -> None:
    read = api.bus.read_f32
    lasterror = 0.0
    integral = 0.0
    mid = (WHITE - BLACK) / 2 + BLACK
    while True:
        error = mid - api.ev3_color_sensor_get_reflect(COLOR_SENSOR_PORT)
        integral = error + integral * 0.01
        steer = read(Kp) * error + read(Ki) * integral + read(Kd) * (error - lasterror)
        motor_steer(api, LEFT_MOTOR, RIGHT_MOTOR, read(MOTOR_POWER), steer)
        lasterror = error
        api.tslp_tsk(CONTROL_PERIOD_US)  # tslp_tsk(100000): 100 ms
