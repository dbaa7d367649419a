"""Test doubles for the campaign tests: stand-ins for the trial runner, never used outside tests."""

from __future__ import annotations

from collections.abc import Iterable

from hakoniwa.wire.protocol import CrashKind, Event, Rx
from hakoniwa.wire.result import TestResult
from testctl.executor import TestSpec


def result(event: Event, lap_s: float = 0.0) -> TestResult:
    return TestResult(event, round(lap_s * 1e6) if event == Event.GOAL else 0, 0.01)


BENCH_FAULT = TestResult(Event.CRASH, 0, 0.01, crash_kind=CrashKind.BENCH, crash_detail=3)


class SyntheticBench:
    """A deterministic fake bench: the lap grows with the distance from the paper's best point
    (Kp, Ki, Kd) = (1.5, 4.3, 4.5); inside the GOAL region (lap < 50 s) the robot finishes, outside it hits
    a wall (large Kp) or runs out of time. Counts calls, so tests can check nothing ran twice."""

    def __init__(self) -> None:
        self.calls: list[TestSpec] = []

    def __call__(self, spec: TestSpec) -> TestResult:
        self.calls.append(spec)
        params = spec.params
        assert params[Rx.MOTOR_POWER] == 15.0
        kp, ki, kd = params[Rx.KP], params[Rx.KI], params[Rx.KD]
        lap = 32.0 + 2.0 * ((kp - 1.5) ** 2 + (ki - 4.3) ** 2 + (kd - 4.5) ** 2)
        if lap < 50.0:
            return result(Event.GOAL, lap)
        return result(Event.HIT_WALL if kp > 2.5 else Event.TIME_OVER)


class Killed(Exception):
    """Stands for the user's Ctrl-C / kill arriving while a test runs."""


class KilledAfter:
    """Wraps a bench and raises `Killed` instead of running test number `k + 1`."""

    def __init__(self, bench: SyntheticBench, k: int) -> None:
        self.bench = bench
        self.k = k
        self.n = 0

    def __call__(self, spec: TestSpec) -> TestResult:
        if self.n == self.k:
            raise Killed
        self.n += 1
        return self.bench(spec)


class ScriptedBench:
    """Returns the given results in order, whatever the parameters."""

    def __init__(self, results: Iterable[TestResult]) -> None:
        self.results = list(results)
        self.n = 0

    def __call__(self, spec: TestSpec) -> TestResult:
        r = self.results[self.n]
        self.n += 1
        return r
