"""The real athrill2 over UDP against the same athrill2 over mmap, both in the hakoniwa sync mode: simulated
seconds per wall second and laps of the C tracer's image at the paper's gains, noise-free, trials of the two
transports interleaved so that both see the same machine load. Each trial runs on a fresh bench; the physics
process's start is excluded (once per campaign), athrill2's start included (once per test).
"""

from __future__ import annotations

import statistics
import subprocess
import sys

import click
from benchmark_sim import REPO, trial_rate  # scripts/ is this script's folder

from athrill_sim.programs.athrill2 import AthrillTransport, RealSync
from hakoniwa.conventions import HELP
from testctl.bench_options import BenchOptions

TRACER = REPO / "athrill_sim" / "apps" / "line_trace.c"


@click.command(context_settings=HELP)
@click.option("--tests", type=click.IntRange(min=1), default=5, show_default=True, help="Trials per transport.")
@click.option("--athrill2", default=str(REPO / "build" / "athrill" / "athrill2"), show_default=True,
              help="The real TOPPERS emulator (scripts/build_athrill2.sh builds it).")
def main(tests: int, athrill2: str) -> None:
    """Print, per transport, the sim-s per wall-s of all trials together, and the laps."""
    image = subprocess.run([sys.executable, "-m", "testctl.hako", "build", str(TRACER)], capture_output=True,
                           text=True, check=True).stdout.strip()
    benches = {"mmap": BenchOptions(app=image, athrill2=athrill2, sync=RealSync.HAKONIWA),
               "udp": BenchOptions(app=image, athrill2=athrill2, transport=AthrillTransport.UDP)}
    sim = {name: 0.0 for name in benches}
    wall = {name: 0.0 for name in benches}
    laps: dict[str, list[float]] = {name: [] for name in benches}
    for _ in range(tests):
        for name, bench in benches.items():
            _, (result,) = trial_rate(bench, 1, warm_up=False)
            laps[name].append(result.lap_time_s or float("nan"))
            sim[name] += (result.goal_time_us or 0) / 1e6
            wall[name] += result.wall_s
    for name in benches:
        print(f"{name:4}: {sim[name] / wall[name]:6.1f} sim-s per wall-s over {tests} trials; laps "
              f"{', '.join(f'{x:.2f}' for x in laps[name])} s (median {statistics.median(laps[name]):.2f})")


if __name__ == "__main__":
    sys.exit(main())
