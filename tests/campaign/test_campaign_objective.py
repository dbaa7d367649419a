"""The paper's first-to-3-of-5 rule, the time-limit penalty, and crash retries."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hakoniwa.wire.protocol import Event
from hakoniwa.wire.result import TestResult
from testctl.campaign.repetition import PAPER_PENALTY_S, RepetitionRule
from tests.helpers.campaign_doubles import result

G, T, W, C = Event.GOAL, Event.TIME_OVER, Event.HIT_WALL, Event.CRASH


def judge(rule: RepetitionRule, events: list[Event], lap: float = 33.0):
    return rule.judge([result(e, lap) for e in events])


def test_three_successes_decide_success_with_mean_lap() -> None:
    rule = RepetitionRule()
    v = rule.judge([result(G, 30.0), result(W), result(G, 33.0), result(T), result(G, 36.0)])
    assert (v.decided, v.success, v.successes, v.failures) == (True, True, 3, 2)
    assert v.value == pytest.approx(33.0)
    assert v.laps == (30.0, 33.0, 36.0)


def test_a_sets_mean_lap_is_on_the_benchs_tick() -> None:
    """best.json read 28.209999999999997 where each lap, and `hako try` of the patched program, read 28.21."""
    assert judge(RepetitionRule(), [G, G, G], lap=28.21).value == 28.21
    v = RepetitionRule().judge([result(G, 28.21), result(G, 28.211), result(G, 28.213)])
    assert v.value == 28.211  # 28.2113...: the mean, to the physics step (1 ms)


def test_three_failures_decide_failure_with_penalty() -> None:
    v = judge(RepetitionRule(), [G, W, T, G, W])
    assert (v.decided, v.success, v.value) == (True, False, PAPER_PENALTY_S)
    assert PAPER_PENALTY_S == 60.0  # the paper's time limit, what journals without a penalty used


def test_a_failure_scores_the_time_limit_it_ran_under() -> None:
    v = judge(RepetitionRule(penalty_s=120.0), [W, T, W])
    assert (v.decided, v.success, v.value) == (True, False, 120.0)
    with pytest.raises(ValueError, match="penalty_s"):
        RepetitionRule(penalty_s=0.0)


@pytest.mark.parametrize(
    "events, decided",
    [([], False), ([G, G], False), ([G, W, G, T], False), ([G, G, G], True), ([W, T, W], True)],
)
def test_undecided_until_one_side_reaches_three(events: list[Event], decided: bool) -> None:
    v = judge(RepetitionRule(), events)
    assert v.decided == decided
    assert (v.value is None) == (not decided)


def test_repeats_generalizes_to_a_strict_majority() -> None:
    assert [RepetitionRule(r).needed for r in (1, 3, 4, 5, 7)] == [1, 2, 3, 3, 4]
    assert judge(RepetitionRule(1), [G]).success
    assert judge(RepetitionRule(1), [W]).decided
    # Four repeats: 2-2 cannot reach 3 successes, so two failures already decide.
    assert judge(RepetitionRule(4), [G, W, W]).decided
    assert not judge(RepetitionRule(4), [G, W, G]).decided


def test_crash_is_retried_not_counted_as_failure() -> None:
    rule = RepetitionRule(max_crashes=3)
    v = judge(rule, [C, G, C, G, C, G])
    assert (v.success, v.crashes, v.failures) == (True, 3, 0)


def test_crashes_beyond_the_allowance_count_as_failures() -> None:
    rule = RepetitionRule(max_crashes=3)
    v = judge(rule, [C] * 5)
    assert (v.decided, v.failures) == (False, 2)
    v = judge(rule, [C] * 6)
    assert (v.decided, v.success, v.value, v.crashes) == (True, False, PAPER_PENALTY_S, 6)


def test_none_is_not_a_test_outcome() -> None:
    with pytest.raises(ValueError, match="NONE"):
        judge(RepetitionRule(), [Event.NONE])


@given(
    repeats=st.integers(1, 7),
    max_crashes=st.integers(0, 3),
    events=st.lists(st.sampled_from([G, T, W, C]), min_size=10, max_size=10),
)
def test_any_sequence_is_decided_within_repeats_plus_crash_allowance(
    repeats: int, max_crashes: int, events: list[Event]
) -> None:
    rule = RepetitionRule(repeats, max_crashes)
    n = next(i for i in range(len(events) + 1) if judge(rule, events[:i]).decided)
    assert n <= repeats + max_crashes
    v = judge(rule, events[:n])
    assert v.success == (v.successes >= rule.needed)
    assert v.successes + v.failures <= repeats


def test_bench_faults_are_no_test_of_the_parameters() -> None:
    from hakoniwa.wire.protocol import CrashKind

    fault = TestResult(Event.CRASH, 0, 0.01, crash_kind=CrashKind.BENCH)
    rule = RepetitionRule(max_crashes=0)
    v = rule.judge([fault] * 10 + [result(G, 30.0)])
    assert (v.decided, v.successes, v.failures, v.crashes) == (False, 1, 0, 0)


@given(
    repeats=st.integers(1, 7),
    max_crashes=st.integers(0, 3),
    events=st.lists(st.sampled_from([G, T, W, C]), min_size=12, max_size=12),
)
def test_launching_what_is_still_needed_gives_the_sequential_verdict(
    repeats: int, max_crashes: int, events: list[Event]
) -> None:
    """Tests launched in groups of `still_needed` (judged in repetition order) end exactly where the
    one-at-a-time rule ends: no test is wasted, none is missing."""
    rule = RepetitionRule(repeats, max_crashes)
    sequential = next(i for i in range(len(events) + 1) if judge(rule, events[:i]).decided)
    ran = 0
    while (k := rule.still_needed([result(e, 33.0) for e in events[:ran]])) > 0:
        assert all(not judge(rule, events[:ran + j]).decided for j in range(k))  # none decides early
        ran += k
    assert ran == sequential
