"""mms's .num and the 256-byte .maz maze formats: read, written back, and refused with one line when wrong."""

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maze.direction import EAST
from maze.errors import MazeError
from maze.files.builtin import builtin_path
from maze.files.mazefile import parse_maze
from maze.files.mazeformats import MAZ_BYTES, dump_maz, dump_num, parse_maz, parse_num
from maze.model import Maze
from tests.helpers.commands import mazelog


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
        r = mazelog("show", "alljapan-010-1989-fin", "--out", str(out))
        assert r.exit_code == 0, r.output
        back = mazelog("show", str(out))
        assert back.exit_code == 0 and back.output.splitlines()[-1] == r.output.splitlines()[-1]
        assert (parse_maz(out.read_bytes()) if suffix == ".maz" else parse_num(out.read_text())).same_walls(truth)


@pytest.mark.parametrize("size", [0, 255, 257, 1024])
def test_a_maz_file_of_the_wrong_size_is_one_line(tmp_path: Path, size: int) -> None:
    bad = tmp_path / "bad.maz"
    bad.write_bytes(bytes(size))
    r = mazelog("explore", str(bad), "--log", str(tmp_path / "x.bin"))
    assert r.exit_code == 1
    assert r.output.strip() == f"Error: {bad}: a .maz file is 256 bytes (16x16, one per cell), this one is {size}"


def test_num_mazes_of_other_sizes_explore(tmp_path: Path) -> None:
    maze = random_maze(21, [False] * (2 * 21 * 21))  # Taiwan's size, all open inside but the start cell
    maze.set(0, 0, EAST, True)
    f = tmp_path / "taiwan.num"
    f.write_text(dump_num(maze))
    r = mazelog("explore", str(f), "--log", str(tmp_path / "t.bin"))
    assert r.exit_code == 0 and "cells visited" in r.output and "of 441" in r.output


def marked_sides_of_maz(data: bytes) -> set[tuple[int, int, int]]:
    """The inner sides each byte marks, read straight from the format's definition (bits 1 N, 2 E, 4 S, 8 W)."""
    from maze.direction import NORTH, SOUTH, WEST

    sides = set()
    for i, byte in enumerate(data):
        x, y = divmod(i, 16)
        for bit, d, inner in ((1, NORTH, y < 15), (2, EAST, x < 15), (4, SOUTH, y > 0), (8, WEST, x > 0)):
            if byte & bit and inner:
                sides.add((x, y, d))
    return sides


def disagreeing_pairs(sides: set[tuple[int, int, int]], size: int) -> int:
    from maze.direction import NORTH

    count = 0
    for x in range(size):
        for y in range(size):
            if x < size - 1:
                count += ((x, y, EAST) in sides) != ((x + 1, y, EAST + 4) in sides)
            if y < size - 1:
                count += ((x, y, NORTH) in sides) != ((x, y + 1, NORTH + 4) in sides)
    return count


@settings(max_examples=60, deadline=None)
@given(st.binary(min_size=MAZ_BYTES, max_size=MAZ_BYTES))
def test_a_maz_whose_cells_disagree_is_a_warning_or_with_strict_an_error(data: bytes) -> None:
    sides = marked_sides_of_maz(data)
    expected = disagreeing_pairs(sides, 16)
    warnings: list[str] = []
    maze = parse_maz(data, warn=warnings.append)
    for x, y, d in maze.inner_walls():  # a wall either side marks is a wall
        dx, dy = (1, 0) if d == EAST else (0, 1)
        assert maze.is_wall(x, y, d) == ((x, y, d) in sides or (x + dx, y + dy, d + 4) in sides)
    if expected == 0:
        assert warnings == [] and parse_maz(data, strict=True).same_walls(maze)
        return
    (warning,) = warnings
    assert warning.startswith(f"{expected} wall{'s' * (expected > 1)} marked by one of")
    with pytest.raises(MazeError, match="refused with --strict"):
        parse_maz(data, strict=True)


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 12).flatmap(lambda n: st.tuples(st.just(n), st.lists(st.booleans(), min_size=2 * n * n,
                                                                             max_size=2 * n * n))),
       st.data())
def test_a_num_with_one_cleared_side_is_warned_about_that_wall(case: tuple[int, list[bool]], data) -> None:
    maze = random_maze(*case)
    text = dump_num(maze)
    assert parse_num(text, strict=True).same_walls(maze)  # what we write is consistent
    walls = [(x, y, d) for x, y, d in maze.inner_walls() if maze.is_wall(x, y, d)]
    if not walls:
        return
    x, y, d = data.draw(st.sampled_from(walls))
    column = 2 + (1 if d == EAST else 0)  # X Y N E S W: this cell's side of the wall, cleared
    lines = text.splitlines()
    row = x * maze.size + y
    words = lines[row].split()
    words[column] = "0"
    lines[row] = " ".join(words)
    damaged = "\n".join(lines) + "\n"
    warnings: list[str] = []
    assert parse_num(damaged, warn=warnings.append).same_walls(maze)  # still a wall: the other side marks it
    other = f"cell ({x + (d == EAST)}, {y + (d != EAST)})"
    assert warnings == [f"1 wall marked by one of its two cells only (first: {other} marks its "
                        f"{'west' if d == EAST else 'south'} wall, cell ({x}, {y}) not its "
                        f"{'east' if d == EAST else 'north'} wall): taken as walls"]
    with pytest.raises(MazeError, match="refused with --strict"):
        parse_num(damaged, strict=True)


def test_show_warns_about_a_maz_whose_cells_disagree_and_strict_refuses_it(tmp_path: Path) -> None:
    data = bytearray(MAZ_BYTES)
    data[0] = 2  # cell (0, 0) marks its east wall; cell (1, 0) does not mark its west one
    bad = tmp_path / "bad.maz"
    bad.write_bytes(bytes(data))
    r = mazelog("show", str(bad))
    assert r.exit_code == 0
    assert (f"warning: {bad}: 1 wall marked by one of its two cells only (first: cell (0, 0) marks its east wall, "
            f"cell (1, 0) not its west wall): taken as walls") in r.stderr
    strict = mazelog("show", str(bad), "--strict")
    assert strict.exit_code == 1
    assert strict.output.strip().startswith(f"Error: {bad}: 1 wall marked by one of its two cells only")
