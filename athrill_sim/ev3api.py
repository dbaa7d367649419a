"""EV3RT's C API over the guest memory bus, so that a robot program reads like its C original.

Names, signatures, units and error codes follow EV3RT as it runs on the real Athrill (its ev3api and the
athrill drivers): a sensor must be configured on its port before use (else E_OBJ and a 0 reading, with a
warning in the log), a motor likewise; the colour sensor's values are the low byte of their slot, the gyro's
and the ultrasonic sensor's the low 16 bits, the ultrasonic slot holds millimetres and the API returns
centimetres; `ev3_motor_reset_counts` raises a flag that the physics side clears once it has zeroed the
encoder; `tslp_tsk` takes microseconds (ASP3's RELTIM). Every read goes through guest memory, as the C code
does, so the mock and the native runtime see exactly the same bytes.
"""

from __future__ import annotations

import sys

from athrill_sim.bus import MemoryBus
from athrill_sim.kernel import Kernel
from hakoniwa.wire.protocol import MOTOR_PORTS, RESET_ANGLE_PORTS, RX_GUEST_BASE, TX_GUEST_BASE, Rx, Tx

# TOPPERS error codes.
E_OK = 0
E_TMOUT = -50
TMO_FEVR = -1
E_PAR = -17
E_ID = -18
E_OBJ = -41

EV3_PORT_A, EV3_PORT_B, EV3_PORT_C, EV3_PORT_D = range(4)
EV3_PORT_1, EV3_PORT_2, EV3_PORT_3, EV3_PORT_4 = range(4)
SENSOR_PORTS = 4

# sensor_type_t and motor_type_t
NONE_SENSOR, ULTRASONIC_SENSOR, GYRO_SENSOR, TOUCH_SENSOR, COLOR_SENSOR = range(5)
NONE_MOTOR, MEDIUM_MOTOR, LARGE_MOTOR, UNREGULATED_MOTOR = range(4)

# ledcolor_t: bits of the TX LED word
LED_OFF, LED_RED, LED_GREEN, LED_ORANGE = 0, 1, 2, 3

# button_t: bits of the RX buttons word
LEFT_BUTTON, RIGHT_BUTTON, UP_BUTTON, DOWN_BUTTON, ENTER_BUTTON, BACK_BUTTON = range(6)

TOUCH_THRESHOLD = 2048  # ADC_RES / 2


