from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maze.errors import MazeError
from maze.mazefile import dump_maze, parse_maze
from maze.model import Maze, central_goals

SHARED_MAZES = Path(__file__).resolve().parents[1].parent / "shared" / "mazes"
MAZE_FILES = sorted(SHARED_MAZES.rglob("*.txt")) if SHARED_MAZES.is_dir() else []
needs_shared = pytest.mark.skipif(not MAZE_FILES, reason=f"shared mazes not found at {SHARED_MAZES}")


@needs_shared
@pytest.mark.parametrize("path", MAZE_FILES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_every_shared_maze_parses_fully_known(path):
    maze = parse_maze(path.read_text())
    assert maze.size == {"classic": 16, "halfsize": 32, "training": 16}[path.parent.name]
    assert maze.known_inner() == maze.size * (maze.size - 1) * 2
    assert maze.start == (0, 0)
    assert maze.goals
    # a file with its start and goals marked prints back to itself
    text = path.read_text()
    if " S " in text and " G " in text:
        assert dump_maze(maze).splitlines() == [ln.rstrip() for ln in text.rstrip("\n").splitlines()]


@needs_shared
def test_classic_goal_is_the_central_2x2_and_halfsize_goals_come_from_the_file():
    classic = parse_maze((SHARED_MAZES / "classic" / "alljapan-001-1980.txt").read_text())
    assert set(classic.goals) == set(central_goals(16))
    half = parse_maze((SHARED_MAZES / "halfsize" / "japan2009hef.txt").read_text())
    assert half.goals == ((24, 15),)


def random_maze(draw, size: int) -> Maze:
    m = Maze(size)
    for x, y, d in list(m.inner_walls()):
        state = draw(st.sampled_from([True, False, None]))
        if state is not None:
            m.set(x, y, d, state)
    m.goals = ((size - 1, size - 1),)
    return m


@st.composite
def mazes(draw):
    return random_maze(draw, draw(st.integers(1, 8)))


@given(mazes(), st.sampled_from("o+"))
def test_dump_parse_round_trip_keeps_unknown_walls(maze, post):
    back = parse_maze(dump_maze(maze, post=post))
    assert back.same_walls(maze)
    assert back.goals == maze.goals and back.start == maze.start


GOOD = dump_maze(Maze.unknown(3, goals=((2, 2),)))


@pytest.mark.parametrize(
    "text, message",
    [
        ("", "line 1"),
        (GOOD.replace("o---o---o---o", "o---o-x-o---o", 1), "line 1, column 6: bad wall segment"),
        (GOOD.replace("| S", "  S", 1), "line 6, column 1: the outer wall"),
        ("\n".join(GOOD.splitlines()[:5]), "needs 7 lines"),
        (GOOD.replace(" G ", " Q "), "line 2, column 10: unknown cell mark"),
        (GOOD.replace("o   o", "o   x", 1), "line 5, column 5: expected a post"),
        (GOOD.replace(" G ", " S "), "a second start"),
    ],
)
def test_malformed_files_name_the_line(text, message):
    with pytest.raises(MazeError, match=message):
        parse_maze(text)


@settings(max_examples=150)
@given(st.data())
def test_mutated_files_raise_only_maze_error(data):
    lines = GOOD.splitlines()
    r = data.draw(st.integers(0, len(lines) - 1))
    c = data.draw(st.integers(0, len(lines[r])))
    ch = data.draw(st.sampled_from(list("o+-|. SGx\t")))
    lines[r] = lines[r][:c] + ch + lines[r][c + 1:]
    try:
        parse_maze("\n".join(lines))
    except MazeError as e:
        assert str(e).startswith("line ")
