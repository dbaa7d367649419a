"""Campaigns on several benches through Dask: a real scheduler and real `dask worker` processes on localhost,
the same results wherever and in whatever order the tests ran, and a worker killed mid-campaign."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from testctl.campaign.journal import JOURNAL_FILE, read_journal
from tests.helpers.cluster_certs import dask_certs
from tests.helpers.commands import hako, one_line_error
from tests.helpers.processes import tagged_env, tagged_processes
from tests.helpers.waiting import wait_until

DASK = [sys.executable, "-m", "dask"]
CAMPAIGN = ["--batch", "2", "--trials", "3", "--seed", "1"]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def hako_run(*args: str, timeout: float = 600) -> subprocess.CompletedProcess:
    return hako("run", *args, timeout=timeout)


def wait_for_workers(address: str, n: int, certs: Path | None = None) -> None:
    from distributed import Client
    from distributed.security import Security

    security = None if certs is None else Security(tls_ca_file=str(certs / "ca.pem"),
                                                   tls_client_cert=str(certs / "client.pem"),
                                                   tls_client_key=str(certs / "client.key"), require_encryption=True)
    # Generous: on a loaded 2-core CI runner a `dask worker` took over a minute to import and connect.
    with Client(address, timeout=120, security=security) as client:
        client.wait_for_workers(n, timeout=240)


def tls_options(certs: Path, role: str) -> list[str]:
    """The options of `dask scheduler` and `dask worker` for TLS with the certificates of
    scripts/make_dask_certs.sh, as docs/CLUSTER.md gives them."""
    return ["--tls-ca-file", str(certs / "ca.pem"), "--tls-cert", str(certs / f"{role}.pem"),
            "--tls-key", str(certs / f"{role}.key")]


class LocalDask:
    """A scheduler and workers as separate processes, as on a cluster (here all on localhost); with `certs`
    (a folder of scripts/make_dask_certs.sh), over TLS."""

    def __init__(self, tmp: Path, workers: int, certs: Path | None = None) -> None:
        scheme = "tcp" if certs is None else "tls"
        self.address = f"{scheme}://127.0.0.1:{free_port()}"
        port = self.address.rsplit(":", 1)[1]
        self.log = open(tmp / "dask.log", "w")
        tls = [] if certs is None else ["--protocol", "tls", *tls_options(certs, "scheduler")]
        self.scheduler = subprocess.Popen([*DASK, "scheduler", "--host", "127.0.0.1", "--port", port,
                                           "--no-dashboard", *tls], stdout=self.log, stderr=self.log)
        tls = [] if certs is None else tls_options(certs, "worker")
        self.workers = [subprocess.Popen([*DASK, "worker", self.address, "--nthreads", "1", "--no-dashboard",
                                          "--local-directory", str(tmp / f"w{i}"), *tls], stdout=self.log,
                                         stderr=self.log, start_new_session=True) for i in range(workers)]
        wait_for_workers(self.address, workers, certs)

    def close(self) -> None:
        for p in [*self.workers, self.scheduler]:
            if p.poll() is None:
                p.terminate()
        for p in [*self.workers, self.scheduler]:
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                p.kill()
        self.log.close()


def essence(out: Path) -> list[tuple]:
    _, records = read_journal(out / JOURNAL_FILE)
    return sorted((r.set_index, r.rep, r.noise_seed, sorted(r.params.items()), r.result.event,
                   r.result.goal_time_us) for r in records if not r.result.bench_fault)


@pytest.fixture(scope="module")
def local_reference(tmp_path_factory) -> Path:
    """`hako run --benches 2` on a LocalCluster."""
    out = tmp_path_factory.mktemp("local") / "campaign"
    done = hako_run("--benches", "2", *CAMPAIGN, "--out", str(out))
    assert done.returncode == 0, done.stderr
    return out


@pytest.mark.slow
def test_a_cluster_of_separate_workers_gives_the_same_results(tmp_path, local_reference):
    cluster = LocalDask(tmp_path, 2)
    try:
        out = tmp_path / "campaign"
        done = hako_run("--scheduler", cluster.address, *CAMPAIGN, "--out", str(out))
    finally:
        cluster.close()
    assert done.returncode == 0, done.stderr
    assert (out / "results.csv").read_text() == (local_reference / "results.csv").read_text()
    assert essence(out) == essence(local_reference)
    header, records = read_journal(out / JOURNAL_FILE)
    assert len({r.bench for r in records}) == 2  # both workers ran tests
    assert header["options"]["batch"] == 2  # the batch it ran with, not one from the local CPU count


@pytest.mark.slow
def test_a_worker_killed_mid_campaign_loses_nothing(tmp_path, local_reference):
    cluster = LocalDask(tmp_path, 2)
    out = tmp_path / "campaign"
    try:
        proc = subprocess.Popen([sys.executable, "-m", "testctl.hako", "run", "--scheduler", cluster.address,
                                 *CAMPAIGN, "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True)
        wait_until(lambda: journaled(out, 4), 120, 0.2, alive=lambda: proc.poll() is None, what="4 tests")
        os.killpg(cluster.workers[0].pid, signal.SIGKILL)  # the worker and the bench it hosts
        _, err = proc.communicate(timeout=600)
    finally:
        cluster.close()
    assert proc.returncode == 0, err
    assert essence(out) == essence(local_reference)  # complete, nothing counted twice
    assert (out / "results.csv").read_text() == (local_reference / "results.csv").read_text()


@pytest.mark.slow
def test_a_campaign_runs_through_a_tls_cluster_and_a_client_of_another_ca_is_refused(tmp_path, local_reference):
    certs = dask_certs(tmp_path / "certs")
    other = dask_certs(tmp_path / "other")
    cluster = LocalDask(tmp_path, 2, certs)
    try:
        out = tmp_path / "campaign"
        client = ["--tls-ca", str(certs / "ca.pem"), "--tls-cert", str(certs / "client.pem"), "--tls-key",
                  str(certs / "client.key")]
        done = hako_run("--scheduler", cluster.address, *client, *CAMPAIGN, "--out", str(out))
        stranger = hako_run("--scheduler", cluster.address, "--tls-ca", str(other / "ca.pem"), "--tls-cert",
                            str(other / "client.pem"), "--tls-key", str(other / "client.key"), *CAMPAIGN, "--out",
                            str(tmp_path / "stranger"), timeout=120)
    finally:
        cluster.close()
    assert done.returncode == 0, done.stderr
    assert "warning" not in done.stderr
    assert essence(out) == essence(local_reference)  # TLS changes the link, not a result
    one_line_error(stranger, f"cannot reach the Dask scheduler at {cluster.address}", "TLS")


def test_an_unreachable_scheduler_is_a_one_line_error(tmp_path):
    address = f"tcp://127.0.0.1:{free_port()}"
    done = hako_run("--scheduler", address, "--smoke", "--out", str(tmp_path / "c"), timeout=120)
    assert done.returncode != 0
    assert address in done.stderr and "Traceback" not in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1


BANNER_SERVER = """
import socket, sys
with socket.create_server(("127.0.0.1", int(sys.argv[1]))) as server:
    while True:
        peer, _ = server.accept()
        peer.sendall(b"SSH-2.0-OpenSSH_9.2p1 Debian-2\\r\\n")
