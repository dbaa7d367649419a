"""What a campaign's value means to a person: a lap time to lower, or a score (ET Robocon's points) to raise.

The search always minimises (GPyOpt, Optuna's samplers, the best-so-far curve, the best set): a time as it
is, a score as its negative (an objective's `cost`). Only what people read turns it back: the figures, the
summary line, results.csv, best.json and the progress line show the score as a score. Each objective names
its measure (`hakoniwa.wire.objective.Objective.measure`).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Measure:
    name: str  # "lap time", "score"
    unit: str  # "s", "points"
    sign: int  # what a person reads is sign x the campaign's value
    word: str  # how a progress line names one value: "lap", "score"
    time: bool = False  # the value is a time on the bench's clock: a lap figure can mark it

    def shown(self, value: float) -> float:
        return self.sign * value + 0.0  # + 0.0: a score of no points reads 0, not -0

    def format(self, value: float) -> str:
        """`value` (the campaign's) in words: "lap 33.12 s", "score 41.50 points"."""
        return f"{self.word} {self.shown(value):.2f} {self.unit}"

    @property
    def label(self) -> str:
        """An axis label: "lap time [s]"."""
        return f"{self.name} [{self.unit}]"

    @property
    def metric(self) -> str:
        """The value the search minimises, named for Optuna: "lap time [s]", "minus the score [points]"."""
        return self.label if self.sign > 0 else f"minus the {self.label}"

    @property
    def better(self) -> str:
        return "lowest" if self.sign > 0 else "highest"


LAP_TIME = Measure("lap time", "s", 1, "lap", time=True)
SCORE = Measure("score", "points", -1, "score")
