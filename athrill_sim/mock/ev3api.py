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

from athrill_sim.mock.bus import MemoryBus
from athrill_sim.mock.ev3brick import BrickApi
from athrill_sim.mock.ev3fs import FsApi
from athrill_sim.mock.ev3lcd import LcdApi
from athrill_sim.mock.ev3serial import SerialApi
from athrill_sim.mock.ev3types import *  # noqa: F403  programs take EV3RT's names from here, as from ev3api.h
from athrill_sim.mock.ev3types import (
    BACK_BUTTON,
    COLOR_SENSOR,
    E_ID,
    E_OBJ,
    E_OK,
    E_PAR,
    E_TMOUT,
    GYRO_SENSOR,
    LED_GREEN,
    LED_RED,
    LEFT_BUTTON,
    NONE_MOTOR,
    NONE_SENSOR,
    SENSOR_PORTS,
    TMO_FEVR,
    TOUCH_SENSOR,
    TOUCH_THRESHOLD,
    ULTRASONIC_SENSOR,
    UNREGULATED_MOTOR,
    RgbRaw,
)
from athrill_sim.mock.kernel import Kernel
from hakoniwa.wire.protocol import MOTOR_PORTS, RX_GUEST_BASE, TX_GUEST_BASE, Rx, Tx


def c_div(a: int, b: int) -> int:
    """C's integer division, which truncates toward zero (Python's // floors)."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b > 0) else -q


def c_char(value: int) -> int:
    """C's (signed) char of an int, as EV3RT's motor commands carry their arguments."""
    return (value + 128) % 256 - 128


def rx(offset: int) -> int:
    return RX_GUEST_BASE + offset


def tx(offset: int) -> int:
    return TX_GUEST_BASE + offset


class Ev3Api(LcdApi, SerialApi, FsApi, BrickApi):
    """One robot program's EV3RT: the sensors, motors, LED and buttons here, the other devices in their
    modules (ev3lcd, ev3serial, ev3fs, ev3brick), each as EV3RT's own source does it."""

    def __init__(self, bus: MemoryBus, kernel: Kernel) -> None:
        self.bus = bus
        self.kernel = kernel
        self._sensors = [NONE_SENSOR] * SENSOR_PORTS
        self._motors = [NONE_MOTOR] * MOTOR_PORTS
        self._powers = [0] * MOTOR_PORTS
        self.run_dir = bus.run_dir
        BrickApi.__init__(self)
        SerialApi.__init__(self)
        FsApi.__init__(self)
        LcdApi.__init__(self)

    def syslog(self, message: str) -> None:
        """EV3RT's syslog: a line in the run's athrill.log, stamped with the simulation time."""
        print(f"[{self.kernel.now() / 1e6:10.3f} s] {message}", file=sys.stderr, flush=True)

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
        """SYSTIM in microseconds since the test started; the read takes its time after it."""
        now = self.kernel.now()
        self.kernel.spend_call()
        return now

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
        self._brake(port, 0)  # opOUTPUT_STOP, brake 0: configured idle, as EV3RT does
        return E_OK

    def ev3_motor_get_type(self, port: int) -> int:
        return self._motors[port] if 0 <= port < MOTOR_PORTS else E_ID

    # -- sensors -------------------------------------------------------------------------------------
    def _sensor_error(self, port: int, kind: int, name: str) -> int:
        """EV3RT's CHECK_PORT and CHECK_COND(type == kind, E_OBJ) (ev3api_sensor.c), which log the error."""
        err = E_ID if not 0 <= port < SENSOR_PORTS else E_OBJ if self._sensors[port] != kind else E_OK
        if err:
            self.syslog(f"{name}(): ercd {err}")
        return err

    def _index(self, port: int, kind: int) -> int:
        """get_sensor_index (ev3api_sensor.c): how many earlier ports have a sensor of the same kind."""
        return sum(t == kind for t in self._sensors[:port])

    def _color_slot(self, port: int, slot0: int) -> int:
        """EV3_SENSOR_ADDR_* (ev3_vdev.h): the second colour sensor (index 1) reads the COLOR1 slots, any other
        the COLOR0 ones."""
        return slot0 + (Rx.COLOR1_AMBIENT - Rx.COLOR0_AMBIENT if self._index(port, COLOR_SENSOR) == 1 else 0)

    def _color(self, port: int, slot0: int, name: str) -> int:
        self.kernel.spend_call()  # a device read takes its time
        if self._sensor_error(port, COLOR_SENSOR, name):
            return 0
        return int(self.bus.read("B", rx(self._color_slot(port, slot0))))

    def ev3_color_sensor_get_reflect(self, port: int) -> int:
        return self._color(port, Rx.COLOR0_REFLECT, "ev3_color_sensor_get_reflect")

    def ev3_color_sensor_get_ambient(self, port: int) -> int:
        return self._color(port, Rx.COLOR0_AMBIENT, "ev3_color_sensor_get_ambient")

    def ev3_color_sensor_get_color(self, port: int) -> int:
        return self._color(port, Rx.COLOR0_COLOR, "ev3_color_sensor_get_color")

    def ev3_color_sensor_get_rgb_raw(self, port: int, val: RgbRaw) -> None:
        """Fills `val` as EV3RT fills its rgb_raw_t (16 bits of each slot); on an error `val` is left alone."""
        self.kernel.spend_call()  # a device read takes its time
        if self._sensor_error(port, COLOR_SENSOR, "ev3_color_sensor_get_rgb_raw"):
            return
        base = self._color_slot(port, Rx.COLOR0_RGB)
        val.r, val.g, val.b = (int(self.bus.read("H", rx(base + 4 * i))) for i in range(3))

    def _gyro(self, port: int, slot: int, name: str) -> int:
        self.kernel.spend_call()  # a device read takes its time
        return 0 if self._sensor_error(port, GYRO_SENSOR, name) else int(self.bus.read("h", rx(slot)))

    def ev3_gyro_sensor_get_angle(self, port: int) -> int:
        return self._gyro(port, Rx.GYRO_ANGLE, "ev3_gyro_sensor_get_angle")

    def ev3_gyro_sensor_get_rate(self, port: int) -> int:
        return self._gyro(port, Rx.GYRO_RATE, "ev3_gyro_sensor_get_rate")

    def ev3_gyro_sensor_reset(self, port: int) -> int:
        """uart_dri_get_data_gyro's GYRO_CAL: the TX reset flag (the physics process clears it once it has
        zeroed its angle), and the RX angle and rate zeroed at once, so a read before the next snapshot is 0."""
        if err := self._sensor_error(port, GYRO_SENSOR, "ev3_gyro_sensor_reset"):
            return err
        self.bus.write("i", tx(Tx.GYRO_RESET), 1)
        self.bus.write("i", rx(Rx.GYRO_ANGLE), 0)
        self.bus.write("i", rx(Rx.GYRO_RATE), 0)
        return E_OK

    def ev3_ultrasonic_sensor_get_distance(self, port: int) -> int:
        self.kernel.spend_call()  # a device read takes its time
        if self._sensor_error(port, ULTRASONIC_SENSOR, "ev3_ultrasonic_sensor_get_distance"):
            return 0
        return c_div(int(self.bus.read("h", rx(Rx.ULTRASONIC_MM))), 10)

    def ev3_ultrasonic_sensor_listen(self, port: int) -> bool:
        """Whether another ultrasonic sensor is heard: its slot nonzero (uart_dri_get_data_ultrasonic, mode 2)."""
        self.kernel.spend_call()  # a device read takes its time
        if self._sensor_error(port, ULTRASONIC_SENSOR, "ev3_ultrasonic_sensor_listen"):
            return False
        return self.bus.read("I", rx(Rx.ULTRASONIC_LISTEN)) != 0

    def ev3_touch_sensor_is_pressed(self, port: int) -> bool:
        """The first touch sensor in port order reads slot 0, any later one slot 1 (uart_dri_get_data_touch)."""
        self.kernel.spend_call()  # a device read takes its time
        if self._sensor_error(port, TOUCH_SENSOR, "ev3_touch_sensor_is_pressed"):
            return False
        slot = Rx.TOUCH0 if self._index(port, TOUCH_SENSOR) == 0 else Rx.TOUCH1
        return int(self.bus.read("h", rx(slot))) > TOUCH_THRESHOLD

    def ev3_button_is_pressed(self, button: int) -> bool:
        self.kernel.spend_call()  # a device read takes its time
        if not LEFT_BUTTON <= button <= BACK_BUTTON:
            return False
        return bool(int(self.bus.read("I", rx(Rx.BUTTONS))) >> button & 1)

    # -- motors --------------------------------------------------------------------------------------
    def _motor_error(self, port: int) -> int:
        if not 0 <= port < MOTOR_PORTS:
            return E_ID
        return E_OBJ if self._motors[port] == NONE_MOTOR else E_OK

    def ev3_motor_get_counts(self, port: int) -> int:
        self.kernel.spend_call()  # a device read takes its time
        if err := self._motor_error(port):
            self.syslog(f"ev3_motor_get_counts(): Failed to get motor counts, ercd: {err}")
            return 0
        return int(self.bus.read("i", rx(Rx.MOTOR_ANGLE + 4 * port)))

    def ev3_motor_reset_counts(self, port: int) -> int:
        """motor_clr_angle (motor_dri.c): the TX reset flag of the port, port D's included."""
        if err := self._motor_error(port):
            return err
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
        self._powers[port] = power
        return E_OK

    def ev3_motor_get_power(self, port: int) -> int:
        """EV3RT answers the power last set (ev3api_motor.c's motor_power[]), not the TX slot, which
        ev3_motor_config zeroes behind its back."""
        self.kernel.spend_call()  # a device read takes its time
        if err := self._motor_error(port):
            self.syslog(f"ev3_motor_get_power(): Failed to get motor power, ercd: {err}")
            return 0
        return self._powers[port]

    def _brake(self, port: int, brake: int) -> None:
        """motor_brake (motor_dri.c) of opOUTPUT_STOP: power slot 0, and the brake as the command's char."""
        self.bus.write("i", tx(Tx.MOTOR_POWER + 4 * port), 0)
        self.bus.write("i", tx(Tx.MOTOR_BRAKE + 4 * port), c_char(int(brake)))

    def ev3_motor_stop(self, port: int, brake: bool) -> int:
        if err := self._motor_error(port):
            return err
        self.ev3_motor_set_power(port, 0)
        self._brake(port, brake)
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
        """ev3_led_set_color (ev3api_brick.c) keeps only the RED and GREEN bits of `color`, so it never fails;
        gpio_set_value (gpio_dri.c) sets or clears each in the LED byte and leaves its other bits alone."""
        led = int(self.bus.read("B", tx(Tx.LED)))
        for bit in (LED_RED, LED_GREEN):
            led = led | bit if color & bit else led & ~bit
        self.bus.write("B", tx(Tx.LED), led)
        return E_OK
