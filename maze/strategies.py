"""The names of the search strategies and objectives, apart from the explorer so the CLI can offer them
without loading numpy and scipy (start-up time)."""

STRATEGIES: dict[str, str] = {
    "goal": "start to goal only",
    "goal-return": "start to goal, then back to the start",
    "full": "goal, then every reachable cell with an unknown wall, then back",
    "closing": "full exploration with dead-end areas closed by virtual walls",
    "stop": "goal, then only cells that could still improve the best path, until none can; then back",
    "closing-stop": "the stopping rule with dead-end closing",
}
OPTIMAL_CLAIMED = frozenset({"full", "closing", "stop", "closing-stop"})  # best path (by the objective) found
OBJECTIVES: dict[str, str] = {
    "cells": "the path with the fewest cells",
    "time": "the fastest run under the time model (maze/data/mice.toml)",
}
