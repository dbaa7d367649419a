"""Campaign benchmarks: the wall time of the paper's `hako run --trials 100`, and Bayesian optimization vs.
random search on the same budget.

The comparison runs use `--repeats 1`: a trial on this bench is deterministic (same parameters, same event,
same microsecond), so one test gives exactly the value that three equal tests of the first-to-3 rule give,
at a third of the cost. The full run keeps the paper's rule (first to 3 of 5).

Every campaign is a real `hako run` (three processes per campaign) writing into --work; an existing finished
campaign there is reused, so an interrupted benchmark continues where it stopped.
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from itertools import accumulate
from pathlib import Path

import click

from testctl.journal import JOURNAL_FILE, read_journal
from testctl.objective import RepetitionRule

CHECKPOINTS = (20, 40, 105)


def campaign(out: Path, *args: str) -> float | None:
    """Run (or resume) one campaign; return the wall seconds it took, or None if it had finished before."""
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
    """The objective of each decided set, in order."""
    header, records = read_journal(out / JOURNAL_FILE)
    rule = RepetitionRule(header["options"]["repeats"], header["options"]["max_crashes"])
    by_set: dict[int, list] = {}
    for r in records:
        by_set.setdefault(r.set_index, []).append(r.result)
    verdicts = [rule.judge(by_set[i]) for i in sorted(by_set)]
    return [v.value for v in verdicts if v.decided]


def best_after(values: list[float], n: int) -> float:
    return list(accumulate(values, min))[min(n, len(values)) - 1]


@click.command()
@click.option("--work", type=click.Path(file_okay=False, path_type=Path), default=Path("runs/bench-campaign"),
              show_default=True, help="Where the campaigns are written (and reused from).")
@click.option("--seeds", default="0,1,2", show_default=True, help="Seeds for BO vs random.")
@click.option("--reference-sets", default=1000, show_default=True, help="Sets in the big random search.")
@click.option("--skip-full", is_flag=True, help="Skip the timed paper run (`hako run --trials 100`).")
@click.option("--jobs", default=1, show_default=True,
              help="Comparison campaigns run side by side (the timed full run always runs alone, first).")
def main(work: Path, seeds: str, reference_sets: int, skip_full: bool, jobs: int) -> None:
    """Print the full-run wall time and BO-vs-random best laps after 20, 40 and 105 parameter sets."""
    work.mkdir(parents=True, exist_ok=True)
    seed_list = [int(s) for s in seeds.split(",")]
    budget = ["--init-points", "5", "--trials", "100", "--repeats", "1"]
    jobs_list: list[tuple[str, Path, list[str]]] = []
    for seed in seed_list:
        for opt in ("gpyopt", "random"):
            jobs_list.append((f"{opt} seed {seed}", work / f"{opt}-s{seed}",
                              ["--optimizer", opt, "--seed", str(seed), *budget]))
    ref = work / f"random-{reference_sets}"
    jobs_list.insert(0, (f"random {reference_sets} sets", ref,
                      ["--optimizer", "random", "--seed", "1000", "--init-points", "5", "--trials",
                       str(reference_sets - 5), "--repeats", "1"]))
    full_line = ""
    if not skip_full:
        full = work / "paper-trials100"
        wall = campaign(full, "--trials", "100", "--seed", "0")
        best = json.loads((full / "best.json").read_text())
        timed = "reused from an earlier run" if wall is None else f"{wall / 60:.1f} min wall"
        full_line = (f"full `hako run --trials 100` (EI, 5 + 100 sets, first to 3 of 5): {timed}; "
                     f"{best['n_tests']} tests; best lap {best['lap_time_s']:.2f} s at "
                     + ", ".join(f"{k}={v:.3f}" for k, v in best["params"].items()))

    with ThreadPoolExecutor(max_workers=jobs) as pool:  # the longest (the reference) first
        walls = dict(zip([j[0] for j in jobs_list], pool.map(lambda j: campaign(j[1], *j[2]), jobs_list)))

    def wall_text(label: str) -> str:
        return "reused" if walls[label] is None else f"{walls[label]:.0f}s"

    ref_best = min(set_values(ref))
    print(f"reference: best lap of a {reference_sets}-set random search: {ref_best:.2f} s "
          f"(wall {wall_text(f'random {reference_sets} sets')})")
    print(f"{'optimizer':<10}{'seed':>5}" + "".join(f"{'best@' + str(n):>11}" for n in CHECKPOINTS) + f"{'wall':>9}")
    at40: dict[str, list[float]] = {"gpyopt": [], "random": []}
    for label, out, _ in jobs_list[1:]:
        opt, _, seed = label.split()
        values = set_values(out)
        bests = [best_after(values, n) for n in CHECKPOINTS]
        at40[opt].append(bests[1])
        print(f"{opt:<10}{seed:>5}" + "".join(f"{b:>11.2f}" for b in bests) + f"{wall_text(label):>9}")
    for opt, vals in at40.items():
        med = statistics.median(vals)
        print(f"median best after 40 sets, {opt}: {med:.2f} s = {100 * (med / ref_best - 1):+.2f}% vs reference")
    if full_line:
        print(full_line)


if __name__ == "__main__":
    main()
