"""A bench as a controller sees it: one physics process serving one run directory, with the Athrill it
starts for every test. Started on demand, restarted when it dies or spoils a test, closed with end = 1. A
campaign's workers, its own picture bench, `hako test` and `hako trial` all test on one."""

from __future__ import annotations

import subprocess
import time
from pathlib import Path

from hakoniwa.wire.processes import die_with_parent
from hakoniwa.wire.protocol import BenchCause
from hakoniwa.wire.result import TestResult
from hakoniwa.wire.rundir import diagnose
from testctl.bench_options import BenchOptions
from testctl.executor import TestSpec
from testctl.runner import PhysicsGone, TestRunner


class Bench:
    def __init__(self, options: BenchOptions, run_dir: Path, *, log=None, physics_args: tuple[str, ...] = ()) -> None:
        """`physics_args`: options of the physics process alone, which are not the bench's (`--view`)."""
        self.options = options
        self.run_dir = Path(run_dir)
        self.log = log  # where the physics process's own messages go (default: inherited)
        self.physics_args = physics_args
        self.exit_status: int | None = None  # how the last physics process ended, once one has
        self._proc: subprocess.Popen | None = None
        self._runner: TestRunner | None = None

    def start(self) -> TestRunner:
        if self._runner is None:
            self.run_dir.mkdir(parents=True, exist_ok=True)
            # A session of its own: a Ctrl-C meant for the campaign must not reach a physics process that the
            # campaign's own bench is starting for a picture (it would die in its imports with a traceback);
            # the bench's owner stops it, and it dies with its parent.
            self.exit_status = None
            self._proc = subprocess.Popen(self.options.physics_command(self.run_dir, [], self.physics_args),
                                          stdout=self.log,
                                          stderr=self.log, stdin=subprocess.DEVNULL, start_new_session=True,
                                          preexec_fn=die_with_parent)
            try:
                self._runner = TestRunner.attach(self.run_dir, self._proc)
            except Exception:
                self.close()
                raise
        return self._runner

    def run(self, spec: TestSpec) -> TestResult:
        """One test. A bench that spoiled the test is restarted before the next, so that a broken bench is
        rebuilt; one whose physics process died mid-test spoiled it too (`BenchCause.PHYSICS_KILLED`, or
        `FILE_DAMAGED` where a mapped file was truncated under it, which kills it with SIGBUS), as did one
        that reported nothing within the runner's timeout (`TIME_STALLED`; it is stopped): a result
        like any bench fault's, which the campaign counts and runs again, never one of the parameters."""
        runner = self.start()
        started = time.monotonic()
        try:
            result = runner.run_test(spec.params, noise_seed=spec.noise_seed, noise_scale=spec.noise_scale,
                                     slot_types=spec.slot_types)
        except PhysicsGone as gone:
            damage = diagnose(self.run_dir)
            assert self._proc is not None
            proc = self._proc
            hung = gone.stalled  # alive, but no event within the runner's timeout: time stood still
            self.close()
            cause = (BenchCause.FILE_DAMAGED if damage else BenchCause.TIME_STALLED if hung
                     else BenchCause.PHYSICS_KILLED)
            return TestResult.spoiled(cause, 0 if hung else proc.returncode or 0, time.monotonic() - started)
        if result.bench_fault:
            self.close()
        return result

    def close(self) -> None:
        if self._runner is not None:
            self._runner.end()
            self._runner.close()
            self._runner = None
        if self._proc is not None:
            try:
                self._proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                self._proc.kill()
                self._proc.wait()
            self.exit_status = self._proc.returncode
            self._proc = None

    def stop(self) -> None:
        """End the physics process now, mid-test or still starting (its Athrill dies with it), as a user's
        Ctrl-C does: it dies of SIGTERM quietly, with no test to finish."""
        if self._proc is not None and self._proc.poll() is None:
            self._proc.terminate()
        self.close()

    def __enter__(self) -> Bench:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
