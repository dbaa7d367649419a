"""Waiting for another process to reach a point: one loop with a deadline, so that a wait that cannot end
fails with what it waited for instead of hanging the suite, and stops at once when what it waits on dies."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TypeVar

T = TypeVar("T")


def wait_until(predicate: Callable[[], T], timeout: float, interval: float = 0.05, *,
               alive: Callable[[], bool] | None = None, what: str = "the condition") -> T:
    """The first true value of `predicate`, polled every `interval` seconds; an AssertionError after `timeout`
    seconds, or as soon as `alive` (the process or thread that should make it true) says it is gone."""
    deadline = time.monotonic() + timeout
    while not (value := predicate()):
        assert alive is None or alive(), f"what should bring {what} is gone"
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(interval)
    return value
