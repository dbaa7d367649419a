import json
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from maze.cli import main
from maze.direction import NORTH
from maze.mazefile import dump_maze, parse_maze
from maze.model import Maze
from maze.restore import records_for
from maze.wallrecord import WallRecord, encode_log

SHARED_MAZES = Path(__file__).resolve().parents[1].parent / "shared" / "mazes"
CLASSIC = SHARED_MAZES / "classic" / "alljapan-001-1980.txt"
needs_classic = pytest.mark.skipif(not CLASSIC.is_file(), reason=f"shared mazes not found at {SHARED_MAZES}")


def run(*args: str, input: bytes | None = None):
    return CliRunner().invoke(main, [str(a) for a in args], input=input)


def no_traceback(result) -> bool:
    return result.exception is None or isinstance(result.exception, SystemExit)


@pytest.fixture
def small_log(tmp_path: Path) -> Path:
    p = tmp_path / "small.bin"
    p.write_bytes(encode_log([WallRecord(0, 1, NORTH, False), WallRecord(1, 0, NORTH, True)]))
    return p


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.binary(max_size=200), strict=st.booleans(), fmt=st.sampled_from(["text", "json", "mazefile"]))
def test_random_bytes_never_crash_replay(tmp_path, data, strict, fmt):
    p = tmp_path / "random.bin"
    p.write_bytes(data)
    result = run("replay", p, "--size", "8", "--format", fmt, *(["--strict"] if strict else []))
    assert no_traceback(result), result.output
    assert result.exit_code in (0, 1)
    if result.exit_code == 1:
        assert result.output.startswith("Error: corrupt log: record ")


def test_replay_formats(small_log, tmp_path):
    text = run("replay", small_log, "--size", "4")
    assert text.exit_code == 0 and "records applied: 2 of 2" in text.output
    mf = run("replay", small_log, "--size", "4", "--format", "mazefile")
    maze = parse_maze(mf.output)
    assert maze.is_known(1, 0, NORTH) and maze.is_wall(1, 0, NORTH) and not maze.is_known(2, 2, 0)
    doc = json.loads(run("replay", small_log, "--size", "4", "--format", "json").output)
    cell = next(c for c in doc["cells"] if (c["x"], c["y"]) == (1, 0))
    assert cell["N"] == "wall" and cell["E"] == "unknown"
    png = tmp_path / "out.png"
    assert run("replay", small_log, "--format", "png", "--out", png).exit_code == 0
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_bad_options_are_one_line_errors(small_log):
    for args in (["--format", "png"], ["--until", "9"], ["--drop-last", "5"], ["--size", "65"], ["--view", "3", "--format", "json"]):
        result = run("replay", small_log, *args)
        assert result.exit_code == 2 or result.exit_code == 1, args
        assert no_traceback(result) and "Error" in result.output, args


def test_torn_log_is_refused_when_strict_and_warned_otherwise(tmp_path):
    p = tmp_path / "torn.bin"
    p.write_bytes(encode_log([WallRecord(0, 1, NORTH, False)] * 3)[:-1])
    strict = run("replay", p, "--strict")
    assert strict.exit_code == 1 and "record 2: torn" in strict.output
    lenient = run("info", p)
    assert lenient.exit_code == 0 and "record 2: torn" in lenient.output and "2 usable" in lenient.output


def test_encode_decode_round_trip(tmp_path):
    src = tmp_path / "log.txt"
    src.write_text("(0, 1, ^, false)\n(0, 1, >, true)\n(3, 0, <, false)\n")
    out = tmp_path / "log.bin"
    assert run("encode", src, out).exit_code == 0
    assert out.stat().st_size == 6
    decoded = run("decode", out).output
    back = tmp_path / "back.bin"
    run("encode", "-", back, input=decoded.encode())
    assert back.read_bytes() == out.read_bytes()
    src.write_text("(0, 1, ^, false)\n(0, 1, sideways, true)\n")
    bad = run("encode", src, out)
    assert bad.exit_code == 1 and "line 2" in bad.output


@needs_classic
def test_diff_counts_right_wrong_unknown(tmp_path):
    truth = parse_maze(CLASSIC.read_text())
    recs = records_for(truth)
    x, y, d = recs[5].x, recs[5].y, recs[5].d
    recs[5] = WallRecord(x, y, d, not recs[5].wall)  # one misread (not of the start cell, known from reset)
    log = tmp_path / "log.bin"
    log.write_bytes(encode_log(recs[:-10]))  # and ten walls never seen
    out = run("diff", CLASSIC, log).output
    assert "right:   469" in out and "wrong:   1" in out and "unknown: 10" in out
    assert f"({x}, {y})" in out


def test_show_reports_malformed_file_with_line(tmp_path):
    p = tmp_path / "bad.txt"
    p.write_text(dump_maze(Maze.unknown(4)).replace("o---o", "o-x-o", 1))
    result = run("show", p)
    assert result.exit_code == 1 and "line 1" in result.output and no_traceback(result)
    p.write_text(dump_maze(Maze.unknown(4)))
    assert "4x4, start (0, 0)" in run("show", p).output


def test_every_command_has_help():
    for cmd in [[], *[[name] for name in main.commands]]:
        result = run(*cmd, "--help")
        assert result.exit_code == 0 and "Usage" in result.output


def test_explore_writes_log_png_and_report(tmp_path):
    maze = tmp_path / "tiny.txt"
    maze.write_text("o---o---o\n|       |\no   o   o\n| S | G |\no---o---o\n")
    log, png = tmp_path / "run.bin", tmp_path / "run.png"
    result = run("explore", maze, "--strategy", "goal", "--log", log, "--png", png)
    assert result.exit_code == 0, result.output
    assert "steps:         3" in result.output and "found 3, true 3: yes" in result.output
    assert log.stat().st_size == 4 and png.read_bytes()[:4] == b"\x89PNG"
    replayed = run("replay", log, "--size", "2", "--format", "mazefile")
    assert parse_maze(replayed.stdout).same_walls(parse_maze(maze.read_text()))
    assert run("explore", maze, "--log", log, "--goal", "5,5").exit_code == 2
