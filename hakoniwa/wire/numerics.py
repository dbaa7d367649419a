"""One set of floating-point kernels on every x86-64 machine, so that a campaign's search is the same
everywhere. Stdlib only: it must run before numpy is first imported.

NumPy and OpenBLAS pick their SIMD kernels at start-up from the CPU. The AVX-512 ones (NumPy's X86_V4
targets, with SVML's exp and log; OpenBLAS's SkylakeX and later) round differently in the last bits from
the AVX2 ones. A Gaussian process fitted to the same laps then proposes a set a few ULPs away, the campaign
tests other sets from there on, and the same `hako run --seed 0` printed best 16.24 s on one CI machine and
16.38 s on another. AVX2 (x86-64-v3) is the common ground of the machines the bench runs on, so the AVX-512
kernels are switched off. An older CPU without AVX2 keeps its own kernels (nothing safe to pin it to);
other architectures are left alone. A variable the user set is kept."""

from __future__ import annotations

import os
import platform
from collections.abc import MutableMapping
from pathlib import Path

# NumPy's dispatch targets above x86-64-v3, by the names numpy 2.4 gives them (pyproject asks for >= 2.4: a
# name it does not dispatch is refused with an ImportWarning)
NUMPY_FEATURES_OFF = "X86_V4 AVX512_ICL AVX512_SPR"
OPENBLAS_CORE = "Haswell"  # OpenBLAS's AVX2 + FMA kernels


def pin_kernels(env: MutableMapping[str, str] = os.environ, cpu_flags: frozenset[str] | None = None) -> None:
    """Set the variables NumPy and OpenBLAS read at load, in `env` (and so in every child process)."""
    if platform.machine().lower() not in ("x86_64", "amd64"):
        return
    flags = _cpu_flags() if cpu_flags is None else cpu_flags
    if not {"avx2", "fma"} <= flags:
        return
    env.setdefault("NPY_DISABLE_CPU_FEATURES", NUMPY_FEATURES_OFF)
    env.setdefault("OPENBLAS_CORETYPE", OPENBLAS_CORE)


def _cpu_flags() -> frozenset[str]:
    """The CPU's feature flags as Linux lists them; none known elsewhere."""
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        return frozenset()
    for line in text.splitlines():
        key, _, value = line.partition(":")
        if key.strip() == "flags":
            return frozenset(value.split())
    return frozenset()
