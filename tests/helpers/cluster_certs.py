"""Certificates for a Dask cluster with TLS, made by scripts/make_dask_certs.sh as docs/CLUSTER.md tells a
user to make them, or a pytest skip saying what is missing."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from tests.helpers.paths import SCRIPTS


def dask_certs(out: Path) -> Path:
    """A folder with ca.pem and the scheduler's, workers' and client's certificates and keys."""
    if shutil.which("openssl") is None:
        pytest.skip("needs openssl to make the TLS certificates: apt-get install openssl")
    done = subprocess.run([str(SCRIPTS / "make_dask_certs.sh"), str(out)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return out
