"""The controller's side of one test: write parameters, raise start, wait for the event, lower start.

This is the only module of the controller that touches the mapped files, and it touches only what the
paper gives the controller: the parameter area and the event/goal-time words of unity_mmap.bin, and the
start/end flags of athrill_mmap.bin, plus the noise seed and scale of each test (`Rx.NOISE_SEED`,
`Rx.NOISE_SCALE`; docs/NOISE.md). Under ET Robocon's score the physics process also leaves the score's
components in the run directory (`SCORE_FILE`), as it leaves a crashed program's last words.
"""

from __future__ import annotations

import dataclasses
import json
import math
import subprocess
import time
from collections.abc import Callable, Mapping
from pathlib import Path

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.etrobocon_rules import Score
from hakoniwa.wire.params import SLOT_FORMATS, encode, fits_area
from hakoniwa.wire.protocol import (
    MAX_NOISE_SCALE,
    BenchCause,
    CrashKind,
    Event,
    LayoutError,
    LayoutFile,
    Objective,
    Rx,
    SyncMode,
    Tx,
    goal_time_from_words,
    poll_athrill,
    poll_unity,
)
from hakoniwa.wire.result import TestResult
from hakoniwa.wire.rundir import PROGRAM_OUTPUT_FILE, SCORE_FILE
from hakoniwa.wire.waiting import pid_alive, wait_for

POLL_S = 0.002  # a test takes about a second; a 2 ms nap costs nothing and leaves the CPU to the bench


class PhysicsGone(HakoError, RuntimeError):
    """The physics process stopped answering; no further test can run in this run directory. `stalled`: it
    still ran but reported nothing in time (said here, since whether a just-killed process has been reaped
    yet is a race)."""

    def __init__(self, message: str, *, stalled: bool = False) -> None:
        super().__init__(message)
        self.stalled = stalled


