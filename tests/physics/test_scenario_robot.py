"""Scenario and robot files: what they mean, and that any text is either that or one ScenarioError/RobotError."""

import json

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hakoniwa.physics.robot import DEFAULT_WIRING
from hakoniwa.physics.robots import BUILT_IN, RobotError, load_robot, parse_robot
from hakoniwa.physics.scenario import EV3_BUTTONS, Press, Scenario, ScenarioError, parse_scenario
from hakoniwa.wire.protocol import NEVER_WAKES
from tests.helpers.commands import hako, one_line_error


def test_a_touch_press_and_a_button_press_hold_for_their_time():
    s = parse_scenario('[[press]]\nsensor = "touch"\nport = 1\nat_s = 1.0\nfor_s = 0.5\n'
                       '[[press]]\nbutton = "enter"\nat_s = 0\n[[serial]]\nat_s = 2\ntext = "1"\n')
    assert s.sensor_presses(999_999) == [] and [p.port for p in s.sensor_presses(1_000_000)] == ["1"]
    assert s.sensor_presses(1_500_000) == []
    assert s.buttons(0) == 1 << 4 and s.buttons(100_000) == 0  # for_s defaults to 0.1 s
    assert s.serial_lines() == "2000000 bt 31\n"


@given(st.lists(st.tuples(st.integers(0, 5), st.integers(0, 50), st.integers(1, 20)), max_size=4),
       st.integers(0, 80))
def test_the_buttons_hold_until_the_instant_the_scenario_says(presses, now_ms):
    """A patched athrill2 reads the buttons without a new snapshot before `buttons_until`: they must not change."""
    s = Scenario(tuple(Press(f"press {i}", None, None, EV3_BUTTONS[button], at * 1000, held * 1000)
                       for i, (button, at, held) in enumerate(presses)))
    until = s.buttons_until(now_ms * 1000)
    assert until > now_ms * 1000
    assert all(s.buttons(t) == s.buttons(now_ms * 1000) for t in range(now_ms * 1000, min(until, 100_000), 500))
    assert until == NEVER_WAKES or any(until in (p.at_us, p.at_us + p.for_us) for p in s.presses)


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


def test_two_devices_on_one_port_are_one_line_before_any_test(tmp_path):
    robot = tmp_path / "twice.toml"
    robot.write_text('[[sensor]]\nport = 2\nkind = "touch"\n[[sensor]]\nport = 2\nkind = "gyro"\n')
    one_line_error(hako("try", "--robot", str(robot), "--json", timeout=120),
                   "two devices on sensor port 2: touch and gyro")


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


# Mostly what an EV3 robot file may say, so that many draws parse, and some of what it may not.
MOTOR_PORTS = st.sampled_from(["A", "B", "C", "D", "a", "b", "c", "d", "E", "AB", 1])
SENSORS = st.tuples(st.sampled_from([1, 2, 3, 4] * 3 + [5, "1", True]),
                    st.sampled_from(["touch", "color", "ultrasonic", "gyro"] * 3 + ["force", "sonar"]))


def toml_value(value: object) -> str:
    return str(value).lower() if isinstance(value, bool) else json.dumps(value)


@given(name=st.none() | st.text("abcXYZ-_ ", min_size=1, max_size=8), left=st.none() | MOTOR_PORTS,
       right=st.none() | MOTOR_PORTS, sensors=st.lists(SENSORS, max_size=3),
       bumper=st.none() | st.booleans() | st.just(1))
def test_any_robot_file_is_the_robot_it_says_or_one_robot_error(name, left, right, sensors, bumper):
    given_keys = {"name": name, "left_motor": left, "right_motor": right, "bumper": bumper}
    text = "".join(f"{k} = {toml_value(v)}\n" for k, v in given_keys.items() if v is not None)
    text += "".join(f"[[sensor]]\nport = {toml_value(port)}\nkind = {toml_value(kind)}\n" for port, kind in sensors)
    try:
        robot = parse_robot(text, "r.toml")
    except RobotError as e:
        assert "\n" not in str(e)
        return
    assert robot.name == (name if name is not None else "r.toml")
    assert robot.wiring.left == (DEFAULT_WIRING.left if left is None else "ABCD".index(left.upper()))
    assert robot.wiring.right == (DEFAULT_WIRING.right if right is None else "ABCD".index(right.upper()))
    assert dict(robot.sensors) == {str(port): kind for port, kind in sensors}
    assert len(robot.sensors) == len(sensors)  # no port given twice
    assert robot.bumper is (bumper is True)
