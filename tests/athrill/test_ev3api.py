"""The mock EV3RT API over a real guest memory bus (no physics process needed)."""

import pytest

from athrill_sim.mock.bus import BusError, MemoryBus
from athrill_sim.mock.ev3api import (
    COLOR_SENSOR,
    E_ID,
    E_OBJ,
    E_OK,
    ENTER_BUTTON,
    EV3_PORT_1,
    EV3_PORT_2,
    EV3_PORT_3,
    EV3_PORT_A,
    EV3_PORT_B,
    EV3_PORT_D,
    GYRO_SENSOR,
    LARGE_MOTOR,
    LED_ORANGE,
    TOUCH_SENSOR,
    ULTRASONIC_SENSOR,
    Ev3Api,
)
from athrill_sim.mock.kernel import Kernel
from hakoniwa.wire.protocol import Rx, Tx, open_athrill, open_unity


@pytest.fixture
def api(tmp_path):
    open_unity(tmp_path, create=True).close()
    open_athrill(tmp_path, create=True).close()
    bus = MemoryBus(tmp_path)
    api = Ev3Api(bus, Kernel(bus.unity, bus.athrill))
    for port in (EV3_PORT_A, EV3_PORT_B):
        api.ev3_motor_config(port, LARGE_MOTOR)
    yield api
    bus.close()


def powers(api):
    return api.bus.athrill.read_i32s(Tx.MOTOR_POWER, 4)


# Expected values worked out by hand from EV3RT's ev3api_motor.c (ev3_motor_steer, lines 240-283): |turn| and
# |power| capped at 100; the wheel on the side of the turn gets abs_power * (100 - abs_turn) / 100 in C integer
# arithmetic (right for turn > 0, else left); both negated when power < 0.
@pytest.mark.parametrize("power, turn, left, right", [
    (15, 0, 15, 15),
    (15, 50, 15, 7),      # 15*50/100 = 7.5 -> 7
    (15, 100, 15, 0),     # the inner wheel stops, never reverses
    (15, -100, 0, 15),
    (15, 33, 15, 10),     # 15*67/100 = 10.05 -> 10
    (15, -33, 10, 15),
    (15, 250, 15, 0),     # |turn| capped at 100, not refused
    (15, -101, 0, 15),
    (-15, 30, -15, -10),  # 15*70/100 = 10.5 -> 10, then negated
    (-15, -30, -10, -15),
    (150, 20, 100, 80),   # |power| capped at 100 first
    (-150, 0, -100, -100),
    (7, 99, 7, 0),        # 7*1/100 = 0.07 -> 0
])
def test_motor_steer_follows_ev3rt(api, power, turn, left, right):
    assert api.ev3_motor_steer(EV3_PORT_A, EV3_PORT_B, power, turn) == E_OK
    p = powers(api)
    assert (p[EV3_PORT_A], p[EV3_PORT_B]) == (left, right)


def test_motor_steer_needs_both_motors(api):
    api.ev3_motor_steer(EV3_PORT_A, EV3_PORT_B, 20, 0)
    assert api.ev3_motor_steer(EV3_PORT_A, EV3_PORT_D, 30, 0) == E_OBJ
    assert api.ev3_motor_steer(EV3_PORT_A, 9, 30, 0) == E_ID
    assert powers(api)[EV3_PORT_A] == 20  # motors left alone


def test_set_power_clamps_and_needs_a_configured_motor(api):
    api.ev3_motor_set_power(EV3_PORT_B, 250)
    assert powers(api)[EV3_PORT_B] == 100
    assert api.ev3_motor_get_power(EV3_PORT_B) == 100
    assert api.ev3_motor_set_power(EV3_PORT_D, 10) == E_OBJ
    assert api.ev3_motor_set_power(7, 10) == E_ID


def test_parameters_are_read_from_guest_memory(api):
    api.bus.unity.write_f32(Rx.KP, 1.539)
    assert api.bus.read_f32(0x090F0000 + 540) == pytest.approx(1.539)
    assert api.bus.read_f32(0x090F0FFC) == 0.0  # anywhere in the 4 KiB window
    with pytest.raises(BusError):
        api.bus.read_f32(0x08000000)


def test_sensors_read_like_ev3rts_drivers(api):
    u = api.bus.unity
    u.write_i32(Rx.COLOR0_REFLECT, 0x1234_0049)  # EV3RT takes the low byte: 73
    u.write_i32(Rx.COLOR0_COLOR, 6)
    u.write_i32(Rx.ULTRASONIC_MM, 427)  # mm in, cm out (truncated)
    u.write_i32(Rx.GYRO_ANGLE, -90)
    u.write_i32(Rx.TOUCH0, 4095)
    for port, kind in ((EV3_PORT_1, COLOR_SENSOR), (EV3_PORT_2, ULTRASONIC_SENSOR), (EV3_PORT_3, GYRO_SENSOR)):
        assert api.ev3_sensor_config(port, kind) == E_OK
    assert api.ev3_color_sensor_get_reflect(EV3_PORT_1) == 73
    assert api.ev3_color_sensor_get_color(EV3_PORT_1) == 6
    assert api.ev3_ultrasonic_sensor_get_distance(EV3_PORT_2) == 42
    assert api.ev3_gyro_sensor_get_angle(EV3_PORT_3) == -90
    assert api.ev3_sensor_config(EV3_PORT_3, TOUCH_SENSOR) == E_OK
    assert api.ev3_touch_sensor_is_pressed(EV3_PORT_3)


