"""Search strategies over the real contest mazes, and the flash cost of backing the search up.

Usage: python scripts/bench_search.py [--quick] [--jobs N] [--cuts N]
Prints, per maze size: total steps and turns per strategy and the share of mazes whose found path is truly
shortest; then the wall log vs whole-maze snapshots on a NOR flash model for one 32x32 search.
"""

from __future__ import annotations

import time
from collections import defaultdict
from multiprocessing import Pool
from pathlib import Path

import click

from maze.explorer import SHORTEST_CLAIMED, STRATEGIES, explore
from maze.flash import SECTOR_BYTES, compare_schemes, snapshot_bytes
from maze.mazefile import parse_maze
from maze.model import inner_wall_count
from maze.wallrecord import RECORD_BYTES

MAZES = Path(__file__).resolve().parents[1].parent / "shared" / "mazes"
GROUPS = {"classic": "16x16 classic", "halfsize": "32x32 halfsize"}
BASELINE, CANDIDATE = "full", "closing-stop"


def run_one(job: tuple[str, str]) -> tuple[str, str, str, int, int, int, bool]:
    path, strategy = job
    r = explore(parse_maze(Path(path).read_text()), strategy)
    return Path(path).parent.name, Path(path).name, strategy, r.steps, r.turns, len(set(r.trace)), r.shortest


def maze_files(quick: bool) -> list[Path]:
    files = []
    for group in GROUPS:
        found = sorted((MAZES / group).glob("*.txt"))
        files += found[:: 8 if group == "classic" else 4] if quick else found
    return files


def print_strategy_tables(rows: list[tuple[str, str, str, int, int, int, bool]]) -> None:
    for group, title in GROUPS.items():
        mine = [r for r in rows if r[0] == group]
        if not mine:
            continue
        by = defaultdict(list)
        for r in mine:
            by[r[2]].append(r)
        full_steps = sum(r[3] for r in by[BASELINE])
        print(f"\n{title}: {len(by[BASELINE])} mazes")
        print("| strategy | total steps | vs full | total turns | mean cells visited | truly shortest | claims shortest |")
        print("|---|---:|---:|---:|---:|---:|:---:|")
        for s in STRATEGIES:
            rs = by[s]
            steps = sum(r[3] for r in rs)
            share = 100 * sum(r[6] for r in rs) / len(rs)
            print(f"| {s} | {steps} | {100 * (steps - full_steps) / full_steps:+.1f}% | {sum(r[4] for r in rs)} | "
                  f"{sum(r[5] for r in rs) / len(rs):.0f} | {share:.0f}% | {'yes' if s in SHORTEST_CLAIMED else 'no'} |")
        full = {r[1]: r[3] for r in by[BASELINE]}
        savings = [1 - r[3] / full[r[1]] for r in by[CANDIDATE]]
        print(f"{CANDIDATE} vs {BASELINE}, per maze: saving min {100 * min(savings):.1f}%, "
              f"max {100 * max(savings):.1f}%")


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
        print(f"| {size}x{size} | {size * size} | {snapshot_bytes(size)} | {walls} records = {walls * RECORD_BYTES} bytes |")


@click.command()
@click.option("--quick", is_flag=True, help="Every 8th classic and every 4th halfsize maze, 50 power cuts.")
@click.option("--jobs", type=click.IntRange(min=1), default=2, show_default=True, help="Worker processes.")
@click.option("--cuts", type=click.IntRange(min=1), default=None, help="Random power cuts per scheme [300; quick 50].")
@click.option("--flash-maze", type=click.Path(exists=True, dir_okay=False, path_type=Path),
              default=MAZES / "halfsize" / "japan2019hef.txt", show_default=True)
@click.option("--flash-strategy", type=click.Choice(list(STRATEGIES)), default=CANDIDATE, show_default=True)
def main(quick: bool, jobs: int, cuts: int | None, flash_maze: Path, flash_strategy: str) -> None:
    """Benchmark the search strategies and the flash backup schemes."""
    files = maze_files(quick)
    if not files:
        raise click.ClickException(f"no mazes under {MAZES}")
    t0 = time.perf_counter()
    jobs_list = [(str(f), s) for f in files for s in STRATEGIES]
    with Pool(jobs) as pool, click.progressbar(pool.imap_unordered(run_one, jobs_list), length=len(jobs_list),
                                               label="searching", file=click.get_text_stream("stderr")) as bar:
        rows = list(bar)
    print_strategy_tables(rows)
    print_flash_table(flash_maze, flash_strategy, cuts or (50 if quick else 300))
    print(f"\n{len(files)} mazes x {len(STRATEGIES)} strategies in {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