def c_div(a: int, b: int) -> int:
    """C's integer division, which truncates toward zero (Python's // floors)."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b > 0) else -q


def rx(offset: int) -> int:
    return RX_GUEST_BASE + offset


def tx(offset: int) -> int:
    return TX_GUEST_BASE + offset


class Ev3Api:
    def __init__(self, bus: MemoryBus, kernel: Kernel) -> None:
        self.bus = bus
        self.kernel = kernel
        self._sensors = [NONE_SENSOR] * SENSOR_PORTS
        self._motors = [NONE_MOTOR] * MOTOR_PORTS

    def syslog(self, message: str) -> None:
        """EV3RT's syslog: a line in the run's athrill.log, stamped with the simulation time."""
        print(f"[{self.kernel.now_us / 1e6:10.3f} s] {message}", file=sys.stderr, flush=True)

    # -- kernel --------------------------------------------------------------------------------------
    def tslp_tsk(self, timeout_us: int) -> int:
        """Sleep; the task is woken by the timeout (E_TMOUT), as in TOPPERS. TMO_FEVR sleeps for good: this
        mock's one task has nobody to wake it."""
        if timeout_us == TMO_FEVR:
            self.kernel.sleep_forever()
        self.kernel.sleep(int(timeout_us))
        return E_TMOUT

    def dly_tsk(self, delay_us: int) -> int:
        self.kernel.sleep(int(delay_us))
        return E_OK

    def get_tim(self) -> int:
        """SYSTIM in microseconds since the test started."""
        return self.kernel.now_us

    # -- configuration -------------------------------------------------------------------------------
    def ev3_sensor_config(self, port: int, sensor_type: int) -> int:
        if not 0 <= port < SENSOR_PORTS:
            return E_ID
        self._sensors[port] = sensor_type
        return E_OK

    def ev3_sensor_get_type(self, port: int) -> int:
        return self._sensors[port] if 0 <= port < SENSOR_PORTS else E_ID

    def ev3_motor_config(self, port: int, motor_type: int) -> int:
        if not 0 <= port < MOTOR_PORTS:
            return E_ID
        if not NONE_MOTOR <= motor_type <= UNREGULATED_MOTOR:
            return E_PAR
        self._motors[port] = motor_type
        self.bus.write("i", tx(Tx.MOTOR_BRAKE + 4 * port), 0)  # configured idle, as EV3RT does
        return E_OK

    def ev3_motor_get_type(self, port: int) -> int:
        return self._motors[port] if 0 <= port < MOTOR_PORTS else E_ID

    # -- sensors -------------------------------------------------------------------------------------
    def _sensor(self, port: int, kind: int, fmt: str, offset: int, name: str) -> int:
        if not 0 <= port < SENSOR_PORTS:
            self.syslog(f"{name}(): ercd {E_ID}")
            return 0
        if self._sensors[port] != kind:
            self.syslog(f"{name}(): ercd {E_OBJ}")
            return 0
        return int(self.bus.read(fmt, rx(offset)))

    def ev3_color_sensor_get_reflect(self, port: int) -> int:
        return self._sensor(port, COLOR_SENSOR, "B", Rx.COLOR0_REFLECT, "ev3_color_sensor_get_reflect")

    def ev3_color_sensor_get_ambient(self, port: int) -> int:
        return self._sensor(port, COLOR_SENSOR, "B", Rx.COLOR0_AMBIENT, "ev3_color_sensor_get_ambient")

    def ev3_color_sensor_get_color(self, port: int) -> int:
        return self._sensor(port, COLOR_SENSOR, "B", Rx.COLOR0_COLOR, "ev3_color_sensor_get_color")

    def ev3_color_sensor_get_rgb_raw(self, port: int) -> tuple[int, int, int]:
        name = "ev3_color_sensor_get_rgb_raw"
        return tuple(self._sensor(port, COLOR_SENSOR, "H", Rx.COLOR0_RGB + 4 * i, name) for i in range(3))

    def ev3_gyro_sensor_get_angle(self, port: int) -> int:
        return self._sensor(port, GYRO_SENSOR, "h", Rx.GYRO_ANGLE, "ev3_gyro_sensor_get_angle")

    def ev3_gyro_sensor_get_rate(self, port: int) -> int:
        return self._sensor(port, GYRO_SENSOR, "h", Rx.GYRO_RATE, "ev3_gyro_sensor_get_rate")

    def ev3_gyro_sensor_reset(self, port: int) -> int:
        if not 0 <= port < SENSOR_PORTS:
            return E_ID
        if self._sensors[port] != GYRO_SENSOR:
            return E_OBJ
        self.bus.write("i", tx(Tx.GYRO_RESET), 1)
        return E_OK

    def ev3_ultrasonic_sensor_get_distance(self, port: int) -> int:
        mm = self._sensor(port, ULTRASONIC_SENSOR, "h", Rx.ULTRASONIC_MM, "ev3_ultrasonic_sensor_get_distance")
        return c_div(mm, 10)

    def ev3_touch_sensor_is_pressed(self, port: int) -> bool:
        """EV3RT numbers touch sensors in port order: the first configured one reads slot 0, the next slot 1."""
        earlier = sum(t == TOUCH_SENSOR for t in self._sensors[:max(port, 0)])
        slot = Rx.TOUCH0 if earlier == 0 else Rx.TOUCH1
        return self._sensor(port, TOUCH_SENSOR, "h", slot, "ev3_touch_sensor_is_pressed") > TOUCH_THRESHOLD

    def ev3_button_is_pressed(self, button: int) -> bool:
        if not LEFT_BUTTON <= button <= BACK_BUTTON:
            return False
        return bool(int(self.bus.read("I", rx(Rx.BUTTONS))) >> button & 1)

    # -- motors --------------------------------------------------------------------------------------
    def _motor_error(self, port: int) -> int:
        if not 0 <= port < MOTOR_PORTS:
            return E_ID
        return E_OBJ if self._motors[port] == NONE_MOTOR else E_OK

    def ev3_motor_get_counts(self, port: int) -> int:
        if err := self._motor_error(port):
            self.syslog(f"ev3_motor_get_counts(): Failed to get motor counts, ercd: {err}")
            return 0
        return int(self.bus.read("i", rx(Rx.MOTOR_ANGLE + 4 * port)))

    def ev3_motor_reset_counts(self, port: int) -> int:
        if err := self._motor_error(port):
            return err
        if port < RESET_ANGLE_PORTS:
            self.bus.write("i", tx(Tx.MOTOR_RESET_ANGLE + 4 * port), 1)
        return E_OK

    def ev3_motor_set_power(self, port: int, power: int) -> int:
        if err := self._motor_error(port):
            return err
        power = int(power)
        if not -100 <= power <= 100:
            used = 100 if power > 0 else -100
            self.syslog(f"ev3_motor_set_power(): power {power} is out-of-range, {used} is used instead.")
            power = used
        self.bus.write("i", tx(Tx.MOTOR_POWER + 4 * port), power)
        return E_OK

    def ev3_motor_get_power(self, port: int) -> int:
        if err := self._motor_error(port):
            self.syslog(f"ev3_motor_get_power(): Failed to get motor power, ercd: {err}")
            return 0
        return int(self.bus.read("i", tx(Tx.MOTOR_POWER + 4 * port)))

    def ev3_motor_stop(self, port: int, brake: bool) -> int:
        if err := self._motor_error(port):
            return err
        self.bus.write("i", tx(Tx.MOTOR_POWER + 4 * port), 0)
        self.bus.write("i", tx(Tx.MOTOR_BRAKE + 4 * port), int(bool(brake)))
        return E_OK

    def ev3_motor_steer(self, left_motor: int, right_motor: int, power: int, turn_ratio: int) -> int:
        """EV3RT's steer (ev3api_motor.c): |turn| and |power| capped at 100, the inner wheel slowed to
        |p|·(100−|t|)/100 in C integer arithmetic, so it stops at ±100 and never runs backwards; a positive
        turn slows the right wheel."""
        if err := self._motor_error(left_motor) or self._motor_error(right_motor):
            return err
        abs_turn, abs_power = min(abs(turn_ratio), 100), min(abs(power), 100)
        inner = abs_power * (100 - abs_turn) // 100
        left, right = (abs_power, inner) if turn_ratio > 0 else (inner, abs_power)
        if power < 0:
            left, right = -left, -right
        self.ev3_motor_set_power(left_motor, left)
        self.ev3_motor_set_power(right_motor, right)
        return E_OK

    def ev3_motor_rotate(self, port: int, degrees: int, speed_abs: int, blocking: bool) -> int:
        """EV3RT for Athrill does not support it: E_OK, and the motor is left alone (ev3api_motor.c)."""
        return E_OK

    # -- LED -----------------------------------------------------------------------------------------
    def ev3_led_set_color(self, color: int) -> int:
        if color not in (LED_OFF, LED_RED, LED_GREEN, LED_ORANGE):
            return E_PAR
        self.bus.write("i", tx(Tx.LED), color)
        return E_OK
