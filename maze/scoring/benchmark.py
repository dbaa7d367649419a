"""`mazelog bench`: mice (mms programs) and built-in strategies over many mazes, in parallel processes.

Both kinds go through the same world (maze/mouse/mmsworld.py): a built-in strategy's search is replayed into it as the
mms commands a mouse would send (at each cell, front, left and right wall queries, then turns and a move), so
the wall log, mms's statistics and our figures are measured by one piece of code for everybody.
"""

from __future__ import annotations

import csv
import os
from collections.abc import Iterator
from dataclasses import asdict, dataclass, fields
from pathlib import Path

from ..direction import DELTA, NORTH
from ..errors import MazeError
from ..files.builtin import builtin_names, builtin_path
from ..files.mazeio import read_maze
from ..log.wallrecord import encode_log
from ..model import Cell, Maze
from ..mouse.mms import parse_command
from ..mouse.mmsworld import MmsWorld
from ..outputs import write_bytes
from ..timing.mouseparams import load_mouse

MAZE_SUFFIXES = (".txt", ".num", ".maz")
TIME_TOLERANCE = 1e-9


@dataclass(frozen=True)
class Entrant:
    name: str  # what the tables call it
    program: str | None = None  # an mms command line, or None for a built-in strategy
    strategy: str | None = None


@dataclass(frozen=True)
class Job:
    entrant: Entrant
    maze: str  # a path
    objective: str
    diagonal: bool
    max_steps: int | None
    timeout: float
    out: str  # folder for this run's wall log and stderr


@dataclass
class Row:
    entrant: str
    maze: str
    size: int
    ended: str
    fault: str
    steps: int
    turns: int
    search_s: float
    visited: int
    records: int
    mms_total_distance: int
    mms_total_turns: int
    mms_best_run_distance: str
    mms_best_run_turns: str
    mms_score: float
    found: float  # cells or seconds, by the objective; -1 if no path is known
    true: float
    optimal: bool


def maze_files(paths: tuple[Path, ...]) -> list[Path]:
    """Files and folders (their maze files, recursively); none given: the built-in set."""
    if not paths:
        return [p for p in (builtin_path(n) for n in builtin_names()) if p is not None]
    files: list[Path] = []
    for path in paths:
        if path.is_dir():
            files += sorted(p for p in path.rglob("*") if p.suffix.lower() in MAZE_SUFFIXES and p.is_file()
                            and p.name != "README.md")
        else:
            files.append(path)
    if not files:
        raise MazeError(f"no maze files ({', '.join(MAZE_SUFFIXES)}) in {', '.join(map(str, paths))}")
    return files


def commands_for(trace: list[Cell]) -> Iterator[str]:
    """A built-in strategy's walk as an mms mouse would send it."""
    heading = NORTH
    turn_words = {2: ["turnLeft"], 6: ["turnRight"], 4: ["turnRight", "turnRight"]}
    for a, b in zip(trace, trace[1:]):
        yield from ("wallFront", "wallLeft", "wallRight")
        step = (b[0] - a[0], b[1] - a[1])
        move = next(d for d, delta in DELTA.items() if delta == step)
        yield from turn_words.get((move - heading) % 8, [])
        heading = move
        yield "moveForward"
    yield from ("wallFront", "wallLeft", "wallRight")


def run_job(job: Job) -> Row:
    truth = read_maze(Path(job.maze))
    timing = load_mouse(None, truth.size)
    world = MmsWorld(truth, timing)
    name = Path(job.maze).stem
    ended, fault = "", ""
    if job.entrant.program is not None:
        from ..mouse.harness import program_argv, run_mouse

        run = run_mouse(program_argv(job.entrant.program), world, Path(job.out) / f"{name}.stderr.txt",
                        job.max_steps, None, job.timeout)
        ended, fault = run.ended, run.fault or ""
    else:
        from ..search.explorer import explore

        assert job.entrant.strategy is not None
        result = explore(truth, job.entrant.strategy, job.objective, job.diagonal, timing)
        for line in commands_for(result.trace):
            world.handle(parse_command(line))
        ended = "the strategy ended"
    write_bytes(Path(job.out) / f"{name}.bin", encode_log(world.records))
    found, true = best_runs(world.sensed, truth, job.objective, job.diagonal)
    stats = world.stats
    return Row(job.entrant.name, name, truth.size, ended, fault, world.steps, world.turns,
               round(world.search().seconds, 3), len(set(world.trace)), len(world.records), stats.total_distance,
               stats.total_turns, stats.value("best-run-distance"), stats.value("best-run-turns"),
               round(stats.score, 3), found, true, found >= 0 and found <= true + TIME_TOLERANCE)


