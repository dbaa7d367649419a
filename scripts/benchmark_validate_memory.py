"""The controller's resident memory over a long validation, and what submitting every draw at once cost.

Usage: python scripts/benchmark_validate_memory.py [--draws 10000] [--benches 2] [--time-limit 0.2]

It runs `hako run --smoke --validate 0` once into a scratch folder (a campaign with a best set), then
validates that set on --draws draws through `testctl.campaign.validate.validate_best`, the code `hako run --validate`
runs, on --benches local Dask workers (the scheduler lives in this process, as in `hako run`), every draw
journaled. The draws run on a bench with a short --time-limit so that many fit: a TIME_OVER after 0.2
simulated seconds costs what every test costs the controller (a task, a result, a journal line), without
the lap. `hako run` itself caps --validate at testctl.options.MAX_DRAWS; this measures past it. It prints
the resident memory of this process every --every draws, then, for comparison, the memory that handing
the same number of draws to the cluster at once (what validation did before) takes, without running them.
"""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import click
import psutil

from testctl.bench_options import BenchOptions
from testctl.campaign.journal import JOURNAL_FILE, read_journal
from testctl.campaign.loop import Campaign, load_config
from testctl.campaign.validate import validate_best, validation_specs
from testctl.cluster import DaskExecutor


def rss_mb() -> float:
    return psutil.Process().memory_info().rss / 2**20


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--draws", type=click.IntRange(min=1), default=10_000, show_default=True)
@click.option("--benches", type=click.IntRange(min=1), default=2, show_default=True)
@click.option("--time-limit", type=float, default=0.2, show_default=True, help="Simulated seconds per draw.")
@click.option("--every", type=click.IntRange(min=1), default=500, show_default=True, help="Draws per printed line.")
def main(draws: int, benches: int, time_limit: float, every: int) -> None:
    """Print the controller's RSS over a validation of --draws draws."""
    with tempfile.TemporaryDirectory(prefix="hako-valmem-") as tmp:
        out = Path(tmp) / "c"
        subprocess.run([sys.executable, "-m", "testctl.hako", "run", "--smoke", "--validate", "0", "--benches", "1",
                        "--out", str(out)], check=True, stdout=subprocess.DEVNULL)
        header, _ = read_journal(out / JOURNAL_FILE)
        bench = dataclasses.replace(BenchOptions(**{k: v for k, v in header["bench"].items()
                                                    if k in {f.name for f in dataclasses.fields(BenchOptions)}}),
                                    time_limit_s=time_limit)
        executor = DaskExecutor(bench, benches=benches)
        try:
            summary = Campaign(load_config(out), out, executor, resume=True).run()  # all decided: runs nothing
            click.echo(f"machine: {os.cpu_count()} CPUs, load {', '.join(f'{x:.1f}' for x in os.getloadavg())}; "
                       f"{benches} benches, {time_limit} simulated s per draw")
            click.echo("| draws | wall s | RSS MB |")
            click.echo("|---:|---:|---:|")
            t0 = time.monotonic()
            click.echo(f"| 0 | 0 | {rss_mb():.0f} |")
            seen = 0

            def on_result(spec, result) -> None:
                nonlocal seen
                seen += 1
                if seen % every == 0:
                    click.echo(f"| {seen} | {time.monotonic() - t0:.0f} | {rss_mb():.0f} |")

            validate_best(summary, executor, draws, out, on_result)
            before = rss_mb()
            t1 = time.monotonic()
            for spec in validation_specs(summary, draws):  # the old way: every draw handed over at once
                executor.submit(dataclasses.replace(spec, rep=spec.rep + draws))
            click.echo(f"handing {draws} draws to the cluster at once (not run): RSS {before:.0f} -> "
                       f"{rss_mb():.0f} MB in {time.monotonic() - t1:.1f} s")
        finally:
            executor.close()


if __name__ == "__main__":
    main()
