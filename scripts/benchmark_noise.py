"""What the seeded noise does to one parameter set: events and laps over several noise draws, for the paper's
gains and for zero gains, each draw seeded as a campaign seeds its repetitions (campaign seed, set 0, rep r).
"""

from __future__ import annotations

import statistics
import tempfile
from pathlib import Path

import click

from testctl.bench import Bench
from testctl.bench_options import BenchOptions
from testctl.executor import TestSpec
from testctl.noise_seed import noise_seed
from testctl.paper import BEST_GAINS, line_trace_params


@click.command()
@click.option("--seeds", default=10, show_default=True, help="Noise draws per parameter set.")
@click.option("--scale", default=1.0, show_default=True, help="Noise scale (1 = the course's levels).")
@click.option("--campaign-seed", default=1, show_default=True)
def main(seeds: int, scale: float, campaign_seed: int) -> None:
    """Print events and lap times of the paper's gains and of zero gains under noise."""
    sets = {"paper gains": line_trace_params(*BEST_GAINS), "zero gains": line_trace_params(0.0, 0.0, 0.0)}
    with tempfile.TemporaryDirectory(prefix="hako-bench-noise-") as tmp, Bench(BenchOptions(), Path(tmp)) as bench:
        noise_free = {name: bench.run(TestSpec(0, 1, params)) for name, params in sets.items()}
        for name, params in sets.items():
            results = [bench.run(TestSpec(0, r, params, noise_seed(campaign_seed, 0, r), scale))
                       for r in range(1, seeds + 1)]
            laps = [r.lap_time_s for r in results if r.success]
            events = {e: sum(r.event.name == e for r in results) for e in sorted({r.event.name for r in results})}
            free = noise_free[name]
            print(f"{name}: noise-free {free.event.name} {free.lap_time_s or '-'}; with noise x{scale:g} over "
                  f"{seeds} seeds: {events}"
                  + (f"; laps {min(laps):.2f}..{max(laps):.2f} s, mean {statistics.mean(laps):.2f} s, "
                     f"sd {statistics.pstdev(laps):.2f} s" if laps else ""))


if __name__ == "__main__":
    main()