"""


def hako_run_against(server_script: str, tmp_path: Path) -> tuple[str, subprocess.CompletedProcess]:
    """`hako run --scheduler` at a server of this machine (127.0.0.1 only) that runs `server_script`."""
    port = free_port()
    server = subprocess.Popen([sys.executable, "-c", server_script, str(port)])
    try:
        def listening() -> bool:
            with socket.socket() as s:
                return s.connect_ex(("127.0.0.1", port)) == 0

        wait_until(listening, timeout=30, what="the server")
        address = f"tcp://127.0.0.1:{port}"
        return address, hako_run("--scheduler", address, "--smoke", "--out", str(tmp_path / "c"), timeout=120)
    finally:
        server.kill()
        server.wait()


def test_a_port_where_another_server_speaks_first_is_a_one_line_error(tmp_path):
    """The scheduler's address with an SSH port: its banner, read as Dask's handshake, asked numpy for
    exabytes, and the MemoryError came out as a traceback."""
    address, done = hako_run_against(BANNER_SERVER, tmp_path)
    assert done.returncode != 0
    assert done.stderr.strip().splitlines() == [f"Error: {address} does not answer as a Dask scheduler "
                                                "(MemoryError in Dask's handshake)"], done.stderr


SILENT_SERVER = """
import socket, sys
with socket.create_server(("127.0.0.1", int(sys.argv[1]))) as server:
    peers = []
    while True:
        peers.append(server.accept()[0])
