"""Sampler benchmarks: the optimizer's own time per round (fit the GP, propose q points), and what batching
and the speed-ups cost in quality.

Quality is measured on synthetic lap-time objectives over the paper's space (Kp, Ki, Kd in [0, 5]): each
has a floor (no gains make the robot faster than its motors allow) and a 60 s penalty plateau where the
robot fails. `basins` is the one the sampler's settings were chosen on; `valley` and `doubles` (the lap of the
campaign tests' synthetic bench) were not looked at while choosing. Every campaign starts from the same 5
random sets per seed, then runs rounds of q proposals until the budget of sets. The reference is the sampler
as it was before batches (`PreBatchGPyOpt`).

`time_per_round` is also what scripts/benchmark_campaign.py reports as the GP's time per round.
"""

from __future__ import annotations

import os
import statistics
import time
from collections.abc import Callable
from typing import Protocol

import click
import numpy as np

from testctl.campaign.repetition import PAPER_PENALTY_S as PENALTY_S
from testctl.search.sampler import LIES, GPyOptSampler, RandomSampler
from testctl.search.space import ParameterSpace

SPACE = ParameterSpace.default()
INIT_POINTS = 5
Objective = Callable[[np.ndarray], float]


class Proposer(Protocol):
    def suggest_batch(
        self, space: ParameterSpace, X: np.ndarray, Y: np.ndarray, round_index: int, q: int
    ) -> list[tuple[float, ...]]: ...


def basins(x: np.ndarray) -> float:
    """A round bowl to 32.3 s and, apart from it, a wider and shallower one to 33.0 s that can trap a greedy
    search; failing for Kp > 3.5 (30% of the space)."""
    if x[0] > 3.5:
        return PENALTY_S
    best = 32.3 + 2.0 * float(np.sum((x - (1.2, 3.6, 2.8)) ** 2))
    trap = 33.0 + 1.0 * float(np.sum((x - (0.6, 1.0, 4.2)) ** 2))
    return min(best, trap, PENALTY_S)


def valley(x: np.ndarray) -> float:
    """A narrow valley along a tilted line in (Ki, Kd); failing for Ki < 1.5 and beyond 60 s (37% in all)."""
    kp, ki, kd = x
    if ki < 1.5:
        return PENALTY_S
    return min(33.0 + 3.0 * (kd - 0.8 * ki - 0.5) ** 2 + 0.8 * (kp - 2.0) ** 2 + 0.3 * (ki - 3.0) ** 2, PENALTY_S)


def doubles(x: np.ndarray) -> float:
    """The lap of the campaign tests' synthetic bench (tests/helpers/campaign_doubles.py): 2 s per unit of squared
    distance from the paper's best gains (1.5, 4.3, 4.5) above 32 s, failing from 50 s on (69%)."""
    lap = 32.0 + 2.0 * float(np.sum((x - (1.5, 4.3, 4.5)) ** 2))
    return lap if lap < 50.0 else PENALTY_S


OBJECTIVES: dict[str, tuple[Objective, float]] = {
    "basins": (basins, 32.3),
    "valley": (valley, 33.0),
    "doubles": (doubles, 32.0),
}
"""Name: (objective, its least value)."""


def synthetic_data(n_sets: int) -> tuple[np.ndarray, np.ndarray]:
    """n_sets uniform points of the paper's space and their `basins` values, as a campaign's X and Y."""
    X = np.random.default_rng(n_sets).uniform(0.0, 5.0, size=(n_sets, SPACE.dim))
    return X, np.array([[basins(x)] for x in X])


def time_per_round(n_sets: int, q: int, repeats: int = 5, sampler: Proposer | None = None) -> float:
    """Median wall seconds of one round of q proposals (GPyOpt EI unless `sampler` is given) after n_sets
    finished sets; one warm-up round first, which pays for importing GPyOpt."""
    sampler = sampler or GPyOptSampler(seed=0)
    X, Y = synthetic_data(n_sets)
    sampler.suggest_batch(SPACE, X, Y, 0, q)
    times = []
    for r in range(1, repeats + 1):
        start = time.perf_counter()
        sampler.suggest_batch(SPACE, X, Y, r, q)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


class PreBatchGPyOpt:
    """The sampler as it was before batches, the reference for quality and speed: a fresh GPyOpt
    BayesianOptimization per suggestion (5 GP restarts, GPyOpt's acquisition optimizer), one point."""

    def __init__(self, seed: int) -> None:
        self.seed = seed

    def suggest_batch(
        self, space: ParameterSpace, X: np.ndarray, Y: np.ndarray, round_index: int, q: int
    ) -> list[tuple[float, ...]]:
        from GPyOpt.methods import BayesianOptimization

        assert q == 1
        domain = [{"name": p.name, "type": "continuous", "domain": (p.low, p.high)} for p in space.params]
        saved = np.random.get_state()
        np.random.seed(int(np.random.default_rng([self.seed, round_index]).integers(2**32)))
        try:
            x = BayesianOptimization(f=None, domain=domain, X=X, Y=Y, acquisition_type="EI").suggest_next_locations()
        finally:
            np.random.set_state(saved)
        return [tuple(float(v) for v in x[0])]


