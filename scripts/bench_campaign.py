"""Campaign benchmarks: benches in parallel, the paper's full `hako run --trials 100`, and Bayesian optimization
vs. random search on the same budget.

--benches 1,2,4,...  For each N, one campaign on a LocalCluster of N benches (batch N, noise on, in this
                     process, so that the optimizer's own time per round is measured inside the very run):
                     tests per second over the campaign, the speedup over one bench, and the sampler's
                     seconds per round (median and the last round, the one with the most sets).
--full               The wall time of the paper's `hako run --trials 100` exactly as a user runs it (default
                     benches, noise on, first to 3 of 5); for the README's "how long".
--compare            BO vs random: best lap after 20, 40 and 105 sets, seeds 0, 1, 2, against a 1000-set
                     random search. These runs use `--noise 0 --repeats 1`: on the noise-free bench one test
                     gives exactly the value that the repetitions would, at a fraction of the cost.

Every `hako run` writes into --work; an existing finished campaign there is reused (and reported as such).
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import tempfile
import time
from itertools import accumulate
from pathlib import Path

import click

from hakoniwa.physics.options import BenchOptions
from testctl.campaign import Campaign, CampaignConfig
from testctl.journal import JOURNAL_FILE, read_journal
from testctl.objective import RepetitionRule

CHECKPOINTS = (20, 40, 105)


def campaign(out: Path, *args: str) -> float | None:
    """Run (or resume) one `hako run`; return the wall seconds it took, or None if it had finished before."""
    if (out / "best.json").exists():
        return None
    start = time.monotonic()
    cmd = [sys.executable, "-m", "hakoniwa.cli", "run"]
    cmd += ["--resume", str(out)] if (out / JOURNAL_FILE).exists() else [*args, "--out", str(out)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise click.ClickException(f"{' '.join(cmd)} failed: {r.stderr.strip().splitlines()[-1:]}")
    return time.monotonic() - start


def set_values(out: Path) -> list[float]:
    """The objective of each decided set, in set order."""
    header, records = read_journal(out / JOURNAL_FILE)
    rule = RepetitionRule(header["options"]["repeats"], header["options"]["max_crashes"])
    by_set: dict[int, list] = {}
    for r in sorted(records, key=lambda r: (r.set_index, r.rep)):
        by_set.setdefault(r.set_index, []).append(r.result)
    verdicts = [rule.judge(by_set[i]) for i in sorted(by_set)]
    return [v.value for v in verdicts if v.decided]


def best_after(values: list[float], n: int) -> float:
    return list(accumulate(values, min))[min(n, len(values)) - 1]


def scaling(benches: list[int], trials: int) -> None:
    """Tests per second on N benches, each N in one campaign of its own."""
    from testctl.cluster import DaskExecutor

    rows = []
    for n in benches:
        config = CampaignConfig(trials=trials, seed=0, batch=n, noise=1.0)
        executor = DaskExecutor(BenchOptions(), benches=n)
        try:
            with tempfile.TemporaryDirectory(prefix="hako-bench-campaign-") as out:
                start = time.monotonic()
                summary = Campaign(config, Path(out), executor).run()
                wall = time.monotonic() - start
        finally:
            executor.close()
        rounds = summary.proposal_s[1:]  # round 0 is the random initial design
        rows.append((n, summary.tests_run, wall, summary.tests_run / wall, statistics.median(rounds),
                     rounds[-1], len(summary.sets)))
    base = rows[0][3]
    print(f"{'benches':>7} {'tests':>6} {'wall s':>8} {'tests/s':>8} {'speedup':>8} {'x linear':>8} "
          f"{'GP s/round (median)':>20} {'GP s, last round':>17} {'sets':>5}")
    for n, tests, wall, rate, med, last, sets in rows:
        print(f"{n:>7} {tests:>6} {wall:>8.1f} {rate:>8.2f} {rate / base:>8.2f} {rate / base / n:>8.2f} "
              f"{med:>20.3f} {last:>17.3f} {sets:>5}")


@click.command()
@click.option("--benches", default=None, help="Bench counts to compare, e.g. 1,2,4,8 (the first is the baseline).")
@click.option("--trials", default=20, show_default=True, help="Optimization sets of each --benches campaign.")
@click.option("--full", is_flag=True, help="Time the paper's `hako run --trials 100`.")
@click.option("--full-benches", type=int, default=None, help="--benches for --full [hako's default].")
@click.option("--compare", is_flag=True, help="BO vs random search (long: about 4000 tests).")
@click.option("--work", type=click.Path(file_okay=False, path_type=Path), default=Path("runs/bench-campaign"),
              show_default=True, help="Where --full and --compare campaigns are written (and reused from).")
@click.option("--seeds", default="0,1,2", show_default=True, help="Seeds for --compare.")
@click.option("--reference-sets", default=1000, show_default=True, help="Sets in --compare's big random search.")
def main(benches: str | None, trials: int, full: bool, full_benches: int | None, compare: bool, work: Path,
         seeds: str, reference_sets: int) -> None:
    """Print campaign throughput and quality figures."""
    if benches:
        scaling([int(b) for b in benches.split(",")], trials)
    work.mkdir(parents=True, exist_ok=True)
    if full:
        more = [] if full_benches is None else ["--benches", str(full_benches)]
        out = work / ("paper-trials100" + (f"-benches{full_benches}" if more else ""))
        wall = campaign(out, "--trials", "100", "--seed", "0", *more)
        best = json.loads((out / "best.json").read_text())
        timed = "reused from an earlier run" if wall is None else f"{wall / 60:.1f} min wall"
        print(f"full `hako run --trials 100 {' '.join(more)}` (EI, 5 + 100 sets, first to 3 of 5, noise on): {timed}; "
              f"{best['n_tests']} tests; best lap {best['lap_time_s']:.2f} s at "
              + ", ".join(f"{k}={v:.3f}" for k, v in best["params"].items()))
    if compare:
        compare_optimizers(work, [int(s) for s in seeds.split(",")], reference_sets)


def compare_optimizers(work: Path, seeds: list[int], reference_sets: int) -> None:
    budget = ["--init-points", "5", "--trials", "100", "--repeats", "1", "--noise", "0"]
    ref = work / f"random-{reference_sets}"
    ref_wall = campaign(ref, "--optimizer", "random", "--seed", "1000", "--init-points", "5", "--trials",
                        str(reference_sets - 5), "--repeats", "1", "--noise", "0")
    ref_best = min(set_values(ref))
    print(f"reference: best lap of a {reference_sets}-set random search: {ref_best:.2f} s "
          f"({'reused' if ref_wall is None else f'{ref_wall:.0f} s wall'})")
    print(f"{'optimizer':<10}{'seed':>5}" + "".join(f"{'best@' + str(n):>11}" for n in CHECKPOINTS) + f"{'wall':>9}")
    at40: dict[str, list[float]] = {"gpyopt": [], "random": []}
    for seed in seeds:
        for opt in ("gpyopt", "random"):
            out = work / f"{opt}-s{seed}"
            wall = campaign(out, "--optimizer", opt, "--seed", str(seed), *budget)
            bests = [best_after(set_values(out), n) for n in CHECKPOINTS]
            at40[opt].append(bests[1])
            print(f"{opt:<10}{seed:>5}" + "".join(f"{b:>11.2f}" for b in bests)
                  + f"{'reused' if wall is None else f'{wall:.0f}s':>9}")
    for opt, vals in at40.items():
        med = statistics.median(vals)
        print(f"median best after 40 sets, {opt}: {med:.2f} s = {100 * (med / ref_best - 1):+.2f}% vs reference")


if __name__ == "__main__":
    main()
