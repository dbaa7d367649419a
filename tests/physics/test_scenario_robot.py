"""Scenario and robot files: what they mean, and that any text is either that or one ScenarioError/RobotError."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hakoniwa.physics.robots import BUILT_IN, RobotError, load_robot, parse_robot
from hakoniwa.physics.scenario import ScenarioError, parse_scenario


def test_a_touch_press_and_a_button_press_hold_for_their_time():
    s = parse_scenario('[[press]]\nsensor = "touch"\nport = 1\nat_s = 1.0\nfor_s = 0.5\n'
                       '[[press]]\nbutton = "enter"\nat_s = 0\n[[serial]]\nat_s = 2\ntext = "1"\n')
    assert s.sensor_presses(999_999) == [] and [p.port for p in s.sensor_presses(1_000_000)] == ["1"]
    assert s.sensor_presses(1_500_000) == []
    assert s.buttons(0) == 1 << 4 and s.buttons(100_000) == 0  # for_s defaults to 0.1 s
    assert s.serial_lines() == "2000000 bt 31\n"


@pytest.mark.parametrize("text, words", [
    ('[[press]]\nsensor = "sonar"\nport = 1\nat_s = 1\n', "sonar"),
    ('[[press]]\nsensor = "touch"\nport = 1\nat_s = -1\n', "at least 0"),
    ('[[press]]\nbutton = "MIDDLE"\nat_s = 1\n', "MIDDLE"),
    ('[[press]]\nsensor = "touch"\nport = 5\nat_s = 1\n', "port"),
    ('[[serial]]\nat_s = 1\n', "text"),
])
def test_bad_scenarios_say_what_is_wrong(text, words):
    with pytest.raises(ScenarioError, match=words):
        parse_scenario(text)


def test_hackev_is_ets_wiring():
    r = BUILT_IN["hackev"]
    assert (r.wiring.left, r.wiring.right) == (2, 1)  # C, B
    assert dict(r.sensors) == {"1": "touch", "2": "color", "3": "ultrasonic", "4": "gyro"}
    assert r.touch_slot("1") == 0 and r.touch_slot("2") is None


def test_two_devices_on_one_port_are_refused():
    with pytest.raises(RobotError, match="two devices on sensor port 2"):
        parse_robot('[[sensor]]\nport = 2\nkind = "touch"\n[[sensor]]\nport = 2\nkind = "gyro"\n', "r.toml")
    with pytest.raises(RobotError, match="two devices on motor port B"):
        parse_robot('left_motor = "B"\nright_motor = "B"\n', "r.toml")
    with pytest.raises(RobotError, match="no robot"):
        load_robot("nonesuch")


@given(st.text(max_size=200))
def test_any_scenario_text_parses_or_is_one_scenario_error(text):
    try:
        parse_scenario(text)
    except ScenarioError as e:
        assert "\n" not in str(e).strip() or "TOML" in str(e)


@given(st.lists(st.tuples(st.sampled_from(["sensor", "button", "port", "at_s", "for_s", "x"]),
                         st.sampled_from(['"touch"', '"ENTER"', '"gyro"', "1", "-1", "0.5", "7", "true", "nan"])),
                max_size=5))
def test_any_press_table_is_a_press_or_one_scenario_error(pairs):
    text = "[[press]]\n" + "".join(f"{k} = {v}\n" for k, v in dict(pairs).items())
    try:
        press = parse_scenario(text).presses[0]
    except ScenarioError as e:
        assert "\n" not in str(e)
    else:
        assert press.at_us >= 0 and press.for_us > 0 and (press.sensor is None) != (press.button is None)


@given(st.text(max_size=200))
def test_any_robot_text_parses_or_is_one_robot_error(text):
    try:
        parse_robot(text, "r.toml")
    except RobotError:
        pass
