"""Time `replay` of a full 32x32 wall log in process (target: under 20 ms).

Usage: python scripts/benchmark_mazelog.py [--maze FILE] [--repeat N]
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

import click

from maze.files.builtin import builtin_path
from maze.files.mazefile import parse_maze
from maze.log.restore import load_log, records_for, restore
from maze.log.wallrecord import encode_log

DEFAULT_MAZE = builtin_path("japan2019hef")


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--maze", "maze_path", type=click.Path(exists=True, dir_okay=False, path_type=Path),
              default=DEFAULT_MAZE, show_default=True, help="True maze whose full log is replayed.")
@click.option("--repeat", type=click.IntRange(min=1), default=200, show_default=True)
def main(maze_path: Path, repeat: int) -> None:
    """Decode + restore a log that lists every inner wall; print min/median/max milliseconds."""
    truth = parse_maze(maze_path.read_text())
    data = encode_log(records_for(truth))
    times = []
    with click.progressbar(range(repeat), label="replaying", file=sys.stderr) as bar:
        for _ in bar:
            t0 = time.perf_counter()
            maze, _ = restore(load_log(data, truth.size, strict=True).records, truth.size)
            times.append((time.perf_counter() - t0) * 1000)
    assert maze.same_walls(truth), "replay did not restore the maze"
    print(f"maze {maze_path.name}: {truth.size}x{truth.size}, {len(data) // 2} records, {len(data)} bytes")
    print(f"replay (decode + restore) over {repeat} runs: min {min(times):.2f} ms, "
          f"median {statistics.median(times):.2f} ms, max {max(times):.2f} ms")


if __name__ == "__main__":
    main()
