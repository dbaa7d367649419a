"""The run-time model against hand-computed cases, and the mouse parameter file."""

from math import pi, sqrt

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from maze.direction import EAST, NORTH, SOUTH, WEST
from maze.errors import MazeError
from maze.fastpath import fastest_route, run_of_cells
from maze.fastpath.graph import ALONG_TURNS, DIAGONAL_TURNS, turn_shapes
from maze.files.builtin import builtin_path
from maze.files.mazefile import parse_maze
from maze.model import Maze
from maze.search.stepmap import pessimistic, shortest_path
from maze.timing.motion import TURNS, search_run, straight_seconds, turn_seconds
from maze.timing.mouseparams import builtin_table, load_mouse, mouse_from_table
from tests.helpers.commands import mazelog

# A mouse with round numbers: 1 m cells, 1 m/s^2, turns at 0.5 m/s with no lateral limit unless a test sets one.
ROUND = {"cell": 1.0, "search": {"speed": 0.5, "accel": 1.0, "pivot_time": 2.0},
         "run": {"accel": 1.0, "top_speed": 4.0, "diagonal_top_speed": 4.0, "turn_speed": 0.5,
                 "lateral_accel": 1000.0}}
MOUSE = mouse_from_table("round", ROUND)
STEP = {(1, 0): EAST, (0, 1): NORTH, (-1, 0): WEST, (0, -1): SOUTH}


def corridor_maze(size: int, cells: list[tuple[int, int]], goal: tuple[int, int]) -> Maze:
    """Every wall closed but those between consecutive cells of each path."""
    maze = Maze(size)
    for x, y, d in maze.inner_walls():
        maze.set(x, y, d, True)
    for (x, y), (nx, ny) in zip(cells, cells[1:]):
        maze.set(x, y, STEP[(nx - x, ny - y)], False)
    maze.goals = (goal,)
    return maze


def test_trapezoid_triangle_and_free_end_by_hand():
    # 0.5 -> 4 -> 0.5 at 1 m/s^2 needs 7.875 m each way; 20 m: 2 * 3.5 s + 4.25 m at 4 m/s
    assert straight_seconds(20, 0.5, 0.5, 4, 1) == pytest.approx(7 + 4.25 / 4)
    # 3 m is too short to reach 4 m/s: peak sqrt((2*3 + 0.25 + 0.25) / 2) = sqrt(3.25)
    assert straight_seconds(3, 0.5, 0.5, 4, 1) == pytest.approx(2 * (sqrt(3.25) - 0.5))
    # to the goal line from rest: 2 m reach 2 m/s in 2 s; 10 m reach 4 m/s after 8 m, then 2 m at 4 m/s
    assert straight_seconds(2, 0, None, 4, 1) == pytest.approx(2)
    assert straight_seconds(10, 0, None, 4, 1) == pytest.approx(4 + 0.5)
    assert straight_seconds(0, 0.5, 0.5, 4, 1) == 0


@pytest.mark.parametrize("cells", [1, 2, 3, 5])
def test_a_straight_of_n_cells_from_the_start_into_the_goal(cells):
    maze = corridor_maze(8, [(0, y) for y in range(cells + 1)], (0, cells))
    route = fastest_route(maze, pessimistic(maze), False, MOUSE)
    # from rest in the start cell's centre to the goal's edge: d = n - 1/2 cells, v = sqrt(2 a d) < 4 m/s
    d = cells - 0.5
    assert route.sequence == f"S{d:g}" and route.seconds == pytest.approx(sqrt(2 * d))
    assert len(route.cells) - 1 == cells


def test_each_turn_length_and_time_by_hand():
    r_45, r_135 = 1 + sqrt(2) / 2, 2 - sqrt(2)  # the widest arcs that fit a 45 and a 135
    lengths = {"90s": pi / 4, "90": 1 + pi / 2, "180": 2 + pi / 2, "45": (1 - sqrt(2) / 2) + r_45 * pi / 4,
               "135": (2 - sqrt(2)) + r_135 * 3 * pi / 4, "V90": sqrt(2) / 2 * pi / 2}
    assert {k: TURNS[k].cells for k in lengths} == pytest.approx(lengths)
    for name, cells in lengths.items():  # no lateral limit: the whole turn at 0.5 m/s
        assert turn_seconds(name, MOUSE) == pytest.approx(cells / 0.5)
    # lateral_accel 0.125: the 90s (r = 0.5 m) is run at sqrt(0.0625) = 0.25 m/s, plus (0.5-0.25)^2/(1*0.5) s
    tight = mouse_from_table("tight", {**ROUND, "run": {**ROUND["run"], "lateral_accel": 0.125}})
    assert turn_seconds("90s", tight) == pytest.approx((pi / 4) / 0.25 + 0.125)
    assert turn_seconds("45", tight) < turn_seconds("45", MOUSE) + 1  # wide turns barely slowed


def test_turn_shapes_are_all_rotations_mirrors_and_reversals_of_six():
    along, every = turn_shapes(False), turn_shapes(True)
    assert len(along) == 3 * 8 and len(every) == 3 * 8 + 2 * 16 + 8
    for shape in every:
        points = [(0, 0), *shape.offsets]
        assert all((x + y) % 2 == 1 for x, y in ((shape.x_parity + px, 1 - shape.x_parity + py) for px, py in points))
    assert {s.name for s in every} == {t.name for t in ALONG_TURNS + DIAGONAL_TURNS}


