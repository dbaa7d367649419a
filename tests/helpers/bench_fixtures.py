"""Starting a real physics process for a test, and talking to it as the test controller does."""

from __future__ import annotations

import os
import subprocess
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from testctl.bench_options import BenchOptions
from testctl.paper import BEST_GAINS, line_trace_params
from testctl.runner import TestRunner

PAPER = line_trace_params(*BEST_GAINS)
ZERO = line_trace_params(0.0, 0.0, 0.0)


@contextmanager
def physics(run_dir: Path, *, extra_env: dict[str, str] | None = None, app: str = "line_trace",
            athrill_timeout_s: float = 10.0,
            bench: BenchOptions | None = None) -> Iterator[tuple[subprocess.Popen, TestRunner]]:
    """A physics process serving `run_dir` with no controller of its own: the test is the controller. `bench`,
    where given, stands for `app` and `athrill_timeout_s`."""
    env = dict(os.environ, **(extra_env or {}))
    bench = bench or BenchOptions(app=app, athrill_timeout_s=athrill_timeout_s)
    proc = subprocess.Popen(bench.physics_command(run_dir, []), env=env)
    try:
        runner = TestRunner.attach(run_dir, proc)
        yield proc, runner
        runner.end()
        assert proc.wait(timeout=30) == 0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
