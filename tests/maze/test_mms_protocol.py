"""The mms line parser: every command mms knows, and a one-line error for every line it does not."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from maze.direction import EAST, NORTH, SOUTH, WEST
from maze.mouse.mms import COMMANDS, STATS, Command, MmsCommandError, parse_command


@pytest.mark.parametrize("line, expected", [
    ("mazeWidth", Command("mazeWidth")),
    ("wallFront", Command("wallFront")),
    ("wallFrontLeft 3", Command("wallFrontLeft", count=3)),
    ("moveForward 4", Command("moveForward", count=4)),
    ("moveForwardHalf", Command("moveForwardHalf")),
    ("turnLeft45", Command("turnLeft45")),
    ("setWall 3 4 n", Command("setWall", x=3, y=4, direction=NORTH)),
    ("clearWall 0 0 e", Command("clearWall", direction=EAST)),
    ("setWall 1 1 s", Command("setWall", x=1, y=1, direction=SOUTH)),
    ("setWall 1 1 w", Command("setWall", x=1, y=1, direction=WEST)),
    ("setColor 2 5 G", Command("setColor", x=2, y=5, colour="G")),
    ("setText 1 2 hello world", Command("setText", x=1, y=2, text="hello worl")),
    ("setText 1 2 a\tb", Command("setText", x=1, y=2, text="a?b")),
    ("getStat score", Command("getStat", stat="score")),
    ("ackReset\r", Command("ackReset")),
])
def test_commands_parse(line: str, expected: Command) -> None:
    assert parse_command(line) == expected


@pytest.mark.parametrize("line, words", [
    ("hello", "unknown command 'hello'"),
    ("wallfront", "unknown command"),
    ("wallFront x", "N must be an integer"),
    ("moveForward 1 2", "takes one argument"),
    ("turnLeft 1", "takes no arguments"),
    ("setWall 1 2 q", "direction must be n, e, s or w"),
    ("setWall 1 n", "needs X Y D"),
    ("setColor 1 2 purple", "colour must be one of"),
    ("getStat speed", "unknown statistic 'speed'"),
    ("setText 1", "needs X Y TEXT"),
])
def test_bad_lines_say_what_is_wrong(line: str, words: str) -> None:
    with pytest.raises(MmsCommandError, match=words):
        parse_command(line)


@given(st.text(max_size=40))
def test_any_line_parses_or_gives_a_protocol_error(line: str) -> None:
    try:
        cmd = parse_command(line)
    except MmsCommandError as e:
        assert "\n" not in str(e).strip() or "\n" in line  # one line, unless the input itself had one
        return
    assert cmd.name in COMMANDS


@given(st.sampled_from(sorted(COMMANDS)), st.integers(-5, 70), st.integers(-5, 70), st.integers(0, 9),
       st.sampled_from("nesw"), st.sampled_from("kbacgorwyBCAGRY"), st.sampled_from(STATS),
       st.text(alphabet=st.characters(min_codepoint=33, max_codepoint=126), min_size=1, max_size=10))
def test_well_formed_commands_round_trip(name: str, x: int, y: int, n: int, d: str, colour: str, stat: str,
                                         text: str) -> None:
    spec = COMMANDS[name][0]
    args = {"": [], "n": [n], "xy": [x, y], "xyd": [x, y, d], "xyc": [x, y, colour], "xyt": [x, y, text],
            "stat": [stat]}[spec]
    cmd = parse_command(" ".join(str(a) for a in [name, *args]))
    assert cmd.name == name
    if spec == "n":
        assert cmd.count == n
    if spec.startswith("xy"):
        assert (cmd.x, cmd.y) == (x, y)
    if spec == "xyt":
        assert cmd.text == text
    if spec == "stat":
        assert cmd.stat == stat


@pytest.mark.parametrize("line, fatal", [
    ("wallFront x", True),  # an answer is due: the program would wait for ever
    ("getStat speed", True),
    ("hello", True),
    ("setWall 1 2 q", False),  # no answer is due: mms drops it and the program goes on
    ("setColor 1 2 purple", False),
    ("clearText a b", False),
])
def test_which_bad_lines_end_the_run(line: str, fatal: bool) -> None:
    with pytest.raises(MmsCommandError) as e:
        parse_command(line)
    assert e.value.fatal is fatal


def test_wall_letters_in_either_case_as_mms_readme_writes_them() -> None:
    assert parse_command("setWall 0 0 W") == Command("setWall", direction=WEST)
