"""Search strategies over the real contest mazes, for the fewest cells and for the fastest run, and the flash
cost of backing a search up.

Usage: python scripts/benchmark_search.py [--quick] [--jobs N] [--cuts N] [--per-maze/--no-per-maze]
                                      [--mazes DIR | --builtin]

Mazes come from ../shared/mazes beside the clone (the micromouseonline/mazefiles collection at commit
a71f846897fdd2193e726a1276c6774c9ce9ac67: its classic/, halfsize/ and training/ folders), or from --mazes DIR
laid out the same way; --builtin runs the 12 mazes shipped in the package instead (a fresh clone has only
those). The design was settled on the development set (16x16
classic + training); the 32x32 halfsize mazes are reported apart, as mazes the design never saw. The mouse is
the built-in one for each size (maze/data/mice.toml), whose figures were set before any of this was run.
"""

from __future__ import annotations

import sys
import time
from collections import defaultdict
from dataclasses import dataclass
from multiprocessing import Pool
from pathlib import Path

import click

from maze.files.builtin import builtin_names, builtin_path
from maze.files.mazefile import parse_maze
from maze.log.flash import SECTOR_BYTES, compare_schemes, snapshot_bytes
from maze.log.wallrecord import RECORD_BYTES
from maze.model import inner_wall_count
from maze.search.explorer import explore
from maze.search.strategies import OPTIMAL_CLAIMED, STRATEGIES

MAZES = Path(__file__).resolve().parents[1].parent / "shared" / "mazes"
MAZEFILES = "micromouseonline/mazefiles at commit a71f846897fdd2193e726a1276c6774c9ce9ac67"
GROUPS = {"classic": "16x16 classic", "training": "16x16 training", "halfsize": "32x32 halfsize"}
SETS = {"development set (16x16 classic + training)": ("classic", "training"),
        "held-out set (32x32 halfsize, unseen while designing)": ("halfsize",)}
BASELINE, CANDIDATE = "full", "closing-stop"
Run = tuple[str, str, bool]  # strategy, objective, diagonal
CELL_RUNS: list[Run] = [(s, "cells", False) for s in STRATEGIES]
TIME_RUNS: list[Run] = [("full", "time", d) for d in (False, True)] + [
    (s, "time", d) for d in (False, True) for s in ("stop", "closing-stop")]
HEADLINE: Run = ("stop", "time", True)


@dataclass(frozen=True)
class Row:
    group: str
    maze: str
    run: Run
    steps: int
    turns: int
    visited: int
    shortest: bool
    fastest: bool
    search_s: float
    found_s: float
    true_s: float


def run_one(job: tuple[str, str, Run]) -> Row:
    group, path, run = job
    r = explore(parse_maze(Path(path).read_text()), *run)
    timed = r.found_route is not None and r.true_route is not None
    return Row(group, Path(path).stem, run, r.steps, r.turns, len(set(r.trace)), r.shortest,
               r.fastest, r.search.seconds, r.found_route.seconds if timed else 0.0,
               r.true_route.seconds if timed else 0.0)


def maze_files(root: Path, quick: bool, groups: tuple[str, ...]) -> list[tuple[str, Path]]:
    files = []
    for group in groups:
        found = sorted((root / group).glob("*.txt"))
        found = found[:: 8 if group == "classic" else 4 if group == "halfsize" else 1] if quick else found
        files += [(group, f) for f in found]
    return files


def builtin_files(groups: tuple[str, ...]) -> list[tuple[str, Path]]:
    """The shipped mazes, grouped as the collection's folders are: 32x32 halfsize, training, classic."""
    files = []
    for name in builtin_names():
        path = builtin_path(name)
        assert path is not None
        size = len(path.read_text().splitlines()[0]) // 4
        group = "halfsize" if size > 16 else "training" if name.startswith(("maze-train", "minimaze")) else "classic"
        if group in groups:
            files.append((group, path))
    return files


def label(run: Run) -> str:
    strategy, objective, diagonal = run
    return f"{strategy} --objective {objective}" + (" --diagonal" if diagonal else "")


def pct(a: float, b: float) -> str:
    return f"{100 * (a - b) / b:+.1f}%"