def run_campaign(sampler: Proposer, objective: Objective, seed: int, q: int, budget: int) -> list[float]:
    """The objective values of `budget` sets, in order: the 5 shared initial sets, then rounds of q."""
    X = np.array(RandomSampler(seed).suggest_batch(SPACE, np.empty((0, 3)), np.empty((0, 1)), 0, INIT_POINTS))
    Y = np.array([[objective(x)] for x in X])
    round_index = 1
    while len(X) < budget:
        batch = np.array(sampler.suggest_batch(SPACE, X, Y, round_index, min(q, budget - len(X))))
        X = np.vstack([X, batch])
        Y = np.vstack([Y, [[objective(x)] for x in batch]])
        round_index += 1
    return [float(y) for y in Y[:, 0]]


def quality_methods(lies: bool) -> dict[str, tuple[Callable[[int], Proposer], int]]:
    """Label: (sampler for a seed, q). With `lies`, every lie for q > 1; else the default one."""
    methods: dict[str, tuple[Callable[[int], Proposer], int]] = {
        "random search": (RandomSampler, 1),
        "pre-batch EI": (PreBatchGPyOpt, 1),
        "EI q=1": (GPyOptSampler, 1),
    }
    for q in (4, 8):
        if lies:
            for lie in LIES:
                methods[f"EI q={q} lie={lie}"] = (lambda seed, lie=lie: GPyOptSampler(seed, lie=lie), q)
        else:
            methods[f"EI q={q}"] = (GPyOptSampler, q)
    return methods


def load() -> str:
    return "load average {:.2f} {:.2f} {:.2f} on {} cores".format(*os.getloadavg(), os.cpu_count())


def print_timing(sizes: list[int], qs: list[int], repeats: int) -> None:
    import GPyOpt  # noqa: F401  (loaded first, so that the thread limit below covers its libraries)
    from threadpoolctl import threadpool_limits

    print(f"seconds per round, median of {repeats} ({load()} before):")
    print("| sets n | " + " | ".join(f"EI q={q}" for q in qs) + " | pre-batch EI | pre-batch EI, 1 thread |")
    print("|---:|" + "---:|" * (len(qs) + 2))
    for n in sizes:
        cells = [time_per_round(n, q, repeats) for q in qs]
        cells.append(time_per_round(n, 1, repeats, PreBatchGPyOpt(0)))
        with threadpool_limits(limits=1):
            cells.append(time_per_round(n, 1, repeats, PreBatchGPyOpt(0)))
        print(f"| {n} | " + " | ".join(f"{c:.3f}" for c in cells) + " |", flush=True)
    print(f"({load()} after)")


def print_quality(objectives: list[str], seeds: list[int], budget: int, lies: bool) -> None:
    import GPyOpt  # noqa: F401  (as in print_timing)
    from threadpoolctl import threadpool_limits

    checkpoints = sorted({budget // 2, 3 * budget // 4, budget})
    print(f"\nbest value found minus the objective's least value (s): median [mean] over {len(seeds)} seeds; "
          f"{INIT_POINTS} shared random sets, then rounds of q")
    for name in objectives:
        objective, least = OBJECTIVES[name]
        chosen_on = " (the objective the settings were chosen on)" if name == "basins" else ""
        print(f"\n{name}, least {least} s{chosen_on}")
        print("| method | " + " | ".join(f"after {n} sets" for n in checkpoints) + " | wall s |")
        print("|---|" + "---:|" * (len(checkpoints) + 1))
        for label, (factory, q) in quality_methods(lies).items():
            start = time.perf_counter()
            with threadpool_limits(limits=1):  # for the pre-batch sampler's speed; no value changes
                runs = [run_campaign(factory(seed), objective, seed, q, budget) for seed in seeds]
            cells = []
            for n in checkpoints:
                regrets = [min(values[:n]) - least for values in runs]
                cells.append(f"{statistics.median(regrets):.3f} [{statistics.mean(regrets):.3f}]")
            print(f"| {label} | " + " | ".join(cells) + f" | {time.perf_counter() - start:.0f} |", flush=True)


@click.command()
@click.option("--sizes", default="10,50,105", show_default=True, help="Finished sets n for the timing table.")
@click.option("--qs", default="1,2,4,8", show_default=True, help="Batch sizes for the timing table.")
@click.option("--repeats", default=7, show_default=True, help="Timed rounds per cell (the median is printed).")
@click.option("--objectives", default=",".join(OBJECTIVES), show_default=True, help="Objectives for quality.")
@click.option("--seeds", default=20, show_default=True, help="Quality campaigns per method: seeds 0..N-1.")
@click.option("--budget", default=40, show_default=True, help="Sets per quality campaign (initial ones included).")
@click.option("--lies", is_flag=True, help="Compare the liar's values min, mean and max for q > 1.")
@click.option("--skip-timing", is_flag=True)
@click.option("--skip-quality", is_flag=True)
def main(sizes: str, qs: str, repeats: int, objectives: str, seeds: int, budget: int, lies: bool,
         skip_timing: bool, skip_quality: bool) -> None:
    """Print seconds per round (n x q) and the best values found (method x objective)."""
    if not skip_timing:
        print_timing([int(n) for n in sizes.split(",")], [int(q) for q in qs.split(",")], repeats)
    if not skip_quality:
        print_quality(objectives.split(","), list(range(seeds)), budget, lies)


if __name__ == "__main__":
    main()
