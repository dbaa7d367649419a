import pytest
from click.testing import CliRunner

from maze.cli import main
from maze.errors import MazeError
from maze.files.builtin import builtin_path
from maze.files.mazefile import parse_maze
from maze.log.flash import (
    SCHEMES,
    NorFlash,
    PowerCut,
    compare_schemes,
    inner_wall_ids,
    log_sectors,
    log_writes,
    pack_snapshot,
    run_writes,
    snapshot_bytes,
    unpack_snapshot,
)
from maze.log.restore import load_log, restore
from maze.search.explorer import explore

CLASSIC = builtin_path("alljapan-010-1989-fin")


@pytest.fixture(scope="module")
def search():
    return explore(parse_maze(CLASSIC.read_text()), "stop")


def test_nor_rules():
    f = NorFlash(1, budget=4)
    assert f.data[:4] == b"\xff" * 4
    f.program(0, b"\x0f\xf0")
    with pytest.raises(MazeError, match="erase first"):
        f.program(0, b"\xff")  # 0x0f -> 0xff would set bits
    f.program(0, b"\x03")  # clearing more bits is fine
    with pytest.raises(PowerCut):
        f.program(2, b"\x00\x00")
    assert f.data[:4] == b"\x03\xf0\x00\xff" and f.programmed == 4
    f.erase(0)
    assert f.data[:4] == b"\xff" * 4 and f.erases == [1]


def test_snapshot_size_is_the_seeds_minimal_representation():
    # seed table, column 最小表現: N*(N-1)/2 bytes
    assert [snapshot_bytes(n) for n in (8, 16, 32)] == [28, 120, 496]


def test_snapshot_round_trip(search):
    data = pack_snapshot(search.maze, inner_wall_ids(search.maze))
    assert len(data) == snapshot_bytes(search.maze.size)
    assert unpack_snapshot(data, search.maze.size).same_walls(search.maze)


def test_power_cut_at_every_byte_loses_only_the_record_being_written(search):
    writes = log_writes(search)
    total = sum(len(w.payload) for w in writes)
    assert total == 2 * len(search.records)
    size = search.maze.size
    for cut in range(total + 1):
        flash, _ = run_writes(writes, log_sectors(size), cut)
        loaded = load_log(bytes(flash.data), size)
        assert len(loaded.anomalies) == cut % 2  # only a torn record, never anything else
        maze, _ = restore(loaded.records, size)
        assert maze.same_walls(restore(search.records[: cut // 2], size)[0]), cut


def test_replay_cli_restores_a_power_cut_image(tmp_path, search):
    log = tmp_path / "cut.bin"
    runner = CliRunner()
    for cut in (0, 1, 77, 2 * len(search.records) - 1):
        out = runner.invoke(main, ["explore", str(CLASSIC), "--strategy", "stop", "--log", str(log),
                                   "--power-cut", str(cut)])
        assert out.exit_code == 0, out.output
        replay = runner.invoke(main, ["replay", str(log), "--size", "16", "--format", "mazefile"])
        assert replay.exit_code == 0
        expected = restore(search.records[: cut // 2], 16)[0]
        assert ("torn record" in replay.stderr) == bool(cut % 2)
        assert parse_maze(replay.stdout).same_walls(expected)


def test_scheme_comparison(search):
    reports = {r.name: r for r in compare_schemes(search, cuts=60)}
    log, single, double = (reports[name] for name in SCHEMES)
    assert log.bytes_written == 2 * len(search.records)
    assert log.erases == log_sectors(16) == log.max_sector_erases
    assert single.erases == single.writes == log.writes
    assert double.max_sector_erases == (double.writes + 1) // 2
    assert max(log.lost) <= 3 and max(double.lost) <= 3
    assert single.mean_lost > 10 * log.mean_lost  # a cut between erase and commit loses the whole map
