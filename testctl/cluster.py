"""Benches on Dask workers: a campaign's tests run in parallel, on this machine or across a cluster.

Each Dask worker hosts one bench (a physics process and its run directory, in the worker's own scratch
space), started at its first test and kept alive between tests; a worker runs one test at a time. The
controller stays the only writer of the journal: workers only return results.

Faults: a bench that dies mid-test raises, and Dask runs the test again (`retries`), on a fresh bench; a
worker that dies mid-test has its test rescheduled on another worker by the scheduler. Either way the
controller receives each test's result exactly once, so nothing is lost or counted twice; and since a
test's result depends only on its parameters and noise seed, it does not matter where it ran. A cluster
that has lost every worker for NO_WORKERS_TIMEOUT_S, or its scheduler, cannot go on: that is a one-line
`ClusterError` (the campaign then prints the resume command), never a hang or a traceback.
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import queue
import shlex
import shutil
import ssl
import sys
import tempfile
import threading
import time
from concurrent.futures import CancelledError
from pathlib import Path
from typing import cast

import dask.config
from dask.typing import Key
from distributed import Client, Future, LocalCluster, get_worker
from distributed.diagnostics.plugin import WorkerPlugin
from distributed.security import Security

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.result import TestResult
from testctl.bench import Bench
from testctl.bench_options import BenchOptions
from testctl.cluster_address import CLUSTER_DOC, ClusterAddress, TlsFiles
from testctl.executor import Executor, TestSpec

PLUGIN_NAME = "hakoniwa-bench"
RETRIES = 2  # a campaign's test whose bench died is run again this many times before it gives up
CONNECT_TIMEOUT_S = 10
ANSWER_TIMEOUT_S = 10  # after the connection: a scheduler answers Dask's handshake at once
NO_WORKERS_TIMEOUT_S = 60.0  # a cluster without a worker this long is not coming back by itself
LOOK_EVERY_S = 1.0  # how often a wait for results asks the scheduler about the workers


# What multiprocessing's resource tracker says when this process dies without closing the workers' queues
# (SIGKILL): it unlinks their semaphores then, which is all there is to do, so it need not warn.
TRACKER_QUIET = "ignore:resource_tracker:UserWarning:multiprocessing.resource_tracker"


def deaf_interpreter() -> tempfile.TemporaryDirectory:
    """Have multiprocessing start the local workers (a replacement too) with Ctrl-C ignored, and the
    resource tracker quiet, through a folder holding the interpreter it starts them with.

    The user's Ctrl-C goes to the whole process group, and it is the controller's to handle (testctl.interrupts):
    a worker that heard it would die mid-test with a traceback. Python leaves a signal ignored at its start
    ignored, and so do the benches a worker starts; but the controller must not ignore it itself, not even
    while the cluster starts (that lost a Ctrl-C), and blocking it instead does not reach the workers
    (multiprocessing unblocks it)."""
    if TRACKER_QUIET not in sys.warnoptions:
        sys.warnoptions.append(TRACKER_QUIET)  # what the processes it starts are given as -W
    folder = tempfile.TemporaryDirectory(prefix="hako-python-")
    python = Path(folder.name) / "python"
    python.write_text(f"#!/bin/sh\ntrap '' INT\nexec {shlex.quote(sys.executable)} \"$@\"\n")
    python.chmod(0o755)
    multiprocessing.set_executable(str(python))
    return folder


class ClusterError(HakoError, RuntimeError):
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


def tls_security(address: str, files: TlsFiles) -> Security:
    """Dask's TLS for the link to the scheduler at `address`: the files given, the rest from Dask's
    `distributed.comm.tls` config. Loaded here, so that a missing CA or a certificate that is no
    certificate, or one that does not match its key, is a one-line ClusterError before any connection."""
    ca, cert, key = (str(given) if given is not None else dask.config.get(f"distributed.comm.tls.{name}", None)
                     for given, name in ((files.ca, "ca-file"), (files.cert, "client.cert"), (files.key, "client.key")))
    if ca is None or cert is None:
        raise ClusterError(f"{address} is TLS: give --tls-ca and --tls-cert (and --tls-key unless the certificate "
                           f"file holds the key), or set Dask's distributed.comm.tls.ca-file and client.cert "
                           f"({CLUSTER_DOC})")
    security = Security(require_encryption=True, tls_ca_file=ca, tls_client_cert=cert, tls_client_key=key)
    try:
        security.get_connection_args("client")  # builds the SSL context: reads every file now
    except (OSError, ssl.SSLError, ValueError) as e:
        reason = getattr(e, "reason", None) or getattr(e, "strerror", None) or str(e)
        if "PEM lib" in str(e):  # OpenSSL's words for a file it could not read as PEM
            reason = "one of them is not a PEM certificate or key"
        raise ClusterError(f"TLS for the Dask scheduler at {address}: cannot use the CA {ca}, certificate {cert} "
                           f"and key {key or '(in the certificate file)'}: {reason}") from None
    return security


class NoAnswer(ClusterError):
    """The scheduler's address took the connection and never answered Dask's handshake."""


def _handshake(address: str, security: Security | None) -> None:
    """Dask's handshake with the scheduler, within a bound on the wall clock. Dask bounds the TCP connection,
    not the handshake after it (distributed's `comm.core.connect` reads the answer without a timeout), so a
    listener that accepts and says nothing (a stopped process, a web server waiting for a request) held
    `Client()` for ever."""
    import asyncio

    from distributed.comm import connect

    args = security.get_connection_args("client") if security is not None else {}

    async def handshake() -> None:
        comm = await connect(address, timeout=CONNECT_TIMEOUT_S, **args)
        await comm.close()

    async def bounded() -> None:
        try:
            await asyncio.wait_for(handshake(), CONNECT_TIMEOUT_S + ANSWER_TIMEOUT_S)
        except TimeoutError:
            raise NoAnswer(f"{address} took the connection but did not answer as a Dask scheduler within "
                           f"{CONNECT_TIMEOUT_S + ANSWER_TIMEOUT_S} s") from None

    asyncio.run(bounded())


def run_on_worker(spec: TestSpec) -> tuple[TestResult, str]:
    """The task each test is: run it on this worker's bench."""
    host = cast(BenchHost, get_worker().plugins[PLUGIN_NAME])  # the plugin this module registers
    assert host.bench is not None
    with host.lock:
        return host.bench.run(spec), f"{host.worker_name}@{os.uname().nodename}"


class DaskExecutor(Executor):
    """Runs tests on the benches of a LocalCluster of `benches` workers, or of the cluster whose scheduler
    is at `scheduler`. A test whose bench died runs again up to `retries` times: a campaign recovers, while
    `hako test` (retries 0) reports a broken run, as CI wants of a bench that broke."""

    def __init__(self, options: BenchOptions, *, benches: int | None = None, scheduler: ClusterAddress | None = None,
                 retries: int = RETRIES) -> None:
        self._retries = retries
        self._cluster: LocalCluster | None = None
        if scheduler is not None:
            security = tls_security(scheduler.address, scheduler.tls) if scheduler.tls is not None else None
            try:
                _handshake(scheduler.address, security)
                self.client = Client(scheduler.address, timeout=CONNECT_TIMEOUT_S, security=security)
            except NoAnswer:
                raise
            except (OSError, TimeoutError) as e:
                reason = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
                raise ClusterError(f"cannot reach the Dask scheduler at {scheduler.address}: {reason}") from None
            except Exception as e:  # another server on that port: Dask reads its bytes as a frame's length
                raise ClusterError(f"{scheduler.address} does not answer as a Dask scheduler "
                                   f"({type(e).__name__} in Dask's handshake)") from None
        else:
            self._interpreter = deaf_interpreter()
            # No dashboard; and the scheduler's HTTP server (which it starts even so) on a free port, not on
            # 8787, where another campaign's or a notebook's would make every campaign warn.
            self._cluster = LocalCluster(n_workers=benches, threads_per_worker=1, processes=True,
                                         dashboard_address=None, silence_logs=logging.CRITICAL,
                                         scheduler_kwargs={"dashboard": False, "dashboard_address": ":0"})
            self.client = Client(self._cluster)
        # The campaign says in one line what became of a cluster it loses or leaves on a signal; Dask's own
        # tracebacks of the closed connections would bury that line. LocalCluster's silence_logs is not enough:
        # it lowers its handlers only while the cluster is open, and a send still in flight when a signal closes
        # it logs after.
        for name in [n for n in logging.root.manager.loggerDict if n.split(".")[0] == "distributed"]:
            logging.getLogger(name).setLevel(logging.CRITICAL)
        try:
            self.client.wait_for_workers(1, timeout=CONNECT_TIMEOUT_S)
        except TimeoutError:
            self.close()
            raise ClusterError(f"the Dask scheduler at {scheduler and scheduler.address} has no workers") from None
        self.client.register_plugin(BenchHost(options), name=PLUGIN_NAME)
        self.where = scheduler.address if scheduler is not None else "the local cluster"
        self.capacity = len(self.client.scheduler_info()["workers"])
        # Finished futures, as Dask's own thread reports them: a wait wakes the moment a test ends. With one
        # set proposed at a time, every moment between a set's last test and the next proposal leaves all
        # the benches idle (polling every 50 ms cost a full campaign 2-3 s).
        self._done: queue.SimpleQueue[Future] = queue.SimpleQueue()
        self._specs: dict[Key, TestSpec] = {}  # by the future's key

    def submit(self, spec: TestSpec) -> None:
        future = self.client.submit(run_on_worker, spec, retries=self._retries, pure=False)
        self._specs[future.key] = spec
        future.add_done_callback(self._done.put)

    def next_result(self) -> tuple[TestSpec, TestResult, str]:
        without_workers_since: float | None = None
        while True:
            try:
                future = self._done.get(timeout=LOOK_EVERY_S)
                break
            except queue.Empty:
                pass
            if not self._workers():
                now = time.monotonic()
                without_workers_since = without_workers_since or now
                if now - without_workers_since > NO_WORKERS_TIMEOUT_S:
                    raise ClusterError(f"every Dask worker of {self.where} is gone (none for "
                                       f"{NO_WORKERS_TIMEOUT_S:.0f} s); start workers again")
            else:
                without_workers_since = None
        spec = self._specs.pop(future.key)
        try:
            result, bench = future.result()
        except CancelledError as e:  # distributed's FutureCancelledError: the scheduler connection is gone
            raise ClusterError(f"lost the Dask scheduler at {self.where}: {getattr(e, 'reason', e)}") from None
        return spec, result, bench

    def _workers(self) -> int:
        if self.client.status != "running":
            raise ClusterError(f"lost the Dask scheduler at {self.where} ({self.client.status})")
        try:
            return len(self.client.scheduler_info()["workers"])
        except (OSError, TimeoutError) as e:  # distributed's CommClosedError is an OSError
            raise ClusterError(f"lost the Dask scheduler at {self.where}: {e}") from None

    @property
    def running(self) -> int:
        return min(len(self._specs), self.capacity)

    def close(self) -> None:
        self.client.close()
        if self._cluster is not None:
            self._cluster.close()
            self._interpreter.cleanup()
            multiprocessing.set_executable(sys.executable)