def test_a_sensor_not_configured_on_the_port_reads_zero(api, capsys):
    api.bus.unity.write_i32(Rx.COLOR0_REFLECT, 73)
    assert api.ev3_color_sensor_get_reflect(EV3_PORT_2) == 0
    assert "ercd -41" in capsys.readouterr().err  # E_OBJ, as EV3RT logs it


def test_reset_counts_raises_the_flag_the_physics_side_clears(api):
    api.bus.unity.write_i32(Rx.MOTOR_ANGLE + 4 * EV3_PORT_B, 530)
    assert api.ev3_motor_get_counts(EV3_PORT_B) == 530
    assert api.ev3_motor_reset_counts(EV3_PORT_B) == E_OK
    assert api.bus.athrill.read_i32(Tx.MOTOR_RESET_ANGLE + 4 * EV3_PORT_B) == 1


def test_stop_sets_the_brake_flag(api):
    api.ev3_motor_set_power(EV3_PORT_A, 30)
    assert api.ev3_motor_stop(EV3_PORT_A, True) == E_OK
    assert powers(api)[EV3_PORT_A] == 0
    assert api.bus.athrill.read_i32(Tx.MOTOR_BRAKE) == 1


def test_led_and_buttons(api):
    assert api.ev3_led_set_color(LED_ORANGE) == E_OK
    assert api.bus.athrill.read_i32(Tx.LED) == 0b11  # RED | GREEN bits
    # ev3api_brick.c looks only at the RED and GREEN bits: 9 = 0b1001 is red, and E_OK (never E_PAR).
    assert api.ev3_led_set_color(9) == E_OK
    assert api.bus.athrill.read_i32(Tx.LED) == 0b01
    assert not api.ev3_button_is_pressed(ENTER_BUTTON)
    api.bus.unity.write_i32(Rx.BUTTONS, 1 << ENTER_BUTTON)
    assert api.ev3_button_is_pressed(ENTER_BUTTON)


def test_touch_sensors_are_numbered_in_port_order(api):
    """As EV3RT does: the sample's touch sensors on ports 3 and 4 read slots 0 (RX 112) and 1 (RX 124)."""
    from athrill_sim.mock.ev3api import EV3_PORT_4

    api.ev3_sensor_config(EV3_PORT_3, TOUCH_SENSOR)
    api.ev3_sensor_config(EV3_PORT_4, TOUCH_SENSOR)
    api.bus.unity.write_i32(Rx.TOUCH1, 4095)
    assert not api.ev3_touch_sensor_is_pressed(EV3_PORT_3)
    assert api.ev3_touch_sensor_is_pressed(EV3_PORT_4)


def test_gyro_reset_zeroes_the_rx_slots_at_once(api, capsys):
    """uart_dri_get_data_gyro, mode GYRO_CAL (4): TX reset flag 1, then RX angle and rate 0."""
    api.bus.unity.write_i32(Rx.GYRO_ANGLE, 45)
    api.bus.unity.write_i32(Rx.GYRO_RATE, -3)
    api.ev3_sensor_config(EV3_PORT_2, GYRO_SENSOR)
    assert api.ev3_gyro_sensor_reset(EV3_PORT_2) == E_OK
    assert api.bus.athrill.read_i32(Tx.GYRO_RESET) == 1
    assert (api.ev3_gyro_sensor_get_angle(EV3_PORT_2), api.ev3_gyro_sensor_get_rate(EV3_PORT_2)) == (0, 0)
    assert api.ev3_gyro_sensor_reset(EV3_PORT_1) == E_OBJ
    assert "ev3_gyro_sensor_reset(): ercd -41" in capsys.readouterr().err  # ev3api_sensor.c logs it too


def test_a_click_is_a_release(api):
    """brick_dri.c's brick_button_cyc: clicked when the button was down and is up now."""
    clicks = []
    assert api.ev3_button_set_on_clicked(ENTER_BUTTON, clicks.append, 7) == E_OK
    for buttons in (1 << ENTER_BUTTON, 1 << ENTER_BUTTON, 0, 0):
        api.bus.unity.write_i32(Rx.BUTTONS, buttons)
        for hook in api.kernel.on_snapshot:
            hook()
        if buttons:
            assert clicks == []
    assert clicks == [7]