def print_cell_tables(rows: list[Row]) -> None:
    for group, title in GROUPS.items():
        by = defaultdict(list)
        for r in rows:
            if r.group == group and r.run in CELL_RUNS:
                by[r.run[0]].append(r)
        if not by:
            continue
        full_steps = sum(r.steps for r in by[BASELINE])
        print(f"\n{title}, objective cells: {len(by[BASELINE])} mazes")
        print("| strategy | total steps | vs full | total turns | mean cells visited | truly shortest "
              "| claims shortest |")
        print("|---|---:|---:|---:|---:|---:|:---:|")
        for s in STRATEGIES:
            rs = by[s]
            steps = sum(r.steps for r in rs)
            print(f"| {s} | {steps} | {pct(steps, full_steps)} | {sum(r.turns for r in rs)} | "
                  f"{sum(r.visited for r in rs) / len(rs):.0f} | {100 * sum(r.shortest for r in rs) / len(rs):.0f}% | "
                  f"{'yes' if s in OPTIMAL_CLAIMED else 'no'} |")
        full = {r.maze: r.steps for r in by[BASELINE]}
        savings = [1 - r.steps / full[r.maze] for r in by[CANDIDATE]]
        print(f"{CANDIDATE} vs {BASELINE}, per maze: saving min {100 * min(savings):.1f}%, "
              f"max {100 * max(savings):.1f}%")


def print_time_tables(rows: list[Row], per_maze: bool) -> None:
    index = {(r.maze, r.run): r for r in rows}
    for title, groups in SETS.items():
        mine = [r for r in rows if r.group in groups]
        mazes = sorted({(r.group, r.maze) for r in mine})
        if not mazes:
            continue
        print(f"\n{title}, objective time: {len(mazes)} mazes")
        full_runs = {d: ("full", "time", d) for d in (False, True)}
        print("| run | total steps | vs full | search time (model) | vs full | time-optimal path found |")
        print("|---|---:|---:|---:|---:|---:|")
        for run in TIME_RUNS:
            rs = [index[(m, run)] for _, m in mazes]
            base = [index[(m, full_runs[run[2]])] for _, m in mazes]
            steps, full_steps = sum(r.steps for r in rs), sum(r.steps for r in base)
            secs, full_secs = sum(r.search_s for r in rs), sum(r.search_s for r in base)
            print(f"| {label(run)} | {steps} | {pct(steps, full_steps)} | {secs:.0f} s | {pct(secs, full_secs)} | "
                  f"{sum(r.fastest for r in rs)}/{len(rs)} ({100 * sum(r.fastest for r in rs) / len(rs):.0f}%) |")
        cand = [index[(m, HEADLINE)] for _, m in mazes]
        full = {m: index[(m, full_runs[True])] for _, m in mazes}
        savings = [1 - r.steps / full[r.maze].steps for r in cand]
        print(f"{label(HEADLINE)} vs full, per maze: step saving min {100 * min(savings):.1f}%, "
              f"max {100 * max(savings):.1f}%; {sum(s >= 0.2 for s in savings)} of {len(savings)} mazes "
              f"save 20% or more")
        print_closing_verdict(index, mazes)
        if per_maze:
            print(f"\nper maze ({label(HEADLINE)}; full and closing-stop with the same objective):")
            print("| maze | full steps | full search s | stop steps | vs full | stop search s "
                  "| fastest run found / optimal s | optimal | closing-stop steps |")
            print("|---|---:|---:|---:|---:|---:|---:|:---:|---:|")
            for group, m in mazes:
                f, r = full[m], index[(m, HEADLINE)]
                c = index[(m, ("closing-stop", "time", True))]
                print(f"| {group}/{m} | {f.steps} | {f.search_s:.0f} | {r.steps} | {pct(r.steps, f.steps)} | "
                      f"{r.search_s:.0f} | {r.found_s:.3f} / {r.true_s:.3f} | {'yes' if r.fastest else 'NO'} | "
                      f"{c.steps} |")


def print_closing_verdict(index: dict, mazes: list[tuple[str, str]]) -> None:
    for diagonal in (False, True):
        plain = [index[(m, ("stop", "time", diagonal))] for _, m in mazes]
        closing = [index[(m, ("closing-stop", "time", diagonal))] for _, m in mazes]
        better = sum(c.steps < p.steps for p, c in zip(plain, closing))
        worse = sum(c.steps > p.steps for p, c in zip(plain, closing))
        s_plain, s_closing = sum(r.steps for r in plain), sum(r.steps for r in closing)
        print(f"dead-end closing on top of the time stopping rule{' (diagonal)' if diagonal else ''}: "
              f"{s_closing} vs {s_plain} steps ({pct(s_closing, s_plain)}), fewer on {better} mazes, "
              f"more on {worse}; time-optimal {sum(r.fastest for r in closing)} vs {sum(r.fastest for r in plain)}")


