"""What one campaign test costs the machine: the CPU seconds of a bench's processes (the physics process and
every Athrill it starts, the start of the next test's included) per test, and the wall time per test.

On a campaign's busy cores CPU per test, not a test's wall time on an idle machine, is what sets the
campaign's rate: each bench starts the next test's Athrill while the current one runs, which is free on an
idle core and not on a busy one. CPU time also moves much less with the machine's load than wall time.

    python scripts/benchmark_test_cpu.py                       # 6 noisy tests of the paper's tracer, 3 rounds
    python scripts/benchmark_test_cpu.py --before /tmp/before  # the same, interleaved with another tree's code

Each round runs one bench in a process of its own (so each tree's modules are its own), a warm-up test first
(the bench's start), then the tests measured. The bench's processes' CPU is read from /proc before and after
the tests, so the bench's own start (the physics process importing MuJoCo, 1-1.5 s) is not in it: an
earlier version read rusage after the bench closed, which spread that start over the round's tests.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
from pathlib import Path

import click

ROUND = """
import os, sys, tempfile, time
from pathlib import Path
from testctl.bench_options import BenchOptions
from testctl.bench import Bench
from testctl.executor import TestSpec

TICK = os.sysconf("SC_CLK_TCK")


def tree_cpu(pid):
    # CPU of `pid` and of its children that it reaped, with the same of each child still running (the
    # zygote, which reaps the forked mocks): seconds, read from /proc.
    total = 0.0
    for child in open(f"/proc/{pid}/task/{pid}/children").read().split():
        total += tree_cpu(int(child))
    fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return total + sum(int(f) for f in fields[11:15]) / TICK


n, app = int(sys.argv[1]), sys.argv[2]
gains = {540: 3.364, 544: 0.0, 548: 0.0, 552: 15.0}
with tempfile.TemporaryDirectory() as tmp:
    bench = Bench(BenchOptions(app=app), Path(tmp) / "run")
    bench.run(TestSpec(0, 1, gains, 1, 1.0))
    physics = bench._proc.pid
    before = tree_cpu(physics)
    start = time.perf_counter()
    events = [bench.run(TestSpec(0, rep, gains, rep, 1.0)).event.name for rep in range(2, n + 2)]
    wall = time.perf_counter() - start
    cpu = tree_cpu(physics) - before
    bench.close()
print(cpu / n, wall / n, ",".join(sorted(set(events))))
"""


def one_round(tree: Path, tests: int, app: str) -> tuple[float, float, str]:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    out = subprocess.run([sys.executable, "-c", ROUND, str(tests), app], env=env, cwd=tree, capture_output=True,
                         text=True)
    if out.returncode != 0:
        raise click.ClickException(f"a round in {tree} failed: {out.stderr.strip().splitlines()[-1:]}")
    cpu, wall, events = out.stdout.split()
    return float(cpu), float(wall), events


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--tests", type=click.IntRange(min=1), default=6, show_default=True, help="Tests per round.")
@click.option("--rounds", type=click.IntRange(min=1), default=3, show_default=True, help="Rounds per tree.")
@click.option("--app", default="line_trace", show_default=True, help="The program (--app of `hako try`).")
@click.option("--before", type=click.Path(file_okay=False, exists=True, path_type=Path), default=None,
              help="Another tree of the project (e.g. `git archive` of an older commit), run interleaved.")
def main(tests: int, rounds: int, app: str, before: Path | None) -> None:
    """Print CPU and wall seconds per campaign test, medians over rounds."""
    trees = {"this": Path(__file__).resolve().parent.parent}
    if before is not None:
        trees = {"before": before.resolve(), **trees}
    load = "load average {:.2f} {:.2f} {:.2f}".format(*os.getloadavg())
    print(f"{app}, {tests} tests a round, {rounds} rounds, noise on; {load}")
    results: dict[str, list[tuple[float, float, str]]] = {name: [] for name in trees}
    for _ in range(rounds):
        for name, tree in trees.items():
            results[name].append(one_round(tree, tests, app))
    for name, rows in results.items():
        cpu = statistics.median(r[0] for r in rows)
        wall = statistics.median(r[1] for r in rows)
        print(f"{name:>6}: CPU {cpu:.3f} s per test (rounds {', '.join(f'{r[0]:.3f}' for r in rows)}), wall "
              f"{wall:.3f} s per test; events {', '.join(sorted({r[2] for r in rows}))}")
    print("load average {:.2f} {:.2f} {:.2f} after".format(*os.getloadavg()))


if __name__ == "__main__":
    main()
