"""Parameter spaces: the paper's default, the example file, and one-line errors for bad files."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from hakoniwa.wire.protocol import Rx
from testctl.search.space import ParameterSpace, SpaceError
from tests.helpers.paths import DOCS

EXAMPLE = DOCS / "space-example.toml"

GOOD = """
[[param]]
name = "Kp"
offset = 540
low = 0
high = 5

[[fixed]]
name = "motor_power"
offset = 552
value = 15
"""


def test_default_is_the_papers_experiment() -> None:
    space = ParameterSpace.default()
    assert space.names == ("Kp", "Ki", "Kd")
    assert all((p.low, p.high) == (0.0, 5.0) for p in space.params)
    assert space.to_offsets([1.0, 2.0, 3.0]) == {
        Rx.KP: 1.0, Rx.KI: 2.0, Rx.KD: 3.0, Rx.MOTOR_POWER: 15.0
    }


def test_example_file_loads_and_round_trips(tmp_path: Path) -> None:
    space = ParameterSpace.load(EXAMPLE)
    assert space.names == ("Kp", "Ki", "Kd", "motor_power")
    assert ParameterSpace.from_dict(space.to_dict()) == space
    x = (1.0, 2.0, 3.0, 20.0)
    assert space.from_named(space.to_named(x)) == x


def test_every_parameter_of_the_example_changes_the_lap(tmp_path: Path) -> None:
    """The example searches what the built-in tracer reads: moving any one parameter moves the lap."""
    from tests.helpers.bench_fixtures import physics

    space = ParameterSpace.load(EXAMPLE)
    base = (1.539, 4.267, 4.511, 15.0)
    with physics(tmp_path) as (_, runner):
        laps = {}
        for i in range(-1, space.dim):
            x = tuple(v * (1.3 if j == i else 1.0) for j, v in enumerate(base))
            laps[i] = runner.run_test(space.to_offsets(x)).goal_time_us
    assert all(laps[i] != laps[-1] for i in range(space.dim)), laps


def test_good_file(tmp_path: Path) -> None:
    path = tmp_path / "s.toml"
    path.write_text(GOOD)
    space = ParameterSpace.load(path)
    assert space.to_offsets([2.5]) == {540: 2.5, 552: 15.0}


@pytest.mark.parametrize(
    "text, problem",
    [
        ("[[param]\nname=", "not valid TOML"),
        (GOOD.replace('name = "Kp"\n', ""), "missing or non-string 'name'"),
        (GOOD.replace("low = 0\n", ""), "missing or non-numeric 'low'"),
        (GOOD.replace("offset = 540\n", ""), "missing or non-integer 'offset'"),
        (GOOD.replace("value = 15\n", 'value = "15"\n'), "non-numeric 'value'"),
        (GOOD.replace("high = 5", "high = 0"), "low 0.0 must be below high 0.0"),
        (GOOD.replace("offset = 540", "offset = 536"), "outside the parameter area 540..1020"),
        (GOOD.replace("offset = 540", "offset = 1024"), "outside the parameter area"),
        (GOOD.replace("offset = 540", "offset = 542"), "not 4-byte aligned"),
        (GOOD.replace("offset = 552", "offset = 540"), "share offset 540"),
        (GOOD.replace('"motor_power"', '"Kp"'), "'Kp' is used twice"),
        (GOOD.replace("high = 5", "high = 5\nhihg = 6"), "unknown key(s): hihg"),
        (GOOD + "\n[extra]\n", "unknown top-level key(s): extra"),
        ("param = 3\n", "array of tables"),
        ("", "no searched parameter"),
    ],
)
def test_bad_file_raises_one_line_space_error(tmp_path: Path, text: str, problem: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(SpaceError) as info:
        ParameterSpace.load(path)
    message = str(info.value)
    assert problem in message
    assert "\n" not in message
    assert message.startswith(str(path))


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(SpaceError, match="cannot read"):
        ParameterSpace.load(tmp_path / "nope.toml")


@settings(max_examples=80, deadline=None)
@given(key=st.sampled_from(["high", "value"]),
       number=st.floats(-1e300, 1e300) | st.integers(-10**40, 10**40))
def test_every_value_and_bound_is_checked_against_its_float32_slot(tmp_path_factory, key: str, number) -> None:
    """A number a float32 slot cannot hold (1e39) is refused when the file is read, naming the slot's type;
    one it holds exactly as the command line would take it is accepted."""
    import struct

    from hakoniwa.conventions import FLOAT32_MAX

    if key == "high":
        assume(float(number) > -3e38)
        text = GOOD.replace("low = 0", "low = -3e38").replace("high = 5", f"high = {number!r}")
    else:
        text = GOOD.replace("value = 15", f"value = {number!r}")
    path = tmp_path_factory.mktemp("space") / "s.toml"
    path.write_text(text)
    try:
        struct.pack("<f", float(number))  # what the bench does with it, in every test
    except OverflowError:
        with pytest.raises(SpaceError, match=f"{key} .* does not fit a float32 slot"):
            ParameterSpace.load(path)
    else:
        if abs(float(number)) <= FLOAT32_MAX:
            ParameterSpace.load(path)
