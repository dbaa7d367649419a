from pathlib import Path

import pytest

from maze import explorer
from maze.compare import compare
from maze.direction import DELTA, DIRECTIONS, EAST, SOUTH
from maze.errors import MazeError
from maze.explorer import SHORTEST_CLAIMED, STRATEGIES, explore
from maze.mazefile import parse_maze
from maze.restore import restore
from maze.wallrecord import WallRecord

SHARED_MAZES = Path(__file__).resolve().parents[1].parent / "shared" / "mazes"
CLASSIC = sorted((SHARED_MAZES / "classic").glob("*.txt"))[::8]  # five 16x16 mazes, spread over the years
needs_shared = pytest.mark.skipif(not CLASSIC, reason=f"shared mazes not found at {SHARED_MAZES}")

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


@needs_shared
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
    if strategy in SHORTEST_CLAIMED:
        assert r.shortest


@needs_shared
def test_closing_never_seals_the_mouse_in_or_cuts_off_the_goal(monkeypatch):
    from maze.stepmap import UNREACHED, optimistic, step_map

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


@needs_shared
def test_stopping_rule_and_closing_save_steps_over_full_exploration():
    for path in CLASSIC:
        truth = parse_maze(path.read_text())
        full = explore(truth, "full").steps
        assert explore(truth, "closing").steps <= full
        assert explore(truth, "closing-stop").steps < full
