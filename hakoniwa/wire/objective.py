"""What a bench's tests end at and are scored by (`--objective`): the plug-in's contract, and how one is found.

An objective is one module (`hakoniwa.objectives.lap` is the pattern) that defines `OBJECTIVE`, an `Objective`:
the task the physics server checks each test with, when a test succeeds and what it costs, how a decided set is
valued and what a failed one scores, and the measure a person reads. The built-in ones are one line each of
`BUILT_IN`; any other is named `module:attribute`, as `--app` names a Python program, so a team's own objective
(or a test's) needs no file of ours. Each process finds it by that key (`objective_named`): the physics process tasks
with it, the controller judges with it, and the journal records the key.

The contract lives with the wire, which every process shares, and the objectives are found by name at run time
(as Python's entry points are), because the task they give belongs to the physics, above the wire: the result
(`TestResult`) judges by its objective without depending on the physics it tasks.
"""

from __future__ import annotations

import functools
import importlib
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.measure import LAP_TIME, Measure
from hakoniwa.wire.protocol import Event
from hakoniwa.wire.timebase import on_tick_s

# A test's result (`hakoniwa.wire.result.TestResult`) as the contract sees it: the result asks its objective, so
# naming its type here would make the two modules a circle. A plug-in's own methods may name it.
TestResult = Any

# The built-in objectives: key -> the module that defines its OBJECTIVE. One line registers one.
BUILT_IN: dict[str, str] = {
    "lap": "hakoniwa.objectives.lap",
    "completed": "hakoniwa.objectives.completed",
    "etrobocon": "hakoniwa.objectives.etrobocon",
}
DEFAULT = "lap"  # the paper's, and a journal's from before objectives were recorded


class ObjectiveError(HakoError, ValueError):
    """An objective that cannot be found: the message is one line."""


@dataclass(frozen=True)
class Objective:
    """The paper's rule, which the built-in objectives refine: a test succeeds on `success_event` and costs its
    scored time (`scored_time_us`), a decided set is worth the mean cost on the bench's tick, a failed one the
    bench's time limit (`penalty_s`). `task` makes the physics' task for a course's checkpoints and a time limit.
    `key` is how the objective was named (`objective_named`; a built-in's is its name): what the journal and the
    physics process's command line carry."""

    name: str
    success_event: Event
    task: Callable[[Any, int], Any] = field(compare=False)  # (Course, time limit [us]) -> hakoniwa.physics Task
    measure: Measure = LAP_TIME
    key: str = ""

    def __post_init__(self) -> None:
        if not self.key:
            object.__setattr__(self, "key", self.name)

    def success(self, r: TestResult) -> bool:
        return r.event == self.success_event

    def scored_time_us(self, r: TestResult) -> int:
        """The time a successful test is scored by, on the bench's clock."""
        return r.goal_time_us

    def lap_time_s(self, r: TestResult) -> float | None:
        """The scored time of a successful test in seconds (None for a failed one)."""
        return self.scored_time_us(r) / 1e6 if self.success(r) else None

    def cost(self, r: TestResult) -> float | None:
        """What a campaign minimises for a successful test (None for a failed one)."""
        return self.lap_time_s(r)

    def set_value(self, mean_cost: float) -> float:
        """A successful set's value from its successes' mean cost: a time is put on the bench's tick."""
        return on_tick_s(mean_cost)

    def failure_value(self, penalty_s: float) -> float:
        """What a failed set scores: a test that used the whole time limit."""
        return penalty_s


@functools.cache
def objective_named(key: str) -> Objective:
    """The objective named `key`: a built-in's name or `module:attribute`."""
    module, _, attribute = BUILT_IN.get(key, key).partition(":")
    if module not in BUILT_IN.values() and not attribute:
        raise ObjectiveError(f"{key!r} is not one of {', '.join(map(repr, BUILT_IN))}, nor a module:attribute")
    try:
        found = getattr(importlib.import_module(module), attribute or "OBJECTIVE")
    except (ImportError, AttributeError) as e:
        raise ObjectiveError(f"{key!r} cannot be loaded ({type(e).__name__}: {e})") from None
    if not isinstance(found, Objective):
        raise ObjectiveError(f"{key!r} is a {type(found).__name__}, not a hakoniwa.wire.objective.Objective")
    return replace(found, key=key)
