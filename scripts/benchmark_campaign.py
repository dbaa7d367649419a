"""Campaign benchmarks: benches in parallel, the paper's full `hako run --trials 100`, and the optimizers side
by side on the same budget.

--benches 1,2,4,...  For each N, one campaign on a LocalCluster of N benches (batch N, noise on, in this
                     process, so that the optimizer's own time per round is measured inside the very run):
                     tests per second over the campaign, the speedup over one bench, and the sampler's
                     seconds per round (median and the last round, the one with the most sets).
--benches 1,2,3 --pinned 1,2,4
                     The same as a user runs it: `hako run --trials N --benches B --validate 0` (batch 1, the
                     default), pinned to the first 1, 2, 4 CPUs (from --first-cpu), for every B; tests per
                     second over the campaign's tests (first test's start to last test's end, from the
                     journal) and the whole command's wall time. What `hako`'s default bench count rests on.
--full               The wall time of the paper's `hako run --trials 100` exactly as a user runs it (default
                     benches, noise on, first to 3 of 5); for the README's "how long".
--compare            Every optimizer (GPyOpt EI, Optuna's TPE, CMA-ES and GP, random search) on three problems
                     (`PROBLEMS`), 5 random + 100 proposed sets on seeds 100..104: the best lap after 10, 20,
                     40 and 105 sets (median and range over the seeds), and the optimizer's own seconds per
                     proposal measured inside the run. One test per set (`--repeats 1`): on the noise-free
                     bench one test gives exactly the value the repetitions would; with noise, a set's value is
                     one noisy lap, which is the noisy objective the optimizers then face.

Every campaign writes into --work; a finished one there is reused (and reported as such).
"""

from __future__ import annotations

import json
import multiprocessing
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from itertools import accumulate
from pathlib import Path

import click

from testctl.bench_options import BenchOptions
from testctl.campaign.journal import JOURNAL_FILE
from testctl.campaign.loop import Campaign, CampaignConfig

CHECKPOINTS = (10, 20, 40, 105)
PROBLEMS = {  # name: (space file, noise); every campaign 5 random + 100 proposed sets, one test per set
    "gains-noise0": (None, 0.0),
    "gains-noise1": (None, 1.0),
    "power4-noise0": (Path("docs/space-example.toml"), 0.0),
}
COMPARED = ("gpyopt", "tpe", "cmaes", "optuna-gp", "random")
COMPARE_APP = "line_trace_c"  # the Python tracer's laps to the microsecond (DESIGN-NOTES), 10x quicker to start


