"""The mock EV3RT API over a real guest memory bus (no physics process needed)."""

import pytest

from athrill_sim.bus import BusError, MemoryBus
from athrill_sim.ev3api import (E_OK, E_PAR, EV3_PORT_1, EV3_PORT_2, EV3_PORT_B, EV3_PORT_C, Ev3Api,
                                SensorPortError)
from athrill_sim.kernel import Kernel
from hakoniwa.protocol import ATHRILL_GUEST_BASE, Athrill, Unity, open_athrill, open_unity


@pytest.fixture
def api(tmp_path):
    open_unity(tmp_path, create=True).close()
    open_athrill(tmp_path, create=True).close()
    bus = MemoryBus(tmp_path)
    yield Ev3Api(bus, Kernel(bus.unity, bus.athrill))
    bus.close()


def powers(api):
    return api.bus.athrill.read_i32s(Athrill.MOTOR_POWER, 4)


@pytest.mark.parametrize("power, turn, left, right", [
    (15, 0, 15, 15),
    (15, 50, 15, 0),
    (15, 100, 15, -15),
    (15, -100, -15, 15),
    (15, 33, 15, 6),  # 15 - 15*33/50 = 15 - 9 (C truncation)
    (15, -33, 6, 15),
])
def test_motor_steer_follows_ev3rt(api, power, turn, left, right):
    assert api.ev3_motor_steer(EV3_PORT_C, EV3_PORT_B, power, turn) == E_OK
    p = powers(api)
    assert (p[EV3_PORT_C], p[EV3_PORT_B]) == (left, right)


def test_motor_steer_refuses_out_of_range_turn(api):
    api.ev3_motor_steer(EV3_PORT_C, EV3_PORT_B, 20, 0)
    assert api.ev3_motor_steer(EV3_PORT_C, EV3_PORT_B, 20, 101) == E_PAR
    assert powers(api)[EV3_PORT_C] == 20  # motors left alone


def test_set_power_clamps(api):
    api.ev3_motor_set_power(EV3_PORT_B, 250)
    assert powers(api)[EV3_PORT_B] == 100


def test_parameters_are_read_from_guest_memory(api):
    api.bus.unity.write_f32(Unity.KP, 1.539)
    assert api.bus.read_f32(0x090F0000 + 540) == pytest.approx(1.539)
    with pytest.raises(BusError):
        api.bus.read_f32(0x08000000)


def test_sensors_and_ports(api):
    api.bus.unity.write_i32(Unity.COLOR_REFLECT, 73)
    api.bus.unity.write_i32(Unity.ULTRASONIC_CM, 42)
    assert api.ev3_color_sensor_get_reflect(EV3_PORT_1) == 73
    assert api.ev3_ultrasonic_sensor_get_distance(EV3_PORT_2) == 42
    with pytest.raises(SensorPortError, match="no color sensor on port 2"):
        api.ev3_color_sensor_get_reflect(EV3_PORT_2)


def test_motor_counts_reset_is_relative(api):
    api.bus.unity.write_i32(Unity.MOTOR_COUNTS + 4 * EV3_PORT_B, 500)
    api.ev3_motor_reset_counts(EV3_PORT_B)
    api.bus.unity.write_i32(Unity.MOTOR_COUNTS + 4 * EV3_PORT_B, 530)
    assert api.ev3_motor_get_counts(EV3_PORT_B) == 30


def test_led(api):
    assert api.ev3_led_set_color(2) == E_OK
    assert api.bus.read_i32(ATHRILL_GUEST_BASE + Athrill.LED) == 2
    assert api.ev3_led_set_color(9) == E_PAR
