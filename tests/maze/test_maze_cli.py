import json
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from maze.cli import main
from maze.direction import NORTH
from maze.files.builtin import builtin_path
from maze.files.mazefile import dump_maze, parse_maze
from maze.log.restore import records_for
from maze.log.wallrecord import WallRecord, encode_log
from maze.model import Maze
from tests.helpers.commands import mazelog

CLASSIC = builtin_path("alljapan-001-1980")


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
    result = mazelog("replay", p, "--size", "8", "--format", fmt, *(["--strict"] if strict else []))
    assert no_traceback(result), result.output
    assert result.exit_code in (0, 1)
    if result.exit_code == 1:
        assert result.output.startswith("Error: corrupt log: record ")


def test_replay_formats(small_log, tmp_path):
    text = mazelog("replay", small_log, "--size", "4")
    assert text.exit_code == 0 and "records applied: 2 of 2 in the log;" in text.output
    mf = mazelog("replay", small_log, "--size", "4", "--format", "mazefile")
    maze = parse_maze(mf.output)
    assert maze.is_known(1, 0, NORTH) and maze.is_wall(1, 0, NORTH) and not maze.is_known(2, 2, 0)
    doc = json.loads(mazelog("replay", small_log, "--size", "4", "--format", "json").output)
    cell = next(c for c in doc["cells"] if (c["x"], c["y"]) == (1, 0))
    assert cell["N"] == "wall" and cell["E"] == "unknown"
    png = tmp_path / "out.png"
    assert mazelog("replay", small_log, "--format", "png", "--out", png).exit_code == 0
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_bad_options_are_one_line_errors(small_log):
    for args in (["--format", "png"], ["--until", "9"], ["--drop-last", "5"], ["--size", "65"],
                 ["--view", "3", "--format", "json"]):
        result = mazelog("replay", small_log, *args)
        assert result.exit_code == 2 or result.exit_code == 1, args
        assert no_traceback(result) and "Error" in result.output, args


def test_torn_log_is_refused_when_strict_and_warned_otherwise(tmp_path):
    p = tmp_path / "torn.bin"
    p.write_bytes(encode_log([WallRecord(0, 1, NORTH, False)] * 3)[:-1])
    strict = mazelog("replay", p, "--strict")
    assert strict.exit_code == 1 and "record 2: torn" in strict.output
    lenient = mazelog("info", p)
    assert lenient.exit_code == 0 and "record 2: torn" in lenient.output and "2 usable" in lenient.output


def test_encode_decode_round_trip(tmp_path):
    src = tmp_path / "log.txt"
    src.write_text("(0, 1, ^, false)\n(0, 1, >, true)\n(3, 0, <, false)\n")
    out = tmp_path / "log.bin"
    assert mazelog("encode", src, out).exit_code == 0
    assert out.stat().st_size == 6
    decoded = mazelog("decode", out).output
    back = tmp_path / "back.bin"
    mazelog("encode", "-", back, input=decoded.encode())
    assert back.read_bytes() == out.read_bytes()
    src.write_text("(0, 1, ^, false)\n(0, 1, sideways, true)\n")
    bad = mazelog("encode", src, out)
    assert bad.exit_code == 1 and "line 2" in bad.output


def test_diff_counts_right_wrong_unknown(tmp_path):
    truth = parse_maze(CLASSIC.read_text())
    recs = records_for(truth)
    x, y, d = recs[5].x, recs[5].y, recs[5].d
    recs[5] = WallRecord(x, y, d, not recs[5].wall)  # one misread (not of the start cell, known from reset)
    log = tmp_path / "log.bin"
    log.write_bytes(encode_log(recs[:-10]))  # and ten walls never seen
    out = mazelog("diff", CLASSIC, log).output
    assert "right:   469" in out and "wrong:   1" in out and "unknown: 10" in out
    assert f"({x}, {y})" in out


def test_show_reports_malformed_file_with_line(tmp_path):
    p = tmp_path / "bad.txt"
    p.write_text(dump_maze(Maze.unknown(4)).replace("o---o", "o-x-o", 1))
    result = mazelog("show", p)
    assert result.exit_code == 1 and "line 1" in result.output and no_traceback(result)
    p.write_text(dump_maze(Maze.unknown(4)))
    assert "4x4, start (0, 0)" in mazelog("show", p).output


def test_every_command_has_help():
    for cmd in [[], *[[name] for name in main.commands]]:
        result = mazelog(*cmd, "--help")
        assert result.exit_code == 0 and "Usage" in result.output


def test_explore_writes_log_png_and_report(tmp_path):
    maze = tmp_path / "tiny.txt"
    maze.write_text("o---o---o\n|       |\no   o   o\n| S | G |\no---o---o\n")
    log, png = tmp_path / "run.bin", tmp_path / "run.png"
    result = mazelog("explore", maze, "--strategy", "goal", "--log", log, "--png", png)
    assert result.exit_code == 0, result.output
    assert "steps:         3" in result.output and "found 3, true 3: yes" in result.output
    assert log.stat().st_size == 4 and png.read_bytes()[:4] == b"\x89PNG"
    replayed = mazelog("replay", log, "--size", "2", "--format", "mazefile")
    assert parse_maze(replayed.stdout).same_walls(parse_maze(maze.read_text()))
    assert mazelog("explore", maze, "--log", log, "--goal", "5,5").exit_code == 2


# -- issue 8: what a new user meets ---------------------------------------------------------------------------

