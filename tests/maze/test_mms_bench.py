"""`mazelog bench`: mice and built-in strategies over many mazes, one CSV row per run and a summary."""

import csv
import sys
from pathlib import Path

import pytest

from maze.files.builtin import builtin_names, builtin_path
from maze.files.mazefile import parse_maze
from maze.mouse.mms import parse_command
from maze.mouse.mmsworld import MmsWorld
from maze.scoring.benchmark import commands_for
from maze.search.explorer import explore
from maze.timing.mouseparams import load_mouse
from tests.helpers.commands import mazelog
from tests.helpers.paths import MICE

FLOODFILL = f"{sys.executable} {MICE / 'floodfill.py'}"


def bench(tmp_path: Path, *mazes: Path):
    out = tmp_path / "bench"
    r = mazelog("bench", *map(str, mazes), "--strategy", "stop", "--strategy", "full",
                "--mouse", FLOODFILL, "--jobs", "2", "--out", str(out))
    assert r.exit_code == 0, r.output
    with open(out / "results.csv") as fp:
        rows = list(csv.DictReader(fp))
    return r, out, rows


def test_bench_writes_a_row_per_run_and_a_summary(tmp_path: Path) -> None:
    mazes = [builtin_path("minimaze"), builtin_path("alljapan-010-1989-fin")]
    r, out, rows = bench(tmp_path, *mazes)
    assert len(rows) == 6
    assert {row["entrant"] for row in rows} == {"strategy stop", "strategy full", FLOODFILL}
    assert all(row["optimal"] == "True" for row in rows if row["entrant"].startswith("strategy"))
    assert (out / "summary.txt").read_text() in r.output
    assert "best per maze" in r.output and "alljapan-010-1989-fin" in r.output
    assert len(list((out / "runs").glob("*/*.bin"))) == 6


@pytest.mark.slow
def test_bench_over_the_built_in_set(tmp_path: Path) -> None:
    _, _, rows = bench(tmp_path)
    assert len(rows) == 3 * len(builtin_names())


def test_a_built_in_strategy_replayed_through_the_world_senses_what_it_learned() -> None:
    truth = parse_maze(builtin_path("alljapan-010-1989-fin").read_text())
    result = explore(truth, "stop")
    world = MmsWorld(truth, load_mouse(None, truth.size))
    for line in commands_for(result.trace):
        world.handle(parse_command(line))
    assert world.steps == result.steps and world.turns == result.turns
    assert world.sensed.same_walls(result.maze)
    assert abs(world.search().seconds - result.search.seconds) < 1e-9


def test_bench_refuses_a_mouse_naming_no_program(tmp_path: Path) -> None:
    r = mazelog("bench", "--mouse", "no-such-mouse", "--out", str(tmp_path / "b"))
    assert r.exit_code == 1 and "'no-such-mouse' is not found on PATH" in r.output
