"""Whole-process `mazelog explore` of 32x32 mazes, this checkout against an older copy of the maze package,
interleaved run by run so that both see the same machine load (issue 17's target: under 0.5 s with a built-in
strategy). Prints medians per maze, objective and version, and the load average.

Usage: git archive main maze | tar -x -C /tmp/before   # the version to compare with
       python scripts/benchmark_maze_explore.py --before /tmp/before [--runs 5] [MAZE]...
Without MAZE: the built-in 32x32 mazes (development) and, apart, ../shared/mazes/halfsize (held out).
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import click

from maze.files.builtin import builtin_path

ROOT = Path(__file__).resolve().parents[1]
HELD_OUT = ROOT.parent / "shared" / "mazes" / "halfsize"
DEV = ["japan2009hef", "japan2019hef"]
OBJECTIVES = {"cells": [], "time, diagonal": ["--objective", "time", "--diagonal"]}
ENTRY = "import sys; from maze.cli import main; sys.argv[0] = 'mazelog'; main()"


def once(package_root: Path, maze: Path, extra: list[str], log: Path) -> float:
    """One run with `package_root` first on the path; run from an empty folder so no checkout shadows it."""
    env = dict(os.environ, PYTHONPATH=str(package_root))
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", ENTRY, "explore", str(maze), "--log", str(log), *extra], check=True,
                   capture_output=True, env=env, cwd=log.parent)
    return time.perf_counter() - t0


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.argument("mazes", nargs=-1, type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--before", type=click.Path(exists=True, file_okay=False, path_type=Path), default=None,
              help="A folder holding an older maze/ package to compare with.")
@click.option("--runs", type=click.IntRange(min=1), default=5, show_default=True)
def main(mazes: tuple[Path, ...], before: Path | None, runs: int) -> None:
    """Median seconds per whole-process explore."""
    sets = {"given": list(mazes)} if mazes else {
        "development (built-in)": [p for p in (builtin_path(n) for n in DEV) if p is not None],
        "held out": sorted(HELD_OUT.glob("*.txt"))[::3] if HELD_OUT.is_dir() else []}
    versions = {"after": ROOT} | ({"before": before.resolve()} if before else {})
    with tempfile.TemporaryDirectory() as tmp:
        log = Path(tmp) / "run.bin"
        for name, files in sets.items():
            print(f"{name}:")
            for maze in files:
                for label, extra in OBJECTIVES.items():
                    times: dict[str, list[float]] = {v: [] for v in versions}
                    for _ in range(runs):
                        for version, root in versions.items():
                            times[version].append(once(root, maze, extra, log))
                    with open("/proc/loadavg") as fp:
                        load = fp.read().split()[0]
                    shown = ", ".join(f"{v} {statistics.median(t):.2f} s" for v, t in times.items())
                    print(f"  {maze.stem:28} {label:15} {shown}  (load {load})")


if __name__ == "__main__":
    main()