def campaign(out: Path, *args: str) -> float | None:
    """Run (or resume) one `hako run`; return the wall seconds it took, or None if it had finished before.
    A fresh one's phases are printed from its journal (`phases`)."""
    if (out / "best.json").exists():
        return None
    fresh = not (out / JOURNAL_FILE).exists()
    start, launched = time.monotonic(), time.time()
    cmd = [sys.executable, "-m", "testctl.hako", "run"]
    cmd += [*args, "--out", str(out)] if fresh else ["--resume", str(out)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise click.ClickException(f"{' '.join(cmd)} failed: {r.stderr.strip().splitlines()[-1:]}")
    wall = time.monotonic() - start
    if fresh:
        print(phases(out, launched, wall))
    return wall


def phases(out: Path, launched: float, wall: float) -> str:
    """Where a campaign's wall time went, from its journal's test times (each test's end, less its wall time,
    is its start): the start-up before the first test, the sets' tests (and within them the moments no test
    ran: a set's verdict, the next proposal and its tests' start), the validation, and what followed (the
    best set's picture and film, the report, the cluster's close)."""
    from datetime import datetime

    rows = [json.loads(line) for line in (out / JOURNAL_FILE).read_text().splitlines()[1:]]
    spans = sorted((datetime.fromisoformat(r["time"]).timestamp() - r["wall_s"],
                    datetime.fromisoformat(r["time"]).timestamp(), r["phase"] == "validation") for r in rows)
    sets = [(a, b) for a, b, v in spans if not v]
    checks = [(a, b) for a, b, v in spans if v]
    idle, reach = 0.0, sets[0][0]
    for a, b in sets:
        idle += max(0.0, a - reach)
        reach = max(reach, b)
    last = max(b for _, b, _ in spans)
    tested = (f"validation {max(b for _, b in checks) - min(a for a, _ in checks):.1f} s, " if checks else "")
    return (f"phases: start-up {sets[0][0] - launched:.1f} s, sets' tests {reach - sets[0][0]:.1f} s (no test "
            f"running {idle:.1f} s of it), {tested}after the last test {launched + wall - last:.1f} s")


def pinned_scaling(cores: list[int], benches: list[int], trials: int, first_cpu: int) -> None:
    """Campaigns as `hako run` runs them, each pinned to its cores, for the default bench count."""
    from datetime import datetime

    print(f"`hako run --trials {trials} --benches B --validate 0`, batch 1, pinned from CPU {first_cpu}; {load()}")
    print(f"{'cores':>5} {'benches':>7} {'tests':>6} {'tests s':>8} {'tests/s':>8} {'wall s':>7}")
    for c in cores:
        cpus = f"{first_cpu}-{first_cpu + c - 1}"
        for b in benches:
            with tempfile.TemporaryDirectory(prefix="hako-bench-pinned-") as tmp:
                out = Path(tmp) / "campaign"
                cmd = ["taskset", "-c", cpus, sys.executable, "-m", "testctl.hako", "run", "--trials", str(trials),
                       "--benches", str(b), "--validate", "0", "--seed", "0", "--out", str(out)]
                start = time.monotonic()
                r = subprocess.run(cmd, capture_output=True, text=True)
                wall = time.monotonic() - start
                if r.returncode != 0:
                    raise click.ClickException(f"{' '.join(cmd)} failed: {r.stderr.strip().splitlines()[-1:]}")
                rows = [json.loads(line) for line in (out / JOURNAL_FILE).read_text().splitlines()[1:]]
            ends = [datetime.fromisoformat(r["time"]).timestamp() for r in rows]
            span = max(ends) - min(e - r["wall_s"] for e, r in zip(ends, rows))
            print(f"{c:>5} {b:>7} {len(rows):>6} {span:>8.1f} {len(rows) / span:>8.2f} {wall:>7.1f}", flush=True)


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


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--benches", default=None, help="Bench counts to compare, e.g. 1,2,4,8 (the first is the baseline).")
@click.option("--pinned", default=None, help="With --benches: core counts to pin `hako run` campaigns to, e.g. "
                                           "1,2,4.")
@click.option("--first-cpu", default=0, show_default=True, help="The first CPU --pinned campaigns use.")
@click.option("--trials", default=20, show_default=True, help="Optimization sets of each --benches campaign.")
@click.option("--full", is_flag=True, help="Time the paper's `hako run --trials 100`.")
@click.option("--full-benches", type=int, default=None, help="--benches for --full [hako's default].")
@click.option("--compare", is_flag=True, help="The optimizers side by side on three problems (long: 105 tests "
                                             "a campaign).")
@click.option("--work", type=click.Path(file_okay=False, path_type=Path), default=Path("runs/bench-campaign"),
              show_default=True, help="Where --full and --compare campaigns are written (and reused from).")
@click.option("--seeds", default="100,101,102,103,104", show_default=True,
              help="Seeds for --compare (no setting of any optimizer was chosen on them).")
@click.option("--problems", default=",".join(PROBLEMS), show_default=True, help="Problems for --compare.")
@click.option("--optimizers", default=",".join(COMPARED), show_default=True, help="Optimizers for --compare.")
@click.option("--jobs", default=1, show_default=True, help="--compare campaigns run at once (one bench each).")
def main(benches: str | None, pinned: str | None, first_cpu: int, trials: int, full: bool, full_benches: int | None,
         compare: bool, work: Path, seeds: str, problems: str, optimizers: str, jobs: int) -> None:
    """Print campaign throughput and quality figures."""
    if benches and pinned:
        pinned_scaling([int(c) for c in pinned.split(",")], [int(b) for b in benches.split(",")], trials,
                       first_cpu)
    elif benches:
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
        compare_optimizers(work, [int(s) for s in seeds.split(",")], problems.split(","), optimizers.split(","), jobs)


def compare_one(work: Path, problem: str, optimizer: str, seed: int) -> dict:
    """One campaign of the comparison, in this process on one bench; its set values and the optimizer's
    seconds per proposal, kept in the campaign folder so that a rerun reuses it."""
    from testctl.bench import Bench
    from testctl.executor import SerialExecutor
    from testctl.search.space import ParameterSpace

    out = work / f"{problem}-{optimizer}-s{seed}"
    done = out / "compare.json"
    if done.exists():
        return {**json.loads(done.read_text()), "reused": True}
    space_file, noise = PROBLEMS[problem]
    space = ParameterSpace.load(space_file) if space_file else ParameterSpace.default()
    options = BenchOptions(app=COMPARE_APP)
    config = CampaignConfig(space=space, trials=100, init_points=5, repeats=1, seed=seed, optimizer=optimizer,
                            noise=noise, penalty_s=time_limit_s(options))
    if out.exists():
        shutil.rmtree(out)  # an interrupted one: its proposal times died with it
    start = time.monotonic()
    with Bench(options, out / "run", log=subprocess.DEVNULL) as bench:
        summary = Campaign(config, out, SerialExecutor(bench.run)).run()
    row = {"problem": problem, "optimizer": optimizer, "seed": seed, "values": [s.value for s in summary.sets],
           "proposal_s": list(summary.proposal_s[1:]), "wall_s": time.monotonic() - start}
    done.write_text(json.dumps(row))
    return {**row, "reused": False}


def time_limit_s(options: BenchOptions) -> float:
    from hakoniwa.physics.course import load_course

    return load_course(options.course).time_limit_us / 1e6


def spread(values: list[float]) -> str:
    return f"{statistics.median(values):.2f} [{min(values):.2f}-{max(values):.2f}]"


def compare_optimizers(work: Path, seeds: list[int], problems: list[str], optimizers: list[str], jobs: int) -> None:
    """Every (problem, optimizer, seed) campaign, `jobs` at a time; then one table per problem."""
    from concurrent.futures import ProcessPoolExecutor

    from testctl.search.optimizers import missing

    for opt in list(optimizers):
        if (why := missing(opt)) is not None:
            print(f"skipping {opt}: {why}")
            optimizers.remove(opt)
    runs = [(p, o, s) for s in seeds for p in problems for o in optimizers]
    print(f"{len(runs)} campaigns, {jobs} at a time, app {COMPARE_APP}, one test per set; {load()}", flush=True)
    rows = []
    with ProcessPoolExecutor(max_workers=jobs, mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = [pool.submit(compare_one, work, *run) for run in runs]
        for f in futures:
            row = f.result()
            rows.append(row)
            print(f"{row['problem']} {row['optimizer']} seed {row['seed']}: best "
                  + " / ".join(f"{best_after(row['values'], n):.2f}" for n in CHECKPOINTS)
                  + (" (reused)" if row["reused"] else f" ({row['wall_s']:.0f} s)"), flush=True)
    print(f"({load()} after)")
    for problem in problems:
        space_file, noise = PROBLEMS[problem]
        print(f"\n{problem}: {space_file or 'Kp, Ki, Kd in [0, 5], power 15'}, noise {noise:g}; best lap [s] after "
              f"n sets, median [min-max] over seeds {', '.join(map(str, seeds))}")
        print("| optimizer | " + " | ".join(f"after {n}" for n in CHECKPOINTS) + " | s per proposal, median [max] |")
        print("|---|" + "---:|" * (len(CHECKPOINTS) + 1))
        for opt in optimizers:
            mine = [r for r in rows if r["problem"] == problem and r["optimizer"] == opt]
            cells = [spread([best_after(r["values"], n) for r in mine]) for n in CHECKPOINTS]
            times = [t for r in mine for t in r["proposal_s"]]
            print(f"| {opt} | " + " | ".join(cells) + f" | {statistics.median(times):.3f} [{max(times):.2f}] |")


def load() -> str:
    return "load average {:.2f} {:.2f} {:.2f} on {} cores".format(*os.getloadavg(), os.cpu_count())


if __name__ == "__main__":
    main()
