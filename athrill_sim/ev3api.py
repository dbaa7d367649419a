"""An EV3RT-like API over the guest memory bus, so a robot program reads like its C original.

Names, units and error behaviour follow EV3RT: powers in percent, counts in degrees, `ev3_motor_steer`
refuses a turn ratio outside -100..100 with E_PAR and leaves the motors alone, `tslp_tsk` takes
microseconds. Sensor ports are fixed by the robot's wiring below.
"""

from __future__ import annotations

from hakoniwa.protocol import ATHRILL_GUEST_BASE, UNITY_GUEST_BASE, Athrill, Unity
from athrill_sim.bus import MemoryBus
from athrill_sim.kernel import Kernel

E_OK = 0
E_PAR = -17  # parameter error, as in TOPPERS

EV3_PORT_A, EV3_PORT_B, EV3_PORT_C, EV3_PORT_D = range(4)
EV3_PORT_1, EV3_PORT_2, EV3_PORT_3, EV3_PORT_4 = range(4)
MOTOR_PORTS = (EV3_PORT_A, EV3_PORT_B, EV3_PORT_C, EV3_PORT_D)

# The robot's wiring: which sensor sits on which sensor port.
COLOR_SENSOR_PORT = EV3_PORT_1
ULTRASONIC_SENSOR_PORT = EV3_PORT_2
GYRO_SENSOR_PORT = EV3_PORT_3
TOUCH_SENSOR_PORT = EV3_PORT_4


class SensorPortError(ValueError):
    """A program asked a port for a sensor that is not connected there."""


def _c_div(a: int, b: int) -> int:
    """C's integer division, which truncates toward zero (Python's // floors)."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b > 0) else -q


class Ev3Api:
    def __init__(self, bus: MemoryBus, kernel: Kernel) -> None:
        self.bus = bus
        self.kernel = kernel
        self._count_offsets = [0, 0, 0, 0]

    # -- kernel --------------------------------------------------------------------------------------
    def tslp_tsk(self, timeout_us: int) -> int:
        self.kernel.sleep(int(timeout_us))
        return E_OK

    def get_tim(self) -> int:
        """SYSTIM in microseconds since the test started."""
        return self.kernel.now_us

    # -- sensors -------------------------------------------------------------------------------------
    def _sensor(self, port: int, wired: int, offset: int, kind: str) -> int:
        if port != wired:
            raise SensorPortError(f"no {kind} sensor on port {port + 1} (it is wired to port {wired + 1})")
        return self.bus.read_i32(UNITY_GUEST_BASE + offset)

    def ev3_color_sensor_get_reflect(self, port: int) -> int:
        return self._sensor(port, COLOR_SENSOR_PORT, Unity.COLOR_REFLECT, "color")

    def ev3_color_sensor_get_ambient(self, port: int) -> int:
        return self._sensor(port, COLOR_SENSOR_PORT, Unity.COLOR_AMBIENT, "color")

    def ev3_color_sensor_get_rgb_raw(self, port: int) -> tuple[int, int, int]:
        r = self._sensor(port, COLOR_SENSOR_PORT, Unity.COLOR_RGB, "color")
        g = self.bus.read_i32(UNITY_GUEST_BASE + Unity.COLOR_RGB + 4)
        b = self.bus.read_i32(UNITY_GUEST_BASE + Unity.COLOR_RGB + 8)
        return r, g, b

    def ev3_ultrasonic_sensor_get_distance(self, port: int) -> int:
        return self._sensor(port, ULTRASONIC_SENSOR_PORT, Unity.ULTRASONIC_CM, "ultrasonic")

    def ev3_gyro_sensor_get_angle(self, port: int) -> int:
        return self._sensor(port, GYRO_SENSOR_PORT, Unity.GYRO_ANGLE, "gyro")

    def ev3_gyro_sensor_get_rate(self, port: int) -> int:
        return self._sensor(port, GYRO_SENSOR_PORT, Unity.GYRO_RATE, "gyro")

    def ev3_touch_sensor_is_pressed(self, port: int) -> bool:
        return bool(self._sensor(port, TOUCH_SENSOR_PORT, Unity.TOUCH, "touch"))

    # -- motors --------------------------------------------------------------------------------------
    def _raw_counts(self, port: int) -> int:
        return self.bus.read_i32(UNITY_GUEST_BASE + Unity.MOTOR_COUNTS + 4 * port)

    def ev3_motor_get_counts(self, port: int) -> int:
        if port not in MOTOR_PORTS:
            return 0
        return self._raw_counts(port) - self._count_offsets[port]

    def ev3_motor_reset_counts(self, port: int) -> int:
        if port not in MOTOR_PORTS:
            return E_PAR
        self._count_offsets[port] = self._raw_counts(port)
        return E_OK

    def ev3_motor_set_power(self, port: int, power: int) -> int:
        if port not in MOTOR_PORTS:
            return E_PAR
        power = max(-100, min(100, int(power)))
        self.bus.write_i32(ATHRILL_GUEST_BASE + Athrill.MOTOR_POWER + 4 * port, power)
        return E_OK

    def ev3_led_set_color(self, color: int) -> int:
        """LED_OFF 0, LED_RED 1, LED_GREEN 2, LED_ORANGE 3; the physics process may show it."""
        if color not in range(4):
            return E_PAR
        self.bus.write_i32(ATHRILL_GUEST_BASE + Athrill.LED, color)
        return E_OK

    def ev3_motor_stop(self, port: int, brake: bool = True) -> int:
        return self.ev3_motor_set_power(port, 0)

    def ev3_motor_steer(self, left_motor: int, right_motor: int, power: int, turn_ratio: int) -> int:
        """Drive two motors as a pair: turn_ratio 0 runs straight, +100 spins clockwise in place."""
        if not -100 <= turn_ratio <= 100 or left_motor not in MOTOR_PORTS or right_motor not in MOTOR_PORTS:
            return E_PAR
        if turn_ratio >= 0:
            left, right = power, power - _c_div(power * turn_ratio, 50)
        else:
            left, right = power + _c_div(power * turn_ratio, 50), power
        self.ev3_motor_set_power(left_motor, left)
        self.ev3_motor_set_power(right_motor, right)
        return E_OK
