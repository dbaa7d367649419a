"""Whole-process start-up time of the command-line tools, as a new user meets it (target: under 0.3 s for
`mazelog --help` and a text `mazelog replay` of a 32x32 log).

Usage: python scripts/benchmark_startup.py [--runs N]
Each command runs once unmeasured (to warm the file cache), then N times; the table gives the median, min and
max wall-clock seconds of the whole process (interpreter start, imports, work, exit).
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
from maze.files.mazefile import parse_maze
from maze.log.restore import records_for
from maze.log.wallrecord import encode_log

TARGET_S = 0.3
BIN = Path(sys.executable).parent


def wall_seconds(argv: list[str]) -> float:
    t0 = time.perf_counter()
    subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    return time.perf_counter() - t0


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--runs", type=click.IntRange(min=1), default=9, show_default=True, help="Measured runs per command.")
def main(runs: int) -> None:
    """Time `mazelog --help`, a text replay of a full 32x32 log, `hako --help`, `hako run --help` and
    `hako test --help`."""
    with tempfile.TemporaryDirectory() as tmp:
        log = Path(tmp) / "japan2019hef-full.bin"
        log.write_bytes(encode_log(records_for(parse_maze(builtin_path("japan2019hef").read_text()))))
        commands = [
            ("mazelog --help", [str(BIN / "mazelog"), "--help"], TARGET_S),
            ("mazelog replay LOG --format text (32x32, 1984 records)",
             [str(BIN / "mazelog"), "replay", str(log), "--format", "text"], TARGET_S),
            ("hako --help", [str(BIN / "hako"), "--help"], None),
            ("hako run --help", [str(BIN / "hako"), "run", "--help"], None),
            ("hako test --help", [str(BIN / "hako"), "test", "--help"], None),
        ]
        rows = []
        with click.progressbar(commands, label="timing", file=sys.stderr) as bar:
            for name, argv, target in bar:
                wall_seconds(argv)
                times = [wall_seconds(argv) for _ in range(runs)]
                rows.append((name, times, target))
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    print(f"whole-process wall time over {runs} runs (after one unmeasured run), seconds; "
          f"load average {load} on {os.cpu_count()} CPUs")
    print("| command | median | min | max | target |")
    print("|---|---:|---:|---:|---|")
    for name, times, target in rows:
        verdict = "-" if target is None else f"< {target} s: {'yes' if statistics.median(times) < target else 'NO'}"
        print(f"| `{name}` | {statistics.median(times):.3f} | {min(times):.3f} | {max(times):.3f} | {verdict} |")


if __name__ == "__main__":
    main()