"""


def test_a_listener_that_never_answers_is_a_one_line_error_within_the_bound(tmp_path):
    """A port that accepts and says nothing (an HTTP server waiting for a request, a stopped scheduler) held
    the campaign for ever: Dask bounds the connection, not its handshake."""
    from testctl.cluster import ANSWER_TIMEOUT_S, CONNECT_TIMEOUT_S

    start = time.monotonic()
    address, done = hako_run_against(SILENT_SERVER, tmp_path)
    assert time.monotonic() - start < CONNECT_TIMEOUT_S + ANSWER_TIMEOUT_S + 30
    assert done.returncode != 0
    assert done.stderr.strip().splitlines() == [
        f"Error: {address} took the connection but did not answer as a Dask scheduler within "
        f"{CONNECT_TIMEOUT_S + ANSWER_TIMEOUT_S} s"], done.stderr


def descendants(pid: int) -> list[int]:
    """Every process below `pid` (from /proc)."""
    children: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                ppid = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            children.setdefault(ppid, []).append(int(entry.name))
    out, todo = [], [pid]
    while todo:
        for c in children.get(todo.pop(), []):
            out.append(c)
            todo.append(c)
    return out


def is_physics(pid: int) -> bool:
    try:
        return b"testctl.physics_process" in Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:
        return False


@pytest.mark.slow
def test_a_bench_killed_mid_campaign_is_rebuilt_and_its_test_rerun(tmp_path, local_reference):
    out = tmp_path / "campaign"
    tag = f"cluster-kill-{os.getpid()}-{time.monotonic_ns()}"
    proc = subprocess.Popen([sys.executable, "-m", "testctl.hako", "run", "--benches", "2", *CAMPAIGN, "--out",
                             str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=tagged_env(tag))
    wait_until(lambda: journaled(out, 3), 120, 0.2, alive=lambda: proc.poll() is None, what="3 tests")
    victims = [p for p in descendants(proc.pid) if is_physics(p)]
    assert victims
    os.kill(victims[0], signal.SIGKILL)
    _, err = proc.communicate(timeout=600)
    assert proc.returncode == 0, err
    assert essence(out) == essence(local_reference)
    # Every bench the campaign started, the rebuilt one too, ended with it (found by the environment tag:
    # once `hako run` is reaped its orphans would no longer be its descendants).
    wait_until(lambda: tagged_processes(tag, b"testctl.physics_process") == [], 30, 0.2, what="every bench to end")


def journaled(out: Path, tests: int) -> bool:
    """Whether the campaign in `out` has journaled `tests` tests."""
    return (out / JOURNAL_FILE).is_file() and len(read_journal(out / JOURNAL_FILE)[1]) >= tests


def campaign_on(cluster: LocalDask, out: Path) -> subprocess.Popen:
    proc = subprocess.Popen([sys.executable, "-m", "testctl.hako", "run", "--scheduler", cluster.address,
                             *CAMPAIGN, "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_until(lambda: journaled(out, 1), 120, 0.2, alive=lambda: proc.poll() is None, what="a first test")
    return proc


def stopped_with_the_resume_command(proc: subprocess.Popen, out: Path, *words: str) -> None:
    _, err = proc.communicate(timeout=300)
    progress = f"campaign {out}"  # the progress lines, plain off a terminal
    err = "\n".join(line for line in err.splitlines() if not line.startswith(progress))
    one_line_error(subprocess.CompletedProcess(proc.args, proc.returncode, "", err), f"hako run --resume {out}",
                   *words)
    read_journal(out / JOURNAL_FILE)  # intact


def kill_scheduler(cluster: LocalDask) -> None:
    cluster.scheduler.kill()


def kill_every_worker(cluster: LocalDask) -> None:
    os.killpg(cluster.workers[0].pid, signal.SIGKILL)  # the worker, its nanny and its bench


@pytest.mark.slow
@pytest.mark.parametrize("kill, words", [
    (kill_scheduler, ("lost the Dask scheduler",)),
    (kill_every_worker, ("every Dask worker", "none for 60 s")),  # after NO_WORKERS_TIMEOUT_S
])
def test_a_cluster_lost_mid_campaign_ends_it_with_one_line_and_the_resume_command(tmp_path, kill, words):
    cluster = LocalDask(tmp_path, 1)
    out = tmp_path / "campaign"
    try:
        proc = campaign_on(cluster, out)
        kill(cluster)
        stopped_with_the_resume_command(proc, out, *words)
    finally:
        cluster.close()


def test_a_local_cluster_starts_no_dashboard(tmp_path):
    """Another dashboard on 8787 (a second campaign, a notebook) must not make every campaign warn."""
    with socket.socket() as busy:
        busy.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            busy.bind(("", 8787))
        except OSError:
            pass  # someone holds it already: the same situation
        busy.listen()
        done = hako_run("--smoke", "--out", str(tmp_path / "c"))
    assert done.returncode == 0, done.stderr
    assert "8787" not in done.stderr and "dashboard" not in done.stderr.lower()


def test_a_closed_local_cluster_leaves_dasks_loggers_quiet():
    """LocalCluster lowers its log handlers only while it is open: a send still in flight when a signal closes
    it logged Dask's traceback under the campaign's one line (CI, test_validate_interrupts)."""
    probe = ("import logging\n"
             "from testctl.bench_options import BenchOptions\n"
             "from testctl.cluster import DaskExecutor\n"
             "DaskExecutor(BenchOptions(), benches=1).close()\n"
             "print([n for n in ('distributed', 'distributed.batched', 'distributed.core', 'distributed.scheduler')\n"
             "       if logging.getLogger(n).isEnabledFor(logging.ERROR)])\n")
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]", done.stdout
