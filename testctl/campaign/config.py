"""What determines a campaign's sets and results: its configuration, as the journal's header records it.

Apart from `testctl.campaign.loop` (which needs NumPy) so that the command line can show these defaults in its
help without importing anything heavy: `testctl.options` formats its help text from the fields below.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from hakoniwa.wire.measure import Measure
from hakoniwa.wire.objective import DEFAULT, Objective, objective_named
from hakoniwa.wire.protocol import MAX_NOISE_SCALE
from testctl.campaign.journal import JournalError
from testctl.campaign.repetition import RepetitionRule
from testctl.search.optimizers import OPTIMIZERS
from testctl.search.space import ParameterSpace

PHASE_INIT = "init"  # the random initial design
PHASE_BO = "bo"  # an optimization round, whichever sampler proposes it


@dataclass(frozen=True)
class CampaignConfig:
    """Everything that determines a campaign's sets and results. Only `trials` may change on resume (to
    extend a campaign); the rest is checked against the journal's header."""

    space: ParameterSpace = field(default_factory=ParameterSpace.default)
    trials: int = 100
    init_points: int = 5
    repeats: int = RepetitionRule.repeats
    max_crashes: int = RepetitionRule.max_crashes
    seed: int = 0
    optimizer: str = "gpyopt"
    batch: int = 1
    noise: float = 1.0
    penalty_s: float = RepetitionRule.penalty_s  # the bench's time limit, set by the options from course and
    # --time-limit
    objective: str = DEFAULT  # the bench's --objective, by its key: what a test's value is (`measure`)

    def __post_init__(self) -> None:
        if self.optimizer not in OPTIMIZERS:
            raise ValueError(f"unknown optimizer {self.optimizer!r}; choose from {', '.join(OPTIMIZERS)}")
        if self.trials < 0:
            raise ValueError(f"trials must be at least 0, got {self.trials}")
        if self.init_points < 1:
            raise ValueError(f"init_points must be at least 1, got {self.init_points}")
        if self.seed < 0:
            raise ValueError(f"seed must be at least 0, got {self.seed}")
        if self.batch < 1:
            raise ValueError(f"batch must be at least 1, got {self.batch}")
        if not 0.0 <= self.noise <= MAX_NOISE_SCALE:
            raise ValueError(f"noise must be a scale in 0..{MAX_NOISE_SCALE:g}, got {self.noise}")
        self.rule  # noqa: B018 (validates repeats, max_crashes and penalty_s)

    @property
    def rule(self) -> RepetitionRule:
        return RepetitionRule(self.repeats, self.max_crashes, self.penalty_s, self.scored_by)

    @property
    def scored_by(self) -> Objective:
        return objective_named(self.objective)

    @property
    def measure(self) -> Measure:
        return self.scored_by.measure

    @property
    def total_sets(self) -> int:
        return self.init_points + self.trials

    def phase(self, index: int) -> str:
        return PHASE_INIT if index < self.init_points else PHASE_BO

    def rounds(self) -> list[range]:
        """The set indices of each round: the initial design, then batches of `batch` sets."""
        out = [range(0, min(self.init_points, self.total_sets))]
        start = self.init_points
        while start < self.total_sets:
            out.append(range(start, min(start + self.batch, self.total_sets)))
            start += self.batch
        return out

    def header(self) -> dict[str, Any]:
        options = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name != "space"}
        return {"space": self.space.to_dict(), "options": options}

    @classmethod
    def from_header(cls, header: Mapping[str, Any]) -> CampaignConfig:
        """The configuration in a journal's header. A format-1 journal (before batches and noise) was a
        one-set-at-a-time campaign on a noise-free bench."""
        try:
            options = {"batch": 1, "noise": 0.0, **header["options"]}
            return cls(space=ParameterSpace.from_dict(header["space"]), **options)
        except (KeyError, TypeError, ValueError) as e:  # SpaceError is a ValueError
            raise JournalError(f"the journal header does not describe a campaign: {e}") from None
