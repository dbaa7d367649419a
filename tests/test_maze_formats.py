"""mms's .num and the 256-byte .maz maze formats: read, written back, and refused with one line when wrong."""

from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from maze.builtin import builtin_path
from maze.cli import main
from maze.direction import EAST
from maze.errors import MazeError
from maze.mazefile import parse_maze
from maze.mazeformats import MAZ_BYTES, dump_maz, dump_num, parse_maz, parse_num
from maze.model import Maze


def random_maze(size: int, walls: list[bool]) -> Maze:
    maze = Maze(size)
    for (x, y, d), wall in zip(maze.inner_walls(), walls):
        maze.set(x, y, d, wall)
    return maze


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 20).flatmap(lambda n: st.tuples(st.just(n), st.lists(st.booleans(), min_size=2 * n * n,
                                                                             max_size=2 * n * n))))
def test_num_round_trips(case: tuple[int, list[bool]]) -> None:
    maze = random_maze(*case)
    assert parse_num(dump_num(maze)).same_walls(maze)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.booleans(), min_size=2 * 256, max_size=2 * 256))
def test_maz_round_trips(walls: list[bool]) -> None:
    maze = random_maze(16, walls)
    assert parse_maz(dump_maz(maze)).same_walls(maze)


@given(st.binary(max_size=300))
def test_any_bytes_read_as_maz_or_refused(data: bytes) -> None:
    try:
        maze = parse_maz(data)
    except MazeError as e:
        assert len(data) != MAZ_BYTES and "256 bytes" in str(e)
        return
    assert maze.size == 16


@given(st.text(alphabet="0123456789 -\nx", max_size=200))
def test_any_text_read_as_num_or_refused_naming_a_line(text: str) -> None:
    try:
        parse_num(text)
    except MazeError as e:
        assert str(e).startswith("line ") or "square maze" in str(e)


def test_a_real_maze_survives_both_formats(tmp_path: Path) -> None:
    truth = parse_maze(builtin_path("alljapan-010-1989-fin").read_text())
    for suffix in (".maz", ".num"):
        out = tmp_path / f"m{suffix}"
        r = CliRunner().invoke(main, ["show", "alljapan-010-1989-fin", "--out", str(out)])
        assert r.exit_code == 0, r.output
        back = CliRunner().invoke(main, ["show", str(out)])
        assert back.exit_code == 0 and back.output.splitlines()[-1] == r.output.splitlines()[-1]
        assert (parse_maz(out.read_bytes()) if suffix == ".maz" else parse_num(out.read_text())).same_walls(truth)


@pytest.mark.parametrize("size", [0, 255, 257, 1024])
def test_a_maz_file_of_the_wrong_size_is_one_line(tmp_path: Path, size: int) -> None:
    bad = tmp_path / "bad.maz"
    bad.write_bytes(bytes(size))
    r = CliRunner().invoke(main, ["explore", str(bad), "--log", str(tmp_path / "x.bin")])
    assert r.exit_code == 1
    assert r.output.strip() == f"Error: {bad}: a .maz file is 256 bytes (16x16, one per cell), this one is {size}"


def test_num_mazes_of_other_sizes_explore(tmp_path: Path) -> None:
    maze = random_maze(21, [False] * (2 * 21 * 21))  # Taiwan's size, all open inside but the start cell
    maze.set(0, 0, EAST, True)
    f = tmp_path / "taiwan.num"
    f.write_text(dump_num(maze))
    r = CliRunner().invoke(main, ["explore", str(f), "--log", str(tmp_path / "t.bin")])
    assert r.exit_code == 0 and "cells visited" in r.output and "of 441" in r.output