class TrialRunner:
    @classmethod
    def attach(cls, run_dir: Path, physics: subprocess.Popen, timeout_s: float = 60.0) -> TrialRunner:
        """Connect to a physics process that is still starting: its files appear once its world is built.
        Files an earlier run left in the directory are not its files: they name another physics process."""
        deadline = time.monotonic() + timeout_s
        while True:
            try:
                runner = cls(run_dir)
                if runner._physics_pid == physics.pid:
                    return runner
                runner.close()
                problem: Exception = LayoutError(f"{run_dir}: the physics process {physics.pid} made no files")
            except LayoutError as e:
                problem = e
            if physics.poll() is not None or time.monotonic() > deadline:
                raise problem
            time.sleep(0.05)

    def __init__(self, run_dir: Path, *, test_timeout_s: float = 600.0) -> None:
        self.run_dir = Path(run_dir)
        self.test_timeout_s = test_timeout_s
        # Read and written, not mapped: a file truncated under the bench cannot kill the controller (SIGBUS).
        self.unity: LayoutFile = poll_unity(self.run_dir)
        self.athrill: LayoutFile = poll_athrill(self.run_dir)
        self._physics_pid = self.unity.read_u32(Rx.PHYSICS_PID)

    def write_params(self, params: Mapping[int, float], slot_types: Mapping[int, str] | None = None) -> None:
        """Each value into its slot, as a float32 unless `slot_types` names the slot's type."""
        for offset, value in params.items():
            kind = (slot_types or {}).get(offset, "f32")
            if not fits_area(offset, kind):
                raise LayoutError(f"parameter offset {offset} ({kind}) is outside the parameter area")
            self.unity.write(SLOT_FORMATS[kind], offset, encode(kind, float(value)))

    def write_noise(self, seed: int, scale: float) -> None:
        """The noise of the next test: `seed` (u32) picks the draw, `scale` multiplies the course's noise
        levels (0: none at all, the exactly repeatable bench; 1: the course's levels)."""
        if not 0 <= seed <= 0xFFFFFFFF:
            raise ValueError(f"noise seed must be in 0..{0xFFFFFFFF}, got {seed}")
        if not (math.isfinite(scale) and 0 <= scale <= MAX_NOISE_SCALE):
            raise ValueError(f"noise scale must be a number in 0..{MAX_NOISE_SCALE:g}, got {scale!r}")
        self.unity.write_u32(Rx.NOISE_SEED, seed)
        self.unity.write_f32(Rx.NOISE_SCALE, float(scale))

    def run_test(self, params: Mapping[int, float], *, noise_seed: int = 0, noise_scale: float = 0.0,
                 slot_types: Mapping[int, str] | None = None) -> TestResult:
        """One test with `params` ({slot offset: value}, typed by `slot_types`: float32 by default) and the
        noise draw `noise_seed` at `noise_scale` (by default none); blocks until the physics process reports
        an event and has reset for the next test."""
        start = time.monotonic()
        u = self.unity
        self._wait(lambda: u.read_i32(Rx.EVENT) == Event.NONE, "reset before the test")
        self.write_params(params, slot_types)
        self.write_noise(noise_seed, noise_scale)
        self.athrill.write_i32(Tx.START, 1)
        self._wait(lambda: u.read_i32(Rx.EVENT) != Event.NONE, "an event")
        result = self.read_result()
        if result.objective == Objective.ETROBOCON and result.event != Event.CRASH:
            result = dataclasses.replace(result, score=self._score())
        self.athrill.write_i32(Tx.START, 0)
        self._wait(lambda: u.read_i32(Rx.EVENT) == Event.NONE, "the reset after the test")
        return dataclasses.replace(result, wall_s=time.monotonic() - start)

    def read_result(self) -> TestResult:
        """The test's result as the physics process reported it in unity_mmap.bin (`Slots.report`), but for its
        wall time and ET Robocon's score, which `run_test` adds."""
        u = self.unity
        event = Event(u.read_i32(Rx.EVENT))
        goal_us = goal_time_from_words(u.read_u32(Rx.GOAL_TIME_HI), u.read_u32(Rx.GOAL_TIME_LO))
        return TestResult(event, goal_us if event == Event.GOAL else 0, 0.0, u.read_u32(Rx.CHECKPOINTS),
                          u.read_u32(Rx.DISTANCE_MM), u.read_u32(Rx.MAX_TIME_DIFF_US),
                          SyncMode(u.read_u32(Rx.SYNC_MODE)), CrashKind(u.read_i32(Rx.CRASH_KIND)),
                          u.read_i32(Rx.CRASH_DETAIL), self._program_output() if event == Event.CRASH else "",
                          goal_time_from_words(u.read_u32(Rx.COMPLETED_TIME_HI), u.read_u32(Rx.COMPLETED_TIME_LO)),
                          Objective(u.read_u32(Rx.OBJECTIVE)), BenchCause(u.read_u32(Rx.BENCH_CAUSE)),
                          out_time_us=goal_time_from_words(u.read_u32(Rx.OUT_TIME_HI), u.read_u32(Rx.OUT_TIME_LO)),
                          out_xy_mm=(u.read_i32(Rx.OUT_X_MM), u.read_i32(Rx.OUT_Y_MM)))

    def _score(self) -> Score | None:
        """ET Robocon's score the physics process wrote before it reported the event (None if it could not:
        the test then counts as unscored, like a crash)."""
        try:
            return Score.from_dict(json.loads((self.run_dir / SCORE_FILE).read_text()))
        except (OSError, ValueError, KeyError, TypeError):
            return None

    def _program_output(self) -> str:
        """What the physics process kept of a crashed program's last words (nothing for other crashes)."""
        try:
            return (self.run_dir / PROGRAM_OUTPUT_FILE).read_text(errors="replace").strip()
        except OSError:
            return ""

    def end(self) -> None:
        """end = 1: the physics process exits."""
        self.athrill.write_i32(Tx.END, 1)

    def _wait(self, condition: Callable[[], bool], what: str) -> None:
        deadline = time.monotonic() + self.test_timeout_s

        def check() -> None:
            if not pid_alive(self._physics_pid):
                raise PhysicsGone(f"physics process {self._physics_pid} is gone (waiting for {what})")
            if time.monotonic() > deadline:
                raise PhysicsGone(f"no {what} within {self.test_timeout_s:.0f} s", stalled=True)

        wait_for(condition, check, spin_s=0.0, nap_s=POLL_S)

    def close(self) -> None:
        self.unity.close()
        self.athrill.close()

