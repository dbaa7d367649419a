"""The study mirror runs beside the campaign's loop: in order, on one other thread, and a failure there is the
campaign's failure (a bench that broke while drawing a set), raised in the loop's thread."""

from __future__ import annotations

import threading
import time

import pytest

from testctl.campaign.session import InBackground


def test_calls_run_in_order_on_another_thread_and_join_waits_for_them() -> None:
    seen: list[tuple[int, str]] = []

    def slow(i: int) -> None:
        time.sleep(0.01)
        seen.append((i, threading.current_thread().name))

    calls = InBackground(slow)
    for i in range(5):
        calls(i)
    assert len(seen) < 5  # the caller did not wait for them
    calls.join()
    assert [i for i, _ in seen] == list(range(5))
    assert {name for _, name in seen} == {"study-mirror"}


def test_a_call_that_raises_fails_the_caller_and_skips_the_calls_after_it() -> None:
    seen: list[int] = []

    def draw(i: int) -> None:
        if i == 1:
            raise OSError("the bench broke while drawing set 1")
        seen.append(i)

    calls = InBackground(draw)
    calls(0)
    calls(1)
    calls(2)
    with pytest.raises(OSError, match="while drawing set 1"):
        calls.join()
    with pytest.raises(OSError):
        calls(3)
    assert seen == [0]
