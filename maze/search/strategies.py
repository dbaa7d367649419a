"""The search strategies, as explicit parts (what the mouse does after the goal, whether it closes dead ends,
whether it comes back) rather than names the explorer tests; apart from the explorer so the CLI can offer them
without loading the search."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum


class AfterGoal(Enum):
    NOTHING = "nothing"
    EVERY_UNKNOWN = "every reachable cell with an unknown wall"
    STOPPING_RULE = "only cells that could still improve the best path, until none can"


@dataclass(frozen=True)
class Strategy:
    name: str
    description: str
    after_goal: AfterGoal
    closing: bool  # close dead-end areas with virtual walls (seed dead-end-closing.md)
    returns: bool  # back to the start at the end

    @property
    def claims_optimal(self) -> bool:
        """Whether it must end knowing a best path by the objective (what the tests hold it to)."""
        return self.after_goal is not AfterGoal.NOTHING


STRATEGY_LIST = (
    Strategy("goal", "start to goal only", AfterGoal.NOTHING, closing=False, returns=False),
    Strategy("goal-return", "start to goal, then back to the start", AfterGoal.NOTHING, closing=False, returns=True),
    Strategy("full", "goal, then every reachable cell with an unknown wall, then back", AfterGoal.EVERY_UNKNOWN,
             closing=False, returns=True),
    Strategy("closing", "full exploration with dead-end areas closed by virtual walls", AfterGoal.EVERY_UNKNOWN,
             closing=True, returns=True),
    Strategy("stop", "goal, then only cells that could still improve the best path, until none can; then back",
             AfterGoal.STOPPING_RULE, closing=False, returns=True),
    Strategy("closing-stop", "the stopping rule with dead-end closing", AfterGoal.STOPPING_RULE, closing=True,
             returns=True),
)
STRATEGIES: dict[str, Strategy] = {s.name: s for s in STRATEGY_LIST}
OPTIMAL_CLAIMED = frozenset(s.name for s in STRATEGY_LIST if s.claims_optimal)
OBJECTIVES: dict[str, str] = {
    "cells": "the path with the fewest cells",
    "time": "the fastest run under the time model (maze/data/mice.toml)",
}
