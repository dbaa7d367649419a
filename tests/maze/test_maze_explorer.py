import pytest

from maze.direction import DELTA, DIRECTIONS, EAST, SOUTH
from maze.errors import MazeError
from maze.files.builtin import builtin_path
from maze.files.mazefile import parse_maze
from maze.log.restore import restore
from maze.log.wallrecord import WallRecord
from maze.scoring.compare import compare
from maze.search import explorer
from maze.search.explorer import explore
from maze.search.strategies import OPTIMAL_CLAIMED, STRATEGIES
from tests.maze.test_maze_builtin import builtin_maze_params, large_maze_params

# five built-in 16x16 mazes, spread over the years
CLASSIC = [builtin_path(n) for n in ("alljapan-001-1980", "alljapan-007-1986-pre", "alljapan-011-1990-exp-pre",
                                     "alljapan-014-1993-exp-pre", "alljapan-017-1996-exp-fin")]

TINY = """\
o---o---o
|       |
o   o   o
| S | G |
o---o---o
"""


def test_tiny_maze_by_hand():
    r = explore(parse_maze(TINY), "goal")
    assert r.trace == [(0, 0), (0, 1), (1, 1), (1, 0)]
    assert (r.steps, r.turns) == (3, 2)
    # entering (0,1) facing north it learns its east side; entering (1,1) facing east, its south side
    assert r.records == [WallRecord(0, 1, EAST, False), WallRecord(1, 1, SOUTH, False)]
    assert r.batches == [1, 1, 0]
    assert r.shortest


def test_start_cell_must_follow_the_contest_rule():
    with pytest.raises(MazeError, match="start cell"):
        explore(parse_maze(TINY.replace("| S |", "| S  ")), "goal")


@pytest.mark.parametrize("path", CLASSIC, ids=lambda p: p.name)
@pytest.mark.parametrize("strategy", list(STRATEGIES))
def test_search_invariants(path, strategy):
    truth = parse_maze(path.read_text())
    r = explore(truth, strategy)
    # the log replays to exactly what the mouse knows, and never disagrees with the maze
    replayed, contradictions = restore(r.records, truth.size)
    assert contradictions == 0 and replayed.same_walls(r.maze)
    assert compare(truth, replayed).wrong == []
    assert max(r.batches) <= 3 and sum(r.batches) == len(r.records)
    # the mouse moves one cell at a time, never through a wall
    assert r.steps == len(r.trace) - 1 == len(r.batches)
    for (x, y), (nx, ny) in zip(r.trace, r.trace[1:]):
        d = next(d for d in DIRECTIONS if DELTA[d] == (nx - x, ny - y))
        assert not truth.is_wall(x, y, d)
    ends_at = r.trace[-1]
    assert ends_at in truth.goals if strategy == "goal" else ends_at == truth.start
    if strategy in OPTIMAL_CLAIMED:
        assert r.shortest


def test_closing_never_seals_the_mouse_in_or_cuts_off_the_goal(monkeypatch):
    from maze.search.stepmap import UNREACHED, optimistic, step_map

    calls = []
    original = explorer.close_dead_ends

    def checked(maze, virtual, here, branch):
        closed = original(maze, virtual, here, branch)
        dist = step_map(maze.topo, optimistic(maze, virtual), [maze.cell_index(g) for g in maze.goals])
        assert dist[here] < UNREACHED and dist[maze.cell_index(maze.start)] < UNREACHED
        calls.append(len(closed))
        return closed

    monkeypatch.setattr(explorer, "close_dead_ends", checked)
    for path in CLASSIC:
        assert explore(parse_maze(path.read_text()), "closing").shortest
    assert sum(calls) > 0  # closing did happen, so the check above checked something


def test_stopping_rule_and_closing_save_steps_over_full_exploration():
    for path in CLASSIC:
        truth = parse_maze(path.read_text())
        full = explore(truth, "full").steps
        assert explore(truth, "closing").steps <= full
        assert explore(truth, "closing-stop").steps < full


# (steps, records) per strategy, as measured before the time objective was added (commit 756a4a1)
CELL_RESULTS = {
    "alljapan-001-1980": ((123, 253), (152, 291), (364, 426), (268, 382), (156, 296), (156, 296)),
    "alljapan-007-1986-pre": ((112, 234), (226, 273), (420, 472), (286, 356), (198, 244), (198, 244)),
    "alljapan-011-1990-exp-pre": ((154, 294), (260, 336), (434, 478), (338, 392), (260, 339), (260, 339)),
    "alljapan-014-1993-exp-pre": ((86, 203), (158, 296), (348, 464), (346, 462), (244, 375), (244, 375)),
    "alljapan-017-1996-exp-fin": ((81, 172), (192, 367), (432, 478), (402, 473), (336, 461), (336, 461)),
    "japan2009hef": ((131, 331), (244, 500), (866, 1327), (832, 1311), (252, 529), (252, 529)),
}


@pytest.mark.parametrize("name", list(CELL_RESULTS))
def test_cell_strategies_keep_their_results(name):
    truth = parse_maze(builtin_path(name).read_text())
    got = tuple((r.steps, len(r.records)) for r in (explore(truth, s) for s in STRATEGIES))
    assert got == CELL_RESULTS[name]


TIME_MAZES = CLASSIC + [builtin_path(n) for n in ("maze-train-10x5-a", "maze-train-10x5-b", "maze-train-10x5-empty",
                                                  "minimaze")]


@pytest.mark.parametrize("path", TIME_MAZES, ids=lambda p: p.stem)
@pytest.mark.parametrize("diagonal", [False, True], ids=["along", "diagonal"])
def test_time_stopping_rule_ends_knowing_a_time_optimal_run(path, diagonal):
    truth = parse_maze(path.read_text())
    r = explore(truth, "stop", "time", diagonal)
    assert r.fastest and r.found_route.seconds == pytest.approx(r.true_route.seconds, abs=1e-9)
    assert r.trace[-1] == truth.start
    replayed, contradictions = restore(r.records, truth.size)
    assert contradictions == 0 and replayed.same_walls(r.maze)
    assert r.search.seconds > 0 and r.search.stops >= 1


def test_the_time_rule_stops_short_of_a_full_search_on_a_32x32_maze():
    truth = parse_maze(builtin_path("japan2009hef").read_text())
    r = explore(truth, "stop", "time", True)
    full = explore(truth, "full", "time", True)
    assert r.fastest and full.fastest
    assert r.steps < 0.8 * full.steps and r.search.seconds < full.search.seconds


def test_dead_end_closing_does_not_change_the_time_rule():
    """Measured: a dead end lies on no route and on no shortest walk between cells outside it."""
    truth = parse_maze(builtin_path("alljapan-010-1989-fin").read_text())
    plain, closing = (explore(truth, s, "time", True) for s in ("stop", "closing-stop"))
    assert plain.trace == closing.trace


@pytest.mark.slow
@pytest.mark.parametrize("path", builtin_maze_params())
@pytest.mark.parametrize("diagonal", [False, True], ids=["along", "diagonal"])
def test_every_builtin_maze_time_optimal(path, diagonal):
    """Without ../shared too: the time rule stops only once its run is as fast as the full-knowledge optimum."""
    r = explore(parse_maze(path.read_text()), "stop", "time", diagonal)
    assert r.fastest and r.found_route.seconds == pytest.approx(r.true_route.seconds, abs=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize("path", large_maze_params())
def test_every_shared_maze_time_optimal_with_diagonals(path):
    truth = parse_maze(path.read_text())
    assert explore(truth, "stop", "time", True).fastest