def print_flash_table(maze_path: Path, strategy: str, cuts: int) -> None:
    result = explore(parse_maze(maze_path.read_text()), strategy)
    n = result.maze.size
    print(f"\nflash, one {n}x{n} search ({maze_path.name}, {strategy}: {result.steps} steps, "
          f"{len(result.records)} wall records), sector {SECTOR_BYTES} bytes, power cut at {cuts} random bytes")
    print("| scheme | bytes written | erases | max erases of one sector | writes | walls lost on a cut: mean | max |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for rep in compare_schemes(result, cuts):
        print(f"| {rep.name} | {rep.bytes_written} | {rep.erases} | {rep.max_sector_erases} | {rep.writes} | "
              f"{rep.mean_lost:.1f} | {max(rep.lost)} |")
    print("\nstorage per maze size (seed's table; the log column is records x 2 bytes)")
    print("| maze | 1 byte per cell | minimal snapshot | wall log, at most |")
    print("|---|---:|---:|---:|")
    for size in (8, 16, 32):
        walls = inner_wall_count(size)
        print(f"| {size}x{size} | {size * size} | {snapshot_bytes(size)} "
              f"| {walls} records = {walls * RECORD_BYTES} bytes |")


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--quick", is_flag=True, help="Every 8th classic and every 4th halfsize maze, 50 power cuts.")
@click.option("--jobs", type=click.IntRange(min=1), default=2, show_default=True, help="Worker processes.")
@click.option("--cuts", type=click.IntRange(min=1), default=None, help="Random power cuts per scheme [300; quick 50].")
@click.option("--group", "groups", type=click.Choice(list(GROUPS)), multiple=True,
              help="Only these maze folders (repeatable) [all].")
@click.option("--per-maze/--no-per-maze", default=True, show_default=True, help="Print the per-maze time table.")
@click.option("--mazes", "root", type=click.Path(file_okay=False, path_type=Path), default=MAZES,
              show_default="../shared/mazes", help="A folder with classic/, halfsize/ and training/ maze files.")
@click.option("--builtin", is_flag=True, help="Use the mazes shipped in the package instead.")
@click.option("--flash-maze", type=click.Path(exists=True, dir_okay=False, path_type=Path), default=None,
              help="The 32x32 maze of the flash table [default: japan2019hef].")
@click.option("--flash-strategy", type=click.Choice(list(STRATEGIES)), default=CANDIDATE, show_default=True)
def main(quick: bool, jobs: int, cuts: int | None, groups: tuple[str, ...], per_maze: bool, root: Path,
         builtin: bool, flash_maze: Path | None, flash_strategy: str) -> None:
    """Benchmark the search strategies (fewest cells and fastest run) and the flash backup schemes."""
    groups = groups or tuple(GROUPS)
    if builtin:
        files = builtin_files(groups)
    elif not root.is_dir():
        raise click.ClickException(f"no maze folder {root}: it holds {MAZEFILES} (a clone of that repository "
                                   f"at that commit will do); give --mazes DIR, or --builtin for the mazes shipped "
                                   f"in the package")
    else:
        files = maze_files(root, quick, groups)
    if not files:
        raise click.ClickException(f"no mazes under {root} in {', '.join(groups)}")
    flash_maze = flash_maze or builtin_path("japan2019hef")
    t0 = time.perf_counter()
    runs = CELL_RUNS + TIME_RUNS
    jobs_list = [(group, str(f), run) for group, f in files for run in runs]
    with Pool(jobs) as pool, click.progressbar(pool.imap_unordered(run_one, jobs_list), length=len(jobs_list),
                                               label="searching", file=sys.stderr) as bar:
        rows = list(bar)
    print_cell_tables(rows)
    print_time_tables(rows, per_maze)
    if not groups or "halfsize" in groups:
        print_flash_table(flash_maze, flash_strategy, cuts or (50 if quick else 300))
    print(f"\n{len(files)} mazes x {len(runs)} runs in {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
