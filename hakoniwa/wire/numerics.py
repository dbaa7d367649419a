"""One set of floating-point kernels on every x86-64 machine, so that a campaign's search is the same
everywhere. Stdlib only: it must run before numpy is first imported.

NumPy and OpenBLAS pick their SIMD kernels at start-up from the CPU. The AVX-512 ones (NumPy's X86_V4
targets, with SVML's exp and log; OpenBLAS's SkylakeX and later) round differently in the last bits from
the AVX2 ones, and a Gaussian process fitted to the same laps then proposes a set a few ULPs away, from
which the campaign tests other sets. That is the likeliest reason the same `hako run --space` printed best
16.24 s on one CI machine and 16.38 s on another (this development machine has no AVX-512 to show it).
AVX2 (x86-64-v3) is the common ground of the machines the bench runs on, so the AVX-512 kernels are switched
off. An older CPU without AVX2 keeps its own kernels (nothing safe to pin it to); other architectures are
left alone. A variable the user set is kept, and a child process, which inherits both, reads nothing."""

from __future__ import annotations

import os
from collections.abc import MutableMapping

# NumPy's dispatch targets above x86-64-v3, by the names numpy 2.4 gives them (pyproject asks for >= 2.4: a
# name it does not dispatch is refused with an ImportWarning)
NUMPY_FEATURES_OFF = "X86_V4 AVX512_ICL AVX512_SPR"
OPENBLAS_CORE = "Haswell"  # OpenBLAS's AVX2 + FMA kernels
NUMPY_VARIABLE, OPENBLAS_VARIABLE = "NPY_DISABLE_CPU_FEATURES", "OPENBLAS_CORETYPE"


def pin_kernels(env: MutableMapping[str, str] = os.environ, cpu_flags: frozenset[str] | None = None) -> None:
    """Set the variables NumPy and OpenBLAS read at load, in `env` (and so in every child process)."""
    if NUMPY_VARIABLE in env and OPENBLAS_VARIABLE in env:
        return  # set by the user, or by the parent process that pinned them
    if os.uname().machine.lower() not in ("x86_64", "amd64"):  # not `platform`: its import costs 2 ms
        return
    flags = _cpu_flags() if cpu_flags is None else cpu_flags
    if not {"avx2", "fma"} <= flags:
        return
    env.setdefault(NUMPY_VARIABLE, NUMPY_FEATURES_OFF)
    env.setdefault(OPENBLAS_VARIABLE, OPENBLAS_CORE)


def _cpu_flags() -> frozenset[str]:
    """The first CPU's feature flags as Linux lists them (read no further: the file has a block per CPU);
    none known elsewhere."""
    try:
        with open("/proc/cpuinfo") as cpuinfo:
            for line in cpuinfo:
                key, _, value = line.partition(":")
                if key.strip() == "flags":
                    return frozenset(value.split())
    except OSError:
        pass
    return frozenset()
