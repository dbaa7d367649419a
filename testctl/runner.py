"""The controller's side of one test: write parameters, raise start, wait for the event, lower start.

This is the only module of the controller that touches the mapped files, and it touches only what the
paper gives the controller: the parameter area and the event/goal-time words of unity_mmap.bin, and the
start/end flags of athrill_mmap.bin, plus the noise seed and scale of each test (`Rx.NOISE_SEED`,
`Rx.NOISE_SCALE`; docs/NOISE.md). The test's result comes whole in the run directory (`RESULT_FILE`), which the
physics process writes before it raises the event.
"""

from __future__ import annotations

import dataclasses
import math
import subprocess
import time
from collections.abc import Callable, Mapping
from pathlib import Path

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.params import SLOT_FORMATS, encode, fits_area
from hakoniwa.wire.protocol import (
    MAX_NOISE_SCALE,
    Event,
    LayoutError,
    LayoutFile,
    Rx,
    Tx,
    poll_athrill,
    poll_unity,
)
from hakoniwa.wire.result import TestResult
from hakoniwa.wire.rundir import RESULT_FILE
from hakoniwa.wire.waiting import pid_alive, wait_for

POLL_S = 0.002  # a test takes about a second; a 2 ms nap costs nothing and leaves the CPU to the bench


class PhysicsGone(HakoError, RuntimeError):
    """The physics process stopped answering; no further test can run in this run directory. `stalled`: it
    still ran but reported nothing in time (said here, since whether a just-killed process has been reaped
    yet is a race)."""

    def __init__(self, message: str, *, stalled: bool = False) -> None:
        super().__init__(message)
        self.stalled = stalled


class TestRunner:
    __test__ = False  # not a pytest class

    @classmethod
    def attach(cls, run_dir: Path, physics: subprocess.Popen, timeout_s: float = 60.0) -> TestRunner:
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
        self.athrill.write_i32(Tx.START, 0)
        self._wait(lambda: u.read_i32(Rx.EVENT) == Event.NONE, "the reset after the test")
        return dataclasses.replace(result, wall_s=time.monotonic() - start)

    def read_result(self) -> TestResult:
        """The test's result as the physics process sent it before it raised the event (`RESULT_FILE`), but for
        its wall time, which `run_test` adds. A result that cannot be read is the bench's fault: PhysicsGone."""
        try:
            return TestResult.decode((self.run_dir / RESULT_FILE).read_text())
        except (OSError, ValueError, KeyError, TypeError) as e:
            raise PhysicsGone(f"{self.run_dir}: the physics process raised {Event(self.unity.read_i32(Rx.EVENT)).name}"
                              f" without its result ({type(e).__name__}: {e})") from None

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

