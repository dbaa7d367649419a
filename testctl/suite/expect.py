"""What a test case expects of its runs, and whether the runs met it.

An expectation is one short string in the test file, so that a person reads it as a sentence and a failure
message can quote it back: an event (`GOAL`: every run ends so; `not HIT_WALL`: none does), or a bound
`QUANTITY OP NUMBER`. Per-run quantities (`lap_s`, `checkpoints`, `distance_m`) must hold on every run; the
aggregates hold over all runs of the case: `success` (the share of runs that reached GOAL) and `pNN` (the
NNth percentile of the lap time). A run without a lap counts as an infinitely slow one, so `p90 < 42` says
"at least 90 % of the runs finished within 42 s", and `lap_s < 40` fails on a run that did not finish.

Percentiles and the success rate are `testctl.lapstats`'.
"""

from __future__ import annotations

import math
import operator
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.protocol import Event
from hakoniwa.wire.result import TestResult
from testctl.lapstats import lap_or_inf, percentile, success_rate

OPERATORS: dict[str, Callable[[float, float], bool]] = {
    "<=": operator.le, ">=": operator.ge, "==": operator.eq, "<": operator.lt, ">": operator.gt}
EVENTS = tuple(e.name for e in Event if e != Event.NONE)
# What each per-run quantity reads off a result; a run without a lap measures as infinitely slow.
PER_RUN: dict[str, Callable[[TestResult], float]] = {
    "lap_s": lap_or_inf,
    "checkpoints": lambda r: float(r.checkpoints),
    "distance_m": lambda r: r.distance_m,
}
SUCCESS = "success"
_PERCENTILE = re.compile(r"p(\d{1,2})")  # p1 .. p99 (p50 the median)
_BOUND = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*(<=|>=|==|<|>)\s*(\S+)\s*")
_EVENT = re.compile(r"\s*(not\s+)?([A-Z_]+)\s*")


class ExpectationError(HakoError, ValueError):
    """An expectation that cannot be read; the message names what is wrong in one line."""


def known_quantities() -> str:
    return ", ".join([*PER_RUN, SUCCESS, "p1..p99"])


@dataclass(frozen=True)
class Check:
    """One expectation against a case's runs: `measured` is what decided it, in words."""

    expectation: str
    passed: bool
    measured: str

    def message(self) -> str:
        return f"{self.expectation}: measured {self.measured}"


@dataclass(frozen=True)
class EventExpectation:
    event: str
    negated: bool = False

    def __str__(self) -> str:
        return f"not {self.event}" if self.negated else self.event

    def check(self, results: Sequence[TestResult], labels: Sequence[str]) -> Check:
        wrong = [(label, r.event.name) for label, r in zip(labels, results)
                 if (r.event.name == self.event) == self.negated]
        if not wrong:
            return Check(str(self), True, f"{'no ' if self.negated else ''}{self.event} on all {len(results)} runs")
        label, event = wrong[0]
        return Check(str(self), False, f"{event} on {len(wrong)} of {len(results)} runs (first: {label})")


@dataclass(frozen=True)
class Bound:
    quantity: str
    op: str
    limit: float

    def __str__(self) -> str:
        return f"{self.quantity} {self.op} {repr(self.limit).removesuffix('.0')}"

    def check(self, results: Sequence[TestResult], labels: Sequence[str]) -> Check:
        holds = OPERATORS[self.op]
        if self.quantity in PER_RUN:
            values = [PER_RUN[self.quantity](r) for r in results]
            bad = [(label, v) for label, v in zip(labels, values) if not holds(v, self.limit)]
            if bad:
                label, v = max(bad, key=lambda b: abs(b[1] - self.limit))  # the worst offender
                return Check(str(self), False,
                             f"{_show(v, self.quantity)} ({label}; {len(bad)} of {len(values)} runs out of bounds)")
            worst = max(values) if self.op in ("<", "<=") else min(values)
            return Check(str(self), True, f"{_show(worst, self.quantity)} at worst")
        if self.quantity == SUCCESS:
            value = success_rate(results)
        else:
            value = percentile([lap_or_inf(r) for r in results], int(self.quantity[1:]))  # pNN, checked when read
        return Check(str(self), holds(value, self.limit), _show(value, self.quantity))


Expectation = EventExpectation | Bound


def parse_expectation(text: str) -> Expectation:
    """An expectation from its string in the test file, or ExpectationError naming the problem."""
    if not isinstance(text, str):
        raise ExpectationError(f"an expectation must be a string such as \"lap_s < 40\", got {text!r}")
    m = _BOUND.fullmatch(text)
    if m:
        quantity, op, number = m.groups()
        if quantity not in PER_RUN and quantity != SUCCESS and _pct(quantity) is None:
            raise ExpectationError(f"{text!r}: there is no value {quantity!r} (known: {known_quantities()})")
        try:
            limit = float(number)
        except ValueError:
            raise ExpectationError(f"{text!r}: {number!r} is not a number") from None
        if not math.isfinite(limit):
            raise ExpectationError(f"{text!r}: the bound must be a finite number")
        return Bound(quantity, op, limit)
    m = _EVENT.fullmatch(text)
    if m and m.group(2) in EVENTS:
        return EventExpectation(m.group(2), bool(m.group(1)))
    raise ExpectationError(f"{text!r} is neither an event ({', '.join(EVENTS)}, or 'not' one) nor a bound "
                           f"'VALUE OP NUMBER' with VALUE one of {known_quantities()} and OP one of "
                           f"{' '.join(OPERATORS)}")


def _pct(quantity: str) -> int | None:
    m = _PERCENTILE.fullmatch(quantity)
    return int(m.group(1)) if m and 1 <= int(m.group(1)) <= 99 else None


def _show(value: float, quantity: str) -> str:
    if quantity == SUCCESS:
        return f"{value:.3g}"
    if quantity == "checkpoints":
        return f"{value:g}"
    if quantity == "distance_m":
        return f"{value:.3f} m"
    return "no lap" if math.isinf(value) else f"{value:.3f} s"
