"""`--scheduler` and its TLS files: plaintext only where it is safe without a word, a warning in one line
for a plaintext link to another host, and a TLS setting that cannot work refused in one line before any
test runs."""

from __future__ import annotations

from pathlib import Path

import click
import pytest

from testctl.cluster import ClusterError, tls_security
from testctl.cluster_address import ClusterAddress, TlsFiles, cluster_address, host_of
from tests.helpers.cluster_certs import dask_certs
from tests.helpers.commands import hako, one_line_error


def address(scheduler: str | None, *files: Path | None) -> tuple[ClusterAddress | None, list[str]]:
    warnings: list[str] = []
    ca, cert, key = (*files, None, None, None)[:3]
    return cluster_address(scheduler, ca, cert, key, warn=warnings.append), warnings


@pytest.mark.parametrize("scheduler", ["tcp://127.0.0.1:8786", "tcp://localhost:8786", "127.0.0.1:8786",
                                       "tcp://[::1]:8786"])
def test_plaintext_on_this_machine_is_said_nothing_of(scheduler: str):
    assert address(scheduler) == (ClusterAddress(scheduler, None), [])


@pytest.mark.parametrize("scheduler", ["tcp://10.0.0.5:8786", "node7:8786", "tcp://cluster.example.org:8786"])
def test_plaintext_to_another_host_is_one_line_of_warning(scheduler: str):
    found, warnings = address(scheduler)
    assert found == ClusterAddress(scheduler, None)
    assert len(warnings) == 1 and "\n" not in warnings[0]
    assert warnings[0].startswith("warning: ") and scheduler in warnings[0] and "tls://" in warnings[0]


def test_tls_takes_the_files_given_and_warns_of_nothing(tmp_path: Path):
    ca = tmp_path / "ca.pem"
    assert address("tls://10.0.0.5:8786", ca) == (ClusterAddress("tls://10.0.0.5:8786", TlsFiles(ca)), [])


def test_tls_files_with_plaintext_or_no_scheduler_are_refused(tmp_path: Path):
    with pytest.raises(click.UsageError, match="need a tls:// scheduler address.*give --scheduler tls://10.0.0.5:"):
        address("tcp://10.0.0.5:8786", tmp_path / "ca.pem")
    with pytest.raises(click.UsageError, match="the local cluster needs none"):
        address(None, None, tmp_path / "client.pem")
    assert address(None) == (None, [])


def test_hosts_are_read_as_dask_reads_addresses():
    assert [host_of(a) for a in ("tls://[::1]:1", "node7:8786", "tcp://a.b:1")] == ["::1", "node7", "a.b"]


def test_a_tls_scheduler_without_certificates_is_one_line(tmp_path: Path, monkeypatch):
    monkeypatch.setenv("DASK_CONFIG", str(tmp_path))  # no user's Dask config with TLS files in it
    one_line_error(hako("run", "--smoke", "--scheduler", "tls://127.0.0.1:1", "--out", str(tmp_path / "c"),
                        timeout=120), "is TLS: give --tls-ca and --tls-cert", "docs/CLUSTER.md")


def test_certificates_are_read_before_any_connection(tmp_path: Path):
    certs = dask_certs(tmp_path / "certs")
    at = "tls://127.0.0.1:1"
    assert tls_security(at, TlsFiles(certs / "ca.pem", certs / "client.pem", certs / "client.key")) is not None
    with pytest.raises(ClusterError, match="KEY_VALUES_MISMATCH"):
        tls_security(at, TlsFiles(certs / "ca.pem", certs / "client.pem", certs / "worker.key"))
    (tmp_path / "notes.txt").write_text("not a certificate\n")
    with pytest.raises(ClusterError, match="not a PEM certificate or key"):
        tls_security(at, TlsFiles(certs / "ca.pem", tmp_path / "notes.txt", certs / "client.key"))
    with pytest.raises(ClusterError) as info:
        tls_security(at, TlsFiles(tmp_path / "notes.txt", certs / "client.pem", certs / "client.key"))
    assert "\n" not in str(info.value) and str(tmp_path / "notes.txt") in str(info.value)
