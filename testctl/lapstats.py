"""How a parameter set fared over many noise draws: its success rate and its lap quantiles.

A run without a lap counts as an infinitely slow one, so a quantile says what it should about the set:
"p90 = 42 s" means at least 90 % of the runs finished within 42 s, however the others ended. Quantiles are
by nearest rank (the smallest lap that at least that share of the runs reach), which stays defined with
unfinished runs in the sample and is always one of the measured laps.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from hakoniwa.wire.result import TestResult

REPORTED_PERCENTILES = (50, 90)


def lap_or_inf(r: TestResult) -> float:
    return math.inf if r.lap_time_s is None else r.lap_time_s


def percentile(values: Sequence[float], pct: int) -> float:
    """The nearest-rank `pct`th percentile of `values` (which may hold infinities)."""
    if not values:
        raise ValueError("no values")
    ordered = sorted(values)
    return ordered[max(math.ceil(pct / 100 * len(ordered)), 1) - 1]


def success_rate(results: Sequence[TestResult]) -> float:
    return sum(r.success for r in results) / len(results)


@dataclass(frozen=True)
class LapStats:
    runs: int
    successes: int
    laps_s: tuple[float, ...]  # the laps of the runs that succeeded (`TestResult.lap_time_s`), in run order
    quantiles_s: dict[int, float | None]  # None: more than that share of the runs did not finish
    reached: str = "GOAL"  # the event a run succeeds on (COMPLETED under the completed objective)

    @classmethod
    def of(cls, results: Sequence[TestResult]) -> LapStats:
        everyone = [lap_or_inf(r) for r in results]
        quantiles = {p: percentile(everyone, p) for p in REPORTED_PERCENTILES}
        return cls(len(results), sum(r.success for r in results),
                   tuple(r.lap_time_s for r in results if r.lap_time_s is not None),
                   {p: None if math.isinf(q) else q for p, q in quantiles.items()}, results[0].success_event.name)

    @property
    def success(self) -> float:
        return self.successes / self.runs

    def to_dict(self) -> dict:
        return {"runs": self.runs, "successes": self.successes, "success": self.success,
                **{f"p{p}_s": q for p, q in self.quantiles_s.items()}, "laps_s": list(self.laps_s)}

    def describe(self) -> str:
        """One line for a person."""
        quantiles = ", ".join(f"p{p} {'no lap' if q is None else f'{q:.2f} s'}" for p, q in self.quantiles_s.items())
        return f"{self.successes}/{self.runs} reached {self.reached} (success {self.success:.2f}), lap {quantiles}"
