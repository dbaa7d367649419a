"""The progress line's rate and time left come from recent tests, so a campaign that slows down is not
promised an end it cannot keep."""

from __future__ import annotations

from hakoniwa.wire.protocol import Event
from testctl.campaign.journal import TestRecord
from testctl.campaign.loop import Progress
from testctl.campaign.progress import PLAIN_EVERY_S, PLAIN_EVERY_TESTS, ProgressLine
from testctl.time_left import RECENT_TESTS, format_duration
from tests.helpers.campaign_doubles import result


class FakeBar:
    def __init__(self) -> None:
        self.items: list[str] = []
        self.done = 0

    def update(self, n: int, current_item: str) -> None:
        self.done += n
        self.items.append(current_item)


def test_rate_and_time_left_follow_recent_tests():
    now = [0.0]
    bar = FakeBar()
    line = ProgressLine(bar, clock=lambda: now[0])
    record = TestRecord(0, "init", {}, 1, result(Event.GOAL, 33.0), "t")
    line(Progress(0, 100, 0, None, None, 0, 2))
    tests = 0
    for step in [0.1] * 100 + [1.0] * RECENT_TESTS:  # fast at first, then ten times slower
        now[0] += step
        tests += 1
        line(Progress(tests // 3, 100, tests, None, record, 2, 2))
    assert line.rate() == 1.0
    sets_left = 100 - tests // 3
    assert f"~{format_duration(sets_left * 3 / 1.0)} left" in bar.items[-1]  # 3 tests a set, 1 test/s
    assert bar.items[-1].startswith("benches 2/2 busy, 1.00 tests/s")
    assert bar.done == tests // 3


def test_before_any_set_is_decided_a_set_counts_as_its_most_tests():
    now = [0.0]
    bar = FakeBar()
    line = ProgressLine(bar, clock=lambda: now[0], repeats=5)
    record = TestRecord(0, "init", {}, 1, result(Event.GOAL, 33.0), "t")
    line(Progress(0, 10, 0, None, None, 0, 1))
    for tests in (1, 2):
        now[0] += 1.0
        line(Progress(0, 10, tests, None, record, 1, 1))
    assert bar.items[-1].startswith(f"benches 1/1 busy, 1.00 tests/s, ~{format_duration(10 * 5)} left")


def test_off_a_terminal_a_plain_line_comes_every_n_tests_or_n_seconds():
    now = [0.0]
    lines: list[str] = []
    line = ProgressLine(FakeBar(), clock=lambda: now[0], plain=lines.append)
    record = TestRecord(0, "init", {}, 1, result(Event.GOAL, 33.0), "t")
    line(Progress(0, 10, 0, None, None, 0, 1))
    assert lines == ["sets 0/10, tests 0, benches 0/1 busy, no lap yet"]
    for tests in range(1, 2 * PLAIN_EVERY_TESTS + 1):  # quick tests: a line every PLAIN_EVERY_TESTS
        now[0] += 0.1
        line(Progress(0, 10, tests, None, record, 1, 1))
    assert len(lines) == 3 and lines[-1].startswith(f"sets 0/10, tests {2 * PLAIN_EVERY_TESTS}, ")
    now[0] += PLAIN_EVERY_S  # one slow test: a line, although only one test finished
    line(Progress(0, 10, 2 * PLAIN_EVERY_TESTS + 1, None, record, 1, 1))
    assert len(lines) == 4

