"""Issue 19 and 20's mazelog cases, each as a new user met it: outputs that were inputs, an empty file read as a
log, a wrong size assumed silently, help that names a missing option, pictures with a stray line or cut text,
a doc command that needed a file nobody shipped."""

import os
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from maze.cli import wrap_title
from maze.direction import EAST, NORTH
from maze.files.builtin import builtin_path
from maze.log.restore import records_for
from maze.log.wallrecord import WallRecord, encode_log
from maze.model import Maze
from maze.outputs import atomic_open
from maze.pictures.render import COLOURS, text_width, title_width
from tests.helpers.commands import mazelog
from tests.helpers.paths import SCRIPTS


@pytest.fixture
def log(tmp_path: Path) -> Path:
    p = tmp_path / "run.bin"
    assert mazelog("explore", "alljapan-010-1989-fin", "--log", p).exit_code == 0
    return p


@pytest.mark.parametrize("args", [
    lambda log: ["replay", log, "--out", log],
    lambda log: ["replay", log, "--animate", log],
    lambda log: ["replay", log, "--format", "png", "--out", log],
    lambda log: ["replay", log, "--out", log.parent / "alias.bin"],  # a hard link to the log
    lambda log: ["replay", log, "--out", log.parent / "." / log.name],
    lambda log: ["path", log, "--maze", "alljapan-010-1989-fin", "--png", log],
])
def test_an_output_that_is_an_input_is_refused_and_the_input_kept(log: Path, args) -> None:
    os.link(log, log.parent / "alias.bin")
    before = log.read_bytes()
    r = mazelog(*args(log))
    assert r.exit_code == 1 and "refusing to overwrite it" in r.output, r.output
    assert log.read_bytes() == before


def test_explore_with_the_same_file_for_log_and_png(tmp_path: Path) -> None:
    x = tmp_path / "x"
    r = mazelog("explore", "minimaze", "--log", x, "--png", x)
    assert r.exit_code == 1 and "--log and --png are the same file" in r.output
    assert not x.exists()


def test_a_maze_file_given_as_the_log_is_not_overwritten(tmp_path: Path) -> None:
    maze = tmp_path / "m.txt"
    maze.write_text(builtin_path("minimaze").read_text())
    r = mazelog("explore", maze, "--log", maze)
    assert r.exit_code == 1 and "is the input MAZE" in r.output
    assert maze.read_text() == builtin_path("minimaze").read_text()


def test_outputs_appear_whole_or_not_at_all(tmp_path: Path) -> None:
    out = tmp_path / "out.bin"
    out.write_bytes(b"old")
    with pytest.raises(RuntimeError):
        with atomic_open(out) as fp:
            fp.write(b"half of the new")
            raise RuntimeError("disk full")
    assert out.read_bytes() == b"old" and os.listdir(tmp_path) == ["out.bin"]
    with atomic_open(out) as fp:
        fp.write(b"new")
    assert out.read_bytes() == b"new" and (out.stat().st_mode & 0o777) == 0o666 & ~_umask()


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_path_on_an_empty_file(tmp_path: Path) -> None:
    empty = tmp_path / "empty.bin"
    empty.write_bytes(b"")
    r = mazelog("path", empty)
    assert r.exit_code == 1
    assert r.output.strip() == f"Error: {empty}: empty file (neither a maze file nor a wall log with any record)"


def test_path_without_maze_says_what_it_assumed(tmp_path: Path) -> None:
    taiwan = Maze.unknown(21)
    for x, y, d in taiwan.inner_walls():
        if not taiwan.is_known(x, y, d):
            taiwan.set(x, y, d, False)
    log = tmp_path / "taiwan.bin"
    log.write_bytes(encode_log(records_for(taiwan)))
    r = mazelog("path", str(log))
    assert r.exit_code == 0
    assert "note: assumed 32x32 with the central goal, as no --maze or --size was given" in r.stderr
    assert "its records span only 21x21 cells: is it a 21x21 maze? (--size 21)" in r.stderr
    assert "(assumed)" in r.stdout
    told = mazelog("path", str(log), "--size", "21")
    assert told.exit_code == 0 and "note:" not in told.stderr and "21x21" in told.stdout


def test_path_refuses_a_log_outside_the_assumed_size(tmp_path: Path) -> None:
    log = tmp_path / "big.bin"
    log.write_bytes(encode_log([WallRecord(0, 1, NORTH, False), WallRecord(40, 3, EAST, True)]))
    r = mazelog("path", log)
    assert r.exit_code == 1
    assert ("record 1: cell (40, 3) is outside the 32x32 maze: not a log of a 32x32 maze; give --maze or --size"
            in r.output)


def test_info_help_names_only_its_own_options() -> None:
    r = mazelog("info", "-h")
    assert r.exit_code == 0 and "--maze" not in r.output


def test_version() -> None:
    r = mazelog("--version")
    assert r.exit_code == 0 and r.output.startswith("mazelog, version ")


@pytest.mark.parametrize("command", [
    ["show", "japan2019hef", "--png"],
    ["show", "alljapan-010-1989-fin", "--png"],
])
def test_no_stray_line_along_the_bottom_of_a_picture(tmp_path: Path, command: list[str]) -> None:
    png = tmp_path / "m.png"
    assert mazelog(*command, png).exit_code == 0
    pixels = np.array(Image.open(png).convert("RGB"))
    wall = np.all(pixels == COLOURS["wall"], axis=2)
    assert not wall[-4:].any()  # the legend's swatch is higher up; the last rows are margin


def test_path_png_keeps_every_move(tmp_path: Path) -> None:
    moves = mazelog("path", "japan2019hef")
    assert moves.exit_code == 0
    sequence = next(line for line in moves.output.splitlines() if line.startswith("moves:")).split(None, 1)[1]
    lines = wrap_title(sequence, 32)
    assert " ".join(lines) == sequence and len(lines) > 1
    assert all(text_width(line) <= title_width(32) for line in lines)
    png = tmp_path / "p.png"
    assert mazelog("path", "japan2019hef", "--png", png).exit_code == 0
    assert Image.open(png).height > 700  # the title grew by the extra lines


def test_the_doc_encode_command_works_in_an_empty_folder(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    r = mazelog("encode", "seed-log.txt", "seed.bin")
    assert r.exit_code == 0, r.output
    assert "30 records, 60 bytes -> seed.bin" in r.output
    info = mazelog("info", "--size", "4", "seed.bin")
    assert "known inner walls: 24 of 24" in info.output


def test_bench_search_says_where_its_mazes_come_from(tmp_path: Path) -> None:
    import subprocess
    import sys

    script = SCRIPTS / "benchmark_search.py"
    r = subprocess.run([sys.executable, script, "--mazes", tmp_path / "nothing"], capture_output=True, text=True)
    assert r.returncode == 1
    assert "micromouseonline/mazefiles at commit a71f846897fdd2193e726a1276c6774c9ce9ac67" in r.stderr
    assert "--builtin for the mazes shipped in the package" in r.stderr and "Traceback" not in r.stderr


def test_an_output_in_a_missing_folder_is_named_as_given(tmp_path: Path) -> None:
    out = tmp_path / "no" / "such" / "run.bin"
    r = mazelog("explore", "minimaze", "--log", out)
    assert r.exit_code == 1
    assert r.output.strip() == f"Error: {out}: cannot write there (No such file or directory)"
