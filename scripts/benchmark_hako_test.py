"""The wall time of the worked example's test suite (docs/examples/hako-tests.toml), as CI runs it, on 1 and
2 benches: `hako test FILE --benches N` from start to exit, best of --repeat runs, with the machine's load
average before each (the machine is shared, so a figure means little without it) and the tests' own wall
time from the JSON results (what the benches spent, without start-up and pictures).

    python scripts/benchmark_hako_test.py [--benches 1,2] [--repeat 1] [--file docs/examples/hako-tests.toml]
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import click

ROOT = Path(__file__).resolve().parents[1]


def one_run(test_file: Path, benches: int, work: Path) -> tuple[float, float, int, float]:
    """(wall seconds, seconds in tests, tests, 1-minute load before it)."""
    load = os.getloadavg()[0]
    results = work / "results.json"
    start = time.monotonic()
    r = subprocess.run([sys.executable, "-m", "testctl.hako", "test", str(test_file), "--benches", str(benches),
                        "--out", str(work / "out"), "--json", str(results)], capture_output=True, text=True)
    wall = time.monotonic() - start
    if r.returncode != 0:
        raise click.ClickException(f"hako test --benches {benches} exited {r.returncode}: "
                                   f"{(r.stderr.strip().splitlines() or ['?'])[-1]}")
    runs = [run for case in json.loads(results.read_text())["cases"] for run in case["runs"]]
    return wall, sum(run["wall_s"] for run in runs), len(runs), load


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--benches", default="1,2", show_default=True, help="Comma-separated bench counts.")
@click.option("--repeat", type=click.IntRange(min=1), default=1, show_default=True, help="Runs per count (best kept).")
@click.option("--file", "test_file", type=click.Path(dir_okay=False, exists=True, path_type=Path),
              default=ROOT / "docs" / "examples" / "hako-tests.toml", show_default=True)
def main(benches: str, repeat: int, test_file: Path) -> None:
    """Time the example suite on each number of benches."""
    counts = [int(n) for n in benches.split(",")]
    click.echo(f"{test_file} on {os.cpu_count()} CPU cores")
    click.echo("benches  wall_s  in_tests_s  tests  load_1min_before")
    first: float | None = None
    for n in counts:
        best = None
        for _ in range(repeat):
            with tempfile.TemporaryDirectory(prefix="hako-bench-test-") as tmp:
                run = one_run(test_file, n, Path(tmp))
            best = run if best is None or run[0] < best[0] else best
        assert best is not None
        wall, in_tests, tests, load = best
        first = first or wall
        click.echo(f"{n:7d}  {wall:6.1f}  {in_tests:10.1f}  {tests:5d}  {load:16.2f}"
                   + (f"  ({first / wall:.2f}x of 1 bench)" if n != counts[0] else ""))


if __name__ == "__main__":
    main()
