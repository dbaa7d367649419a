import re

import pytest

from athrill_sim.programs.third_party import SEEDS
from maze.direction import EAST, NORTH, SOUTH
from maze.errors import MazeError
from maze.files.mazefile import dump_maze, parse_maze
from maze.log.restore import apply_records, load_log, records_for, restore, select
from maze.log.wallrecord import RECORD_BYTES, WallRecord, encode_log, parse_text_records
from maze.model import Maze, inner_wall_count
from tests.helpers.paths import SHARED, needs_shared
from tests.maze.test_maze_builtin import builtin_maze_params, large_maze_params

SEED = SHARED / "seeds" / "wall-log-backup.md"
needs_seed = pytest.mark.skipif(
    not SEED.is_file(), reason=needs_shared("the seed's worked example", SEED, SEEDS))


def seed_blocks() -> list[str]:
    """The seed's code blocks: [true 4x4 maze, its 30-record log, the all-unknown maze, the C++ union]."""
    return re.findall(r"```\n(.*?)```", SEED.read_text(encoding="utf-8"), re.S)


@needs_seed
def test_seed_example_log_is_30_records_60_bytes():
    records = parse_text_records(seed_blocks()[1])
    assert len(records) == 30
    assert len(encode_log(records)) == 30 * RECORD_BYTES


@needs_seed
def test_seed_log_replays_to_the_seed_maze_in_the_corner_of_a_32x32():
    true_maze, log_text, unknown_picture = seed_blocks()[:3]
    loaded = load_log(encode_log(parse_text_records(log_text)), 32)
    assert loaded.anomalies == []
    before, _ = restore([], 32, goals=((1, 0),))
    assert dump_maze(before, post="+", extent=4) == unknown_picture
    after, contradictions = restore(loaded.records, 32, goals=((1, 0),))
    assert contradictions == 0
    assert dump_maze(after, post="+", extent=4) == true_maze
    # everything outside the 4x4 corner is still unknown
    assert after.known_inner() == before.known_inner() + 30


@needs_seed
def test_seed_log_on_a_4x4_maze_is_the_whole_maze():
    true_maze, log_text = seed_blocks()[:2]
    maze, _ = restore(parse_text_records(log_text), 4, goals=((1, 0),))
    assert maze.same_walls(parse_maze(true_maze))


def test_contradiction_makes_the_wall_unknown_again():
    maze = Maze.unknown(4)
    n = apply_records(maze, [WallRecord(1, 1, NORTH, True), WallRecord(1, 2, SOUTH, False)])
    assert n == 1
    assert not maze.is_known(1, 1, NORTH)
    # a third sighting makes it known again
    apply_records(maze, [WallRecord(1, 1, NORTH, False)])
    assert maze.is_known(1, 1, NORTH) and not maze.is_wall(1, 1, NORTH)


def test_start_cell_and_outer_walls_are_known_at_reset():
    maze = Maze.unknown(8)
    assert maze.is_known(0, 0, EAST) and maze.is_wall(0, 0, EAST)
    assert maze.is_known(0, 0, NORTH) and not maze.is_wall(0, 0, NORTH)
    assert maze.known_inner() == 2
    assert all(maze.is_known(7, y, EAST) for y in range(8))


def test_drop_last_undoes_exactly_the_last_records():
    recs = [WallRecord(1, 1, NORTH, True), WallRecord(2, 1, EAST, False), WallRecord(1, 1, NORTH, False)]
    maze, _ = restore(select(recs, drop_last=1), 4)
    assert maze.is_known(1, 1, NORTH) and maze.is_wall(1, 1, NORTH)
    maze, _ = restore(select(recs, drop_last=2), 4)
    assert not maze.is_known(2, 1, EAST)
    assert select(recs, until=2, drop_last=1) == recs[:2]
    with pytest.raises(MazeError):
        select(recs, until=3, drop_last=1)
    with pytest.raises(MazeError):
        select(recs, drop_last=4)


def test_size_dependent_anomalies_skip_or_refuse():
    data = encode_log([WallRecord(5, 0, NORTH, True), WallRecord(3, 3, EAST, False), WallRecord(1, 1, EAST, True)])
    loaded = load_log(data, 4)
    assert [a.index for a in loaded.anomalies] == [0, 1]
    assert loaded.records == [WallRecord(1, 1, EAST, True)]
    with pytest.raises(MazeError, match="record 0"):
        load_log(data, 4, strict=True)


@pytest.mark.parametrize("path", builtin_maze_params() + large_maze_params())
def test_full_log_of_every_real_maze_restores_it_exactly(path):
    truth = parse_maze(path.read_text())
    data = encode_log(records_for(truth))
    n = truth.size
    assert len(data) // RECORD_BYTES == inner_wall_count(n) == n * (n - 1) * 2
    loaded = load_log(data, n, strict=True)
    maze, contradictions = restore(loaded.records, n)
    assert contradictions == 0
    assert maze.same_walls(truth)
