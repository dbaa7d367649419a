"""Benches on Dask workers: a campaign's tests run in parallel, on this machine or across a cluster.

Each Dask worker hosts one bench (a physics process and its run directory, in the worker's own scratch
space), started at its first test and kept alive between tests; a worker runs one test at a time. The
controller stays the only writer of the journal: workers only return results.

Faults: a bench that dies mid-test raises, and Dask runs the test again (`retries`), on a fresh bench; a
worker that dies mid-test has its test rescheduled on another worker by the scheduler. Either way the
controller receives each test's result exactly once, so nothing is lost or counted twice; and since a
test's result depends only on its parameters and noise seed, it does not matter where it ran.
"""

from __future__ import annotations

import logging
import os
import shutil
import signal
import tempfile
import threading
from pathlib import Path

from distributed import Client, LocalCluster, as_completed, get_worker
from distributed.diagnostics.plugin import WorkerPlugin

from hakoniwa.physics.options import BenchOptions
from testctl.bench import Bench
from testctl.executor import Executor, TestSpec
from testctl.result import TestResult

PLUGIN_NAME = "hakoniwa-bench"
RETRIES = 2  # a test whose bench died is run again this many times before the campaign gives up
CONNECT_TIMEOUT_S = 10


class ClusterError(RuntimeError):
    """The cluster cannot be reached or has no workers; the message is one line."""


class BenchHost(WorkerPlugin):
    """Keeps one bench per worker, built at the worker's first test and closed with the worker."""

    name = PLUGIN_NAME

    def __init__(self, options: BenchOptions) -> None:
        self.options = options
        self.bench: Bench | None = None
        self._dir: str | None = None

    def setup(self, worker) -> None:
        self.lock = threading.Lock()  # a worker started with several threads still runs one test at a time
        self._dir = tempfile.mkdtemp(prefix="hako-bench-", dir=worker.local_directory)
        self.worker_name = str(worker.name)
        self._log = open(Path(self._dir) / "bench.log", "ab")
        self.bench = Bench(self.options, Path(self._dir) / "run", log=self._log)

    def teardown(self, worker) -> None:
        if self.bench is not None:
            self.bench.close()
        self._log.close()
        shutil.rmtree(self._dir or "", ignore_errors=True)


def run_on_worker(spec: TestSpec) -> tuple[TestResult, str]:
    """The task each test is: run it on this worker's bench."""
    host: BenchHost = get_worker().plugins[PLUGIN_NAME]
    assert host.bench is not None
    with host.lock:
        return host.bench.run(spec), f"{host.worker_name}@{os.uname().nodename}"


class DaskExecutor(Executor):
    """Runs tests on the benches of a LocalCluster of `benches` workers, or of the cluster whose scheduler
    is at `scheduler`."""

    def __init__(self, options: BenchOptions, *, benches: int | None = None, scheduler: str | None = None) -> None:
        self._cluster: LocalCluster | None = None
        if scheduler is not None:
            try:
                self.client = Client(scheduler, timeout=CONNECT_TIMEOUT_S)
            except (OSError, TimeoutError) as e:
                raise ClusterError(f"cannot reach the Dask scheduler at {scheduler}: {e}") from None
        else:
            # The workers must not see the user's Ctrl-C (it is the campaign's to handle): a signal ignored
            # when a process starts stays ignored in the processes it starts.
            previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
            try:
                self._cluster = LocalCluster(n_workers=benches, threads_per_worker=1, processes=True,
                                             dashboard_address=None, silence_logs=logging.ERROR)
            finally:
                signal.signal(signal.SIGINT, previous)
            self.client = Client(self._cluster)
        try:
            self.client.wait_for_workers(1, timeout=CONNECT_TIMEOUT_S)
        except TimeoutError:
            self.close()
            raise ClusterError(f"the Dask scheduler at {scheduler} has no workers") from None
        self.client.register_plugin(BenchHost(options), name=PLUGIN_NAME)
        self.capacity = len(self.client.scheduler_info()["workers"])
        self._done = as_completed()
        self._specs: dict[str, TestSpec] = {}

    def submit(self, spec: TestSpec) -> None:
        future = self.client.submit(run_on_worker, spec, retries=RETRIES, pure=False)
        self._specs[future.key] = spec
        self._done.add(future)

    def next_result(self) -> tuple[TestSpec, TestResult, str]:
        future = next(self._done)
        spec = self._specs.pop(future.key)
        result, bench = future.result()
        return spec, result, bench

    @property
    def running(self) -> int:
        return min(len(self._specs), self.capacity)

    def close(self) -> None:
        self.client.close()
        if self._cluster is not None:
            self._cluster.close()
