"""The time left that `hako run`, `hako test` and `--validate` show: the tests left at the recent rate, and
for a campaign's sets the tests they are expected to take, never fewer than a set can take before any is
decided."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from hypothesis import given
from hypothesis import strategies as st

from hakoniwa.wire.protocol import Event
from testctl.suite import session
from testctl.time_left import RECENT_TESTS, Countdown, RecentRate, expected_tests_left, format_duration, time_left
from tests.helpers.campaign_doubles import result


def test_durations_read_naturally():
    assert [format_duration(s) for s in (42, 600, 7200)] == ["42 s", "10 min", "2.0 h"]


@given(st.floats(0.01, 100.0), st.integers(2, 3 * RECENT_TESTS))
def test_a_steady_rate_is_measured_exactly(step_s: float, tests: int):
    now = [0.0]
    rate = RecentRate(lambda: now[0])
    for _ in range(tests):
        now[0] += step_s
        rate.finished()
    assert abs(rate.rate() - 1 / step_s) <= 1e-6 / step_s


def test_one_finished_test_is_no_rate_yet():
    rate = RecentRate(lambda: 0.0)
    rate.finished()
    assert rate.rate() is None and time_left(10, rate.rate()) is None


@given(st.integers(0, 1000), st.integers(1, 9))
def test_before_any_set_is_decided_each_counts_as_its_most_tests(sets_left: int, repeats: int):
    assert expected_tests_left(sets_left, 0, 7, repeats) == sets_left * repeats


@given(st.integers(0, 1000), st.integers(1, 500), st.integers(3, 5))
def test_after_that_a_set_counts_as_the_decided_sets_took(sets_left: int, sets_done: int, per_set: int):
    assert expected_tests_left(sets_left, sets_done, sets_done * per_set, 5) == sets_left * per_set


def test_no_sets_left_is_no_tests_left():
    assert expected_tests_left(-2, 10, 40, 5) == 0


def test_a_countdown_says_the_rate_and_the_time_its_tests_left_take():
    now = [0.0]
    countdown = Countdown(20, clock=lambda: now[0])
    now[0] = 2.0
    assert countdown.finished() is None  # one test: no rate yet
    now[0] = 4.0
    assert countdown.finished() == f"0.50 tests/s, ~{format_duration(18 * 2.0)} left"


class FakeBar:
    def __init__(self, **kwargs) -> None:
        self.items: list[str] = []

    def __enter__(self) -> FakeBar:
        return self

    def __exit__(self, *exc) -> None:
        pass

    def update(self, n: int, current_item: str) -> None:
        self.items.append(current_item)


def test_hako_tests_progress_says_the_time_left(tmp_path: Path, monkeypatch):
    bars: list[FakeBar] = []
    monkeypatch.setattr(session.click, "progressbar", lambda **kw: bars.append(FakeBar(**kw)) or bars[-1])

    def run_cases(cases, open_executor, on_result):
        for rep in range(3):
            on_result(SimpleNamespace(set_index=0, rep=rep), result(Event.GOAL, 33.0))
        return []

    monkeypatch.setattr(session, "run_cases", run_cases)
    case = SimpleNamespace(name="gentle", seeds=(1, 2, 3, 4))
    session.run_suite(tmp_path / "t.toml", [case], tmp_path, benches=1, scheduler=None, junit_file=None,
                      json_file=None)
    items = bars[0].items
    assert items[0] == "gentle: GOAL"  # one test: no rate yet
    assert items[-1].startswith("gentle: GOAL, ") and " tests/s, ~" in items[-1] and items[-1].endswith(" left")