def test_fastest_path_is_not_the_fewest_cells_path():
    """A 12-cell zigzag (11 turns at 0.5 m/s) against a 16-cell ring of two long straights."""
    zigzag = [(0, 0)] + [c for i in range(6) for c in ((i, i + 1), (i + 1, i + 1))]
    ring = [(0, y) for y in range(8)] + [(x, 7) for x in range(1, 8)] + [(7, 6), (6, 6)]
    maze = corridor_maze(8, zigzag, (6, 6))
    for (x, y), (nx, ny) in zip(ring, ring[1:]):
        maze.set(x, y, STEP[(nx - x, ny - y)], False)
    fewest = [(c % 8, c // 8) for c in shortest_path(maze, pessimistic(maze))]
    assert fewest == zigzag
    by_cells = run_of_cells(maze, fewest, False, MOUSE)
    fastest = fastest_route(maze, pessimistic(maze), False, MOUSE)
    turn = (pi / 4) / 0.5
    # zigzag: half a cell from rest to 0.5 m/s (peak sqrt((1 + 0.25)/2)), then eleven 90s turns
    assert by_cells.seconds == pytest.approx(2 * sqrt(0.625) - 0.5 + 11 * turn)
    # ring: 6.5 cells from rest to 0.5 m/s (peak sqrt((13 + 0.25)/2)), 90s, 6 cells 0.5 -> 0.5 (peak 2.5), 90s, 90s
    assert fastest.sequence == "S6.5 R90s S6 R90s R90s"
    assert fastest.seconds == pytest.approx(2 * sqrt(6.625) - 0.5 + turn + 2 * (2.5 - 0.5) + 2 * turn)
    assert len(fastest.cells) - 1 == 16 > len(by_cells.cells) - 1 == 12


@pytest.mark.parametrize("diagonal", [False, True])
def test_every_move_of_a_real_route_costs_what_the_model_says(diagonal):
    maze = parse_maze(builtin_path("japan2019hef").read_text())
    mouse = load_mouse(None, maze.size)
    route = fastest_route(maze, pessimistic(maze), diagonal, mouse)
    run, cell = mouse.run, mouse.cell
    for i, move in enumerate(route.moves):
        kind, rest = move.token[0], move.token[1:]
        if kind in "SD" and i == 0:
            expected = straight_seconds(float(rest) * cell, 0, run.turn_speed, run.top_speed, run.accel)
        elif kind in "SD":
            top = run.top_speed if kind == "S" else run.diagonal_top_speed
            metres = move.cells * cell
            v_out = None if i == len(route.moves) - 1 else run.turn_speed
            expected = straight_seconds(metres, run.turn_speed, v_out, top, run.accel)
        else:
            expected = turn_seconds(rest, mouse)
        assert move.seconds == pytest.approx(expected), move.token
    assert route.seconds == pytest.approx(sum(m.seconds for m in route.moves))
    tokens = {m.token.lstrip("RL") for m in route.moves if m.token[0] in "RL"}
    assert tokens >= ({"90s", "45", "135", "V90"} if diagonal else {"90s", "90"})


def test_search_run_by_hand():
    # three cells north, turn back (stop, pivot, start), two cells south, east into a turn, one more cell
    trace = [(0, 0), (0, 1), (0, 2), (0, 3), (0, 2), (0, 1), (1, 1), (2, 1)]
    run = search_run(trace, MOUSE)
    assert (run.turns, run.pivots, run.stops) == (1, 1, 2)
    metres = 7 - (1 - pi / 4)  # 7 steps of a cell, one of them bent into a quarter circle
    # each of the 2 runs between stops: +speed/accel (half to get up to speed, half to stop)
    assert run.seconds == pytest.approx(metres / 0.5 + 2 * 0.5 / 1 + 2.0)


def test_builtin_mice_and_a_partial_file(tmp_path):
    table = builtin_table()
    assert set(table) == {"classic", "halfsize"}
    assert load_mouse(None, 16).name == "classic" and load_mouse(None, 32).name == "halfsize"
    faster = tmp_path / "fast.toml"
    faster.write_text("[run]\ntop_speed = 4.0\n")
    mouse = load_mouse(str(faster), 32)
    assert mouse.run.top_speed == 4.0 and mouse.cell == 0.09  # the rest from the half-size mouse


@pytest.mark.parametrize("text, message", [
    ("[run]\nturn_speed = 9.0\n", "must not exceed"),
    ("[run]\nturn_speed = 0.9\naccel = 1.0\n", "cannot reach turn_speed"),
    ("cell = -1\n", "positive number"),
    ("[run]\nspeed = 1\n", "unknown key 'speed'"),
    ("[run\n", "fast.toml"),
])
def test_bad_mouse_file_is_one_line_error(tmp_path, text, message):
    bad = tmp_path / "fast.toml"
    bad.write_text(text)
    with pytest.raises(MazeError, match=message):
        load_mouse(str(bad), 32)
    result = mazelog("path", "japan2009hef", "--objective", "time", "--timing", str(bad))
    assert result.exit_code == 1 and result.output.startswith("Error: ") and result.output.count("\n") == 1


numbers = st.one_of(st.floats(-1, 20), st.sampled_from([float("nan"), float("inf")]), st.integers(-1, 20),
                    st.booleans(), st.text(max_size=2))


def section(keys: list[str]):
    return st.one_of(st.fixed_dictionaries({}, optional={k: numbers for k in keys}), numbers)


@settings(max_examples=150, suppress_health_check=[HealthCheck.too_slow])
@given(st.fixed_dictionaries({}, optional={
    "cell": numbers, "search": section(["speed", "accel", "pivot_time", "x"]),
    "run": section(["accel", "top_speed", "diagonal_top_speed", "turn_speed", "lateral_accel"]), "other": numbers}))
def test_any_table_gives_a_mouse_or_a_maze_error(table):
    try:
        mouse = mouse_from_table("random", table)
    except MazeError:
        return
    assert mouse.run.turn_speed <= mouse.run.top_speed