def test_text_commands_load_no_drawing_or_numeric_libraries():
    """Start-up: `mazelog --help` and a text replay took 1.2 s, almost all of it importing matplotlib."""
    code = ("import sys; from maze.cli import main\n"
            "try:\n    main(['--help'])\nexcept SystemExit:\n    pass\n"
            "print(sorted(m for m in ('matplotlib', 'PIL', 'numpy', 'scipy') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip().endswith("[]")


def test_replay_counts_every_record_of_the_log(tmp_path):
    """It said 'records applied: 1 of 1' for a log of 2 records, one of them anomalous."""
    log = tmp_path / "two.bin"
    log.write_bytes(encode_log([WallRecord(0, 1, NORTH, False), WallRecord(9, 0, NORTH, True)]))
    result = mazelog("replay", log, "--size", "4")
    assert "records applied: 1 of 2 in the log (1 skipped as anomalous);" in result.stdout
    torn = tmp_path / "torn.bin"
    torn.write_bytes(encode_log([WallRecord(0, 1, NORTH, False)] * 5)[:-1])
    result = mazelog("replay", torn, "--size", "4", "--drop-last", "2", "--until", "1")
    assert ("records applied: 1 of 5 in the log (1 skipped as anomalous, 2 rolled back, 1 later ones not applied);"
            in result.stdout)
    assert "1 usable of 2" in mazelog("info", log, "--size", "4").output


@pytest.mark.parametrize("fmt", ["text", "json", "mazefile"])
def test_replay_of_an_empty_log_says_so_in_one_note(tmp_path, fmt):
    """It exited 0 with an all-unknown maze and said nothing, in any format."""
    log = tmp_path / "empty.bin"
    log.write_bytes(b"")
    result = mazelog("replay", log, "--size", "4", "--format", fmt)
    assert result.exit_code == 0, result.output
    assert result.stderr.splitlines() == [f"note: {log} holds no records: the maze shown is all unknown"]


def test_power_cut_reports_what_was_written(tmp_path):
    """It reported the full log (388 records, 776 bytes) when the flash image held 1 record."""
    log = tmp_path / "cut.bin"
    result = mazelog("explore", CLASSIC, "--log", log, "--power-cut", "3")
    assert result.exit_code == 0, result.output
    line = next(ln for ln in result.output.splitlines() if ln.startswith("wall log:"))
    assert "1 of " in line and "records written before the power cut at byte 3 and 1 byte of the next" in line
    assert f"flash image {log.stat().st_size} bytes" in line
    replayed = mazelog("replay", log, "--size", "16").stdout
    assert "records applied: 1 of 2 in the log (1 skipped as anomalous)" in replayed


def test_explore_png_is_readable_and_has_a_legend(tmp_path):
    """The picture was 6 inches at 110 dpi, squeezed by a tight bounding box, with no legend for its colours."""
    from PIL import Image

    from maze.pictures.render import COLOURS

    png = tmp_path / "run.png"
    explored = mazelog("explore", CLASSIC, "--log", tmp_path / "run.bin", "--png", png, "--strategy", "closing")
    assert explored.exit_code == 0
    image = Image.open(png)
    assert image.width >= 600 and image.height >= image.width
    legend = [image.getpixel((x, y)) for y in range(image.height - 60, image.height) for x in range(image.width)]
    colours = {tuple(image.getpalette()[3 * i: 3 * i + 3]) for i in set(legend)}
    assert {COLOURS[k] for k in ("wall", "virtual", "visited", "goal", "path", "text")} <= colours


@pytest.mark.parametrize("args, message", [
    (["path", "nosuch"], "neither a file nor a built-in maze"),
    (["path", "japan2009hef", "--size", "32"], "--size and --maze are for a wall log"),
    (["path", "x.bin", "--maze", "japan2009hef", "--size", "16"], "but the maze is 32x32"),
    (["explore", "minimaze", "--log", "x.bin", "--goal", "9,9"], "cannot reach"),
    (["explore", "japan2009hef", "--log", "x.bin", "--timing", "nosuch.toml"], "no such mouse file"),
    (["replay", "x.bin", "--maze", "japan2009hef", "--size", "16"], "but the maze is 32x32"),
])
def test_bad_input_is_one_line(tmp_path, monkeypatch, args, message):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "x.bin").write_bytes(b"\x00\x10")
    result = mazelog(*args)
    assert result.exit_code in (1, 2) and message in result.output and "Traceback" not in result.output
    assert result.output.startswith(("Error", "Usage"))


def test_path_of_a_log_and_of_a_maze_file(tmp_path):
    log = tmp_path / "run.bin"
    mazelog("explore", CLASSIC, "--log", log, "--objective", "time", "--diagonal")
    png = tmp_path / "path.png"
    from_log = mazelog("path", log, "--maze", CLASSIC, "--objective", "time", "--diagonal", "--png", png)
    from_maze = mazelog("path", CLASSIC, "--objective", "time", "--diagonal")
    assert from_log.exit_code == from_maze.exit_code == 0, from_log.output
    times = [next(ln for ln in r.output.splitlines() if ln.startswith("time:")) for r in (from_log, from_maze)]
    assert times[0] == times[1]  # the search found the time-optimal path
    assert "moves:     S" in from_log.output and png.read_bytes()[:4] == b"\x89PNG"
    cells = mazelog("path", CLASSIC)
    assert "objective: cells" in cells.output and "length:    " in cells.output


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.one_of(st.binary(max_size=120), st.text(alphabet="o+-| .SG\n", max_size=120).map(str.encode)))
def test_path_of_any_file_is_a_path_or_a_one_line_error(tmp_path, data):
    p = tmp_path / "random"
    p.write_bytes(data)
    result = mazelog("path", p, *(["--size", "4"] if data[:1] not in (b"o", b"+") else []))
    assert no_traceback(result), result.output
    last = result.output.splitlines()[-1]  # warnings about anomalous records may come first
    assert result.exit_code in (0, 1) and (result.exit_code == 0 or last.startswith("Error: "))
