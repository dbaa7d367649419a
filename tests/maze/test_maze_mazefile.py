import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maze.errors import MazeError
from maze.files.builtin import builtin_path
from maze.files.mazefile import dump_maze, parse_maze
from maze.model import Maze, central_goals
from maze.search.stepmap import UNREACHED, pessimistic, shortest_path, step_map
from tests.maze.test_maze_builtin import builtin_maze_params, large_maze_params


@pytest.mark.parametrize("path", builtin_maze_params() + large_maze_params())
def test_every_real_maze_parses_fully_known_with_a_reachable_goal(path):
    maze = parse_maze(path.read_text())
    assert maze.size == (32 if path.stem.startswith("japan") else 16)
    assert maze.known_inner() == maze.size * (maze.size - 1) * 2
    assert shortest_path(maze, pessimistic(maze))
    assert maze.start == (0, 0)
    assert maze.goals
    # a file with its start and goals marked prints back to itself
    text = path.read_text()
    if " S " in text and " G " in text:
        assert dump_maze(maze).splitlines() == [ln.rstrip() for ln in text.rstrip("\n").splitlines()]


def test_classic_goal_is_the_central_2x2_and_halfsize_goals_come_from_the_file():
    classic = parse_maze(builtin_path("alljapan-001-1980").read_text())
    assert set(classic.goals) == set(central_goals(16))
    half = parse_maze(builtin_path("japan2009hef").read_text())
    assert half.goals == ((24, 15),)


def test_a_training_maze_without_g_gets_the_farthest_reachable_cell():
    # its 5x5 active area leaves out the central 2x2
    mini = parse_maze(builtin_path("minimaze").read_text())
    assert mini.goals == ((4, 4),)
    dist = step_map(mini.topo, pessimistic(mini), [0])
    assert dist[mini.cell_index((4, 4))] == max(d for d in dist if d < UNREACHED)


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
