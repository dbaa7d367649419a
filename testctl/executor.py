"""Where a campaign's tests run: the interface the campaign talks to, and the simplest executor.

The campaign submits `TestSpec`s (one repetition of one parameter set, with its noise) and takes finished
ones back in whatever order they finish; a set's verdict never depends on that order. `SerialExecutor` runs
them one at a time on one bench, in submission order: the controller attached to a single physics process
(the paper's arrangement), and the campaign's tests. `testctl.cluster` runs them on many benches.
`results_of` feeds any executor a few tests per bench at a time, for the campaign, its validation and
`hako test` alike.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from itertools import islice

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.result import TestResult

WINDOW_PER_BENCH = 2  # tests handed to the executor per bench ahead of their results: none waits for work


@dataclass(frozen=True)
class TestSpec:
    """One test to run: repetition `rep` (from 1) of set `set_index` (from 0) with its parameters
    ({slot offset: value}, each slot a float32 unless `slot_types` says otherwise) and the noise draw it
    gets."""

    __test__ = False  # not a pytest class

    set_index: int
    rep: int
    params: Mapping[int, float]
    noise_seed: int = 0
    noise_scale: float = 0.0
    slot_types: Mapping[int, str] = field(default_factory=dict)


class Executor(ABC):
    capacity: int = 1  # benches

    @abstractmethod
    def submit(self, spec: TestSpec) -> None:
        """Queue a test; it runs when a bench is free."""

    @abstractmethod
    def next_result(self) -> tuple[TestSpec, TestResult, str]:
        """Block until a submitted test finishes; return it with its result and the name of its bench."""

    @property
    @abstractmethod
    def running(self) -> int:
        """Tests submitted and not yet returned, at most `capacity` of them on benches."""


class SerialExecutor(Executor):
    def __init__(self, run_test: Callable[[TestSpec], TestResult], name: str = "bench") -> None:
        self.run_test = run_test
        self.name = name
        self._queue: deque[TestSpec] = deque()

    def submit(self, spec: TestSpec) -> None:
        self._queue.append(spec)

    def next_result(self) -> tuple[TestSpec, TestResult, str]:
        spec = self._queue.popleft()
        return spec, self.run_test(spec), self.name

    @property
    def running(self) -> int:
        return min(len(self._queue), self.capacity)


class BenchFault(HakoError, RuntimeError):
    """A bench spoiled a test that cannot be run again in its place (a `hako test` run, a validation, a
    campaign's picture): the run is broken (exit 2), whatever the test would have shown."""


def results_of(executor: Executor, specs: Iterable[TestSpec]) -> Iterator[tuple[TestSpec, TestResult, str]]:
    """Run every spec on `executor`, yielding each as it finishes with its result and bench. Only
    WINDOW_PER_BENCH tests per bench are out at a time: a local cluster's scheduler lives in this process,
    and 100 000 tests submitted at once held every one of them there (memory grew by 20 MB/s)."""
    todo = iter(specs)
    pending = 0
    for spec in islice(todo, WINDOW_PER_BENCH * executor.capacity):
        executor.submit(spec)
        pending += 1
    while pending:
        finished = executor.next_result()
        pending -= 1
        for spec in islice(todo, 1):  # the bench's next test before this one's result is handled
            executor.submit(spec)
            pending += 1
        yield finished


def bench_fault(result: TestResult, bench: str) -> BenchFault:
    return BenchFault(f"the bench {bench} spoiled a test ({result.crash_reason()}); "
                      "a bench fault says nothing of the program, so the test run is void")
