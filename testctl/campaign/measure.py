"""What a campaign's value means to a person: a lap time to lower, or ET Robocon's score to raise.

The search always minimises (GPyOpt, Optuna's samplers, the best-so-far curve, the best set): a time as it
is, a score as its negative (`TestResult.cost`). Only what people read turns it back: the figures, the
summary line, results.csv, best.json and the progress line show the score as a score.
"""

from __future__ import annotations

from dataclasses import dataclass

from hakoniwa.wire.protocol import Objective


@dataclass(frozen=True)
class Measure:
    name: str  # "lap time", "score"
    unit: str  # "s", "points"
    sign: int  # what a person reads is sign x the campaign's value

    def shown(self, value: float) -> float:
        return self.sign * value + 0.0  # + 0.0: a score of no points reads 0, not -0

    def format(self, value: float) -> str:
        """`value` (the campaign's) in words: "lap 33.12 s", "score 41.50 points"."""
        return f"{self.word} {self.shown(value):.2f} {self.unit}"

    @property
    def word(self) -> str:
        return "lap" if self is LAP_TIME else self.name

    @property
    def label(self) -> str:
        """An axis label: "lap time [s]"."""
        return f"{self.name} [{self.unit}]"

    @property
    def better(self) -> str:
        return "lowest" if self.sign > 0 else "highest"


LAP_TIME = Measure("lap time", "s", 1)
SCORE = Measure("score", "points", -1)


def measure_of(objective: str | None) -> Measure:
    """The measure of a bench's objective (by name; None: the lap, as before objectives were recorded)."""
    return SCORE if objective == Objective.ETROBOCON.name.lower() else LAP_TIME
