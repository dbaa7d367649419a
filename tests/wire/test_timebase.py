import pytest
from hypothesis import given
from hypothesis import strategies as st

from hakoniwa.wire.timebase import Scheduler


def fire_times(tick_us: int, period_us: int, until_us: int) -> list[int]:
    fired: list[int] = []
    s = Scheduler(tick_us)
    s.add("stream", period_us, fired.append)
    while s.now_us < until_us:
        s.advance_to(s.next_tick())
    return fired


def test_rcssserver_see_pattern():
    """Seed rcssserver-see-timing.md: a 37.5 ms stream on the 10 ms timer, in every 300 ms period."""
    fired = fire_times(10_000, 37_500, 600_000)
    assert [t // 1000 for t in fired] == [40, 80, 120, 150, 190, 230, 270, 300,
                                         340, 380, 420, 450, 490, 530, 570, 600]


def test_next_tick_lets_caller_batch_to_the_next_firing():
    s = Scheduler(1_000)
    s.add("a", 10_000, lambda t: None)
    s.add("b", 25_000, lambda t: None)
    ticks = []
    while s.now_us < 50_000:
        ticks.append(s.next_tick())
        s.advance_to(ticks[-1])
    assert ticks == [10_000, 20_000, 25_000, 30_000, 40_000, 50_000]


@given(st.integers(1, 50).map(lambda k: k * 1000), st.integers(1, 200_000))
def test_firings_are_quantized_and_never_early(tick_us, period_us):
    fired = fire_times(tick_us, period_us, 1_000_000)
    for count, t in enumerate(fired, 1):
        assert t % tick_us == 0
        assert t >= period_us * count
        if period_us >= tick_us:  # then it is never late by a whole tick either
            assert t < period_us * count + tick_us


def test_reset_restarts_every_stream():
    s = Scheduler(10_000)
    fired: list[int] = []
    s.add("x", 37_500, fired.append)
    for _ in range(10):
        s.advance_to(s.next_tick())
    s.reset()
    fired.clear()
    s.advance_to(40_000)
    assert fired == [40_000]


def test_off_tick_advance_is_refused():
    with pytest.raises(ValueError):
        Scheduler(10_000).advance_to(15_000)
