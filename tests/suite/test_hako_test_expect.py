"""The expectations of a test case: how they are read, and what they say of a case's runs."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hakoniwa.wire.protocol import Event
from testctl.lapstats import LapStats, percentile
from testctl.suite.expect import (
    EVENTS,
    OPERATORS,
    PER_RUN,
    Bound,
    EventExpectation,
    ExpectationError,
    parse_expectation,
)
from tests.helpers.campaign_doubles import result

QUANTITIES = st.one_of(st.sampled_from([*PER_RUN, "success"]), st.integers(1, 99).map(lambda p: f"p{p}"))
LIMITS = st.floats(allow_nan=False, allow_infinity=False, min_value=-1e9, max_value=1e9)


@given(QUANTITIES, st.sampled_from(list(OPERATORS)), LIMITS)
def test_a_bound_reads_back_as_written(quantity, op, limit):
    bound = Bound(quantity, op, limit)
    assert parse_expectation(str(bound)) == bound
    assert parse_expectation(f"  {quantity}{op}{limit!r} ") == bound


@given(st.sampled_from(EVENTS), st.booleans())
def test_an_event_reads_back_as_written(event, negated):
    e = EventExpectation(event, negated)
    assert parse_expectation(str(e)) == e


@given(st.text(max_size=30))
def test_any_text_is_an_expectation_or_one_clear_error(text):
    try:
        e = parse_expectation(text)
    except ExpectationError as err:
        assert "\n" not in str(err)
    else:
        assert parse_expectation(str(e)) == e


@pytest.mark.parametrize("text, words", [
    ("speed < 3", ["no value 'speed'", "lap_s"]),
    ("p0 < 3", ["no value 'p0'"]),
    ("p100 < 3", ["no value 'p100'"]),
    ("lap_s < fast", ["'fast' is not a number"]),
    ("lap_s < inf", ["finite"]),
    ("lap_s != 3", ["neither an event"]),
    ("GOOL", ["neither an event", "GOAL"]),
    ("NONE", ["neither an event"]),
])
def test_a_bad_expectation_names_what_is_wrong(text, words):
    with pytest.raises(ExpectationError) as e:
        parse_expectation(text)
    for w in words:
        assert w in str(e.value)


@given(st.lists(st.one_of(st.floats(0, 1e3), st.just(math.inf)), min_size=1, max_size=40), st.integers(1, 99))
def test_a_percentile_is_a_measured_value_that_enough_runs_reach(values, pct):
    q = percentile(values, pct)
    assert q in values
    assert sum(v <= q for v in values) >= pct / 100 * len(values)
    assert sum(v < q for v in values) < pct / 100 * len(values)


RUNS = [result(Event.GOAL, 31.0), result(Event.GOAL, 33.0), result(Event.HIT_WALL), result(Event.GOAL, 32.0)]
LABELS = [f"seed {i}" for i in range(len(RUNS))]


@pytest.mark.parametrize("text, passed, measured", [
    ("GOAL", False, "HIT_WALL on 1 of 4 runs (first: seed 2)"),
    ("not HIT_WALL", False, "HIT_WALL on 1 of 4 runs (first: seed 2)"),
    ("not TIME_OVER", True, "no TIME_OVER on all 4 runs"),
    ("lap_s < 40", False, "no lap (seed 2; 1 of 4 runs out of bounds)"),
    ("success >= 0.75", True, "0.75"),
    ("success > 0.75", False, "0.75"),
    ("p50 <= 32", True, "32.000 s"),
    ("p75 < 40", True, "33.000 s"),
    ("p90 < 40", False, "no lap"),
])
def test_what_an_expectation_says_of_a_cases_runs(text, passed, measured):
    check = parse_expectation(text).check(RUNS, LABELS)
    assert (check.passed, check.measured) == (passed, measured)
    assert check.message() == f"{text}: measured {measured}"


def test_a_per_run_bound_reports_its_worst_run():
    finished = [r for r in RUNS if r.success]
    assert parse_expectation("lap_s < 32.5").check(finished, ["a", "b", "c"]).measured == \
        "33.000 s (b; 1 of 3 runs out of bounds)"
    assert parse_expectation("lap_s < 40").check(finished, ["a", "b", "c"]).measured == "33.000 s at worst"
    assert parse_expectation("checkpoints >= 0").check(finished, ["a", "b", "c"]).measured == "0 at worst"


def test_the_lap_statistics_count_a_run_without_a_lap_as_slowest():
    stats = LapStats.of(RUNS)
    assert (stats.runs, stats.successes, stats.success) == (4, 3, 0.75)
    assert stats.quantiles_s == {50: 32.0, 90: None}
    assert stats.describe() == "3/4 reached GOAL (success 0.75), lap p50 32.00 s, p90 no lap"