def best_runs(sensed: Maze, truth: Maze, objective: str, diagonal: bool) -> tuple[float, float]:
    """The best run the sensed walls prove, and the true maze's: cells, or seconds under the time model."""
    from ..search.stepmap import pessimistic, shortest_path

    if objective == "cells":
        return (float(len(shortest_path(sensed, pessimistic(sensed))) - 1),
                float(len(shortest_path(truth, pessimistic(truth))) - 1))
    from ..fastpath import fastest_route

    timing = load_mouse(None, truth.size)
    found = fastest_route(sensed, pessimistic(sensed), diagonal, timing)
    true = fastest_route(truth, pessimistic(truth), diagonal, timing)
    assert true is not None
    return (round(found.seconds, 6) if found is not None else -1.0), round(true.seconds, 6)


def write_csv(rows: list[Row], path: Path) -> None:
    from ..outputs import atomic_open

    with atomic_open(path, "w") as fp:
        writer = csv.DictWriter(fp, fieldnames=[f.name for f in fields(Row)])
        writer.writeheader()
        for row in sorted(rows, key=lambda r: (r.entrant, r.maze)):
            writer.writerow(asdict(row))


def summary(rows: list[Row], entrants: list[str], objective: str) -> str:
    """Totals per entrant, then per maze who did best: the fewest steps among those that know an optimal run
    (cells or time, by the objective), else the best run known."""
    unit = "cells" if objective == "cells" else "s"
    lines = [f"{'entrant':30} {'mazes':>5} {'optimal':>7} {'faults':>6} {'steps':>8} {'search s':>9} "
             f"{'mms score':>9} {'wins':>4}"]
    wins = {e: 0 for e in entrants}
    by_maze: dict[str, list[Row]] = {}
    for row in rows:
        by_maze.setdefault(row.maze, []).append(row)
    best_lines = []
    for maze in sorted(by_maze):
        group = by_maze[maze]
        optimal = [r for r in group if r.optimal and not r.fault]
        pool = optimal or [r for r in group if r.found >= 0 and not r.fault]
        if not pool:
            best_lines.append(f"  {maze:32} nobody knows a path")
            continue
        best = min(pool, key=lambda r: (r.steps, r.search_s) if optimal else (r.found, r.steps))
        wins[best.entrant] += 1
        how = "optimal" if optimal else f"best known {best.found:g} {unit} (true {best.true:g})"
        best_lines.append(f"  {maze:32} {best.entrant} ({best.steps} steps, {how})")
    for entrant in entrants:
        mine = [r for r in rows if r.entrant == entrant]
        lines.append(f"{entrant[:30]:30} {len(mine):5d} {sum(r.optimal for r in mine):7d} "
                     f"{sum(bool(r.fault) for r in mine):6d} {sum(r.steps for r in mine):8d} "
                     f"{sum(r.search_s for r in mine):9.1f} {sum(r.mms_score for r in mine) / max(len(mine), 1):9.1f} "
                     f"{wins[entrant]:4d}")
    return "\n".join(lines + ["", "best per maze (fewest steps among those that know an optimal run):",
                              *best_lines]) + "\n"


def entrant_folder(out: Path, entrant: Entrant, index: int) -> Path:
    safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in entrant.name)[:40]
    folder = out / "runs" / f"{index:02d}-{safe}"
    os.makedirs(folder, exist_ok=True)
    return folder


def default_jobs() -> int:
    return max(1, (os.cpu_count() or 2) // 2)

