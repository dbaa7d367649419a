"""Where `--scheduler` points, and whether the link to it is encrypted.

A campaign sends its parameters to the cluster and gets its results back over this link. Dask's `tcp://` is
plaintext: harmless on this machine (127.0.0.1, localhost), readable and forgeable by anyone on the network
between here and another host. `tls://` is Dask's TLS, with the certificates of `--tls-ca`, `--tls-cert`
and `--tls-key` (or Dask's own `distributed.comm.tls` settings); docs/CLUSTER.md shows how to make them. So
a plaintext address of another host is allowed, since it may be a private network the user trusts, but
warned about in one line; TLS files with a plaintext address are refused, since the user asked for
encryption and would not get it.

This module imports no Dask: `hako --help` and a refused command line stay quick.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from urllib.parse import urlsplit

import click

TLS_SCHEME = "tls"
LOCAL_HOSTS = ("127.0.0.1", "localhost", "::1")
CLUSTER_DOC = "docs/CLUSTER.md"


@dataclass(frozen=True)
class TlsFiles:
    """The client's side of Dask's TLS; a file not given comes from Dask's `distributed.comm.tls` config."""

    ca: Path | None = None  # the CA that signed the scheduler's certificate
    cert: Path | None = None  # this client's certificate (signed by a CA the scheduler trusts)
    key: Path | None = None  # its key, unless the certificate file holds it


@dataclass(frozen=True)
class ClusterAddress:
    address: str  # as Dask takes it: tcp://HOST:PORT, tls://HOST:PORT or HOST:PORT (tcp)
    tls: TlsFiles | None  # None: plaintext

    @property
    def host(self) -> str:
        return host_of(self.address)


def host_of(address: str) -> str:
    """The host of a Dask address (`tcp://HOST:PORT`, `HOST:PORT`, `tls://[::1]:8786`)."""
    return urlsplit(address if "://" in address else f"tcp://{address}").hostname or ""


def cluster_address(scheduler: str | None, ca: Path | None, cert: Path | None, key: Path | None,
                    warn=lambda line: click.echo(line, err=True)) -> ClusterAddress | None:
    """The cluster the command line names (None: a local cluster), after its one-line checks; `warn` hears
    the warning of a plaintext address of another host."""
    files = TlsFiles(ca, cert, key)
    if scheduler is None:
        if files != TlsFiles():
            raise click.UsageError("--tls-ca, --tls-cert and --tls-key secure the link to a --scheduler "
                                   "tls://HOST:PORT; the local cluster needs none")
        return None
    tls = scheduler.startswith(f"{TLS_SCHEME}://")
    if not tls and files != TlsFiles():
        raise click.UsageError(f"--tls-ca, --tls-cert and --tls-key need a tls:// scheduler address, and {scheduler} "
                               f"is plaintext: give --scheduler tls://{host_of(scheduler)}:PORT ({CLUSTER_DOC})")
    if not tls and host_of(scheduler) not in LOCAL_HOSTS:
        warn(f"warning: the link to the Dask scheduler at {scheduler} is not encrypted (tcp://), and it is not "
             f"on this machine: use tls:// with --tls-ca, --tls-cert and --tls-key on a network you do not trust "
             f"({CLUSTER_DOC})")
    return ClusterAddress(scheduler, files if tls else None)
