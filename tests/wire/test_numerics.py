"""The floating-point kernels are pinned where a campaign's search would otherwise differ between machines."""

import platform
import subprocess
import sys

import pytest

from hakoniwa.wire.numerics import NUMPY_FEATURES_OFF, OPENBLAS_CORE, pin_kernels

x86 = pytest.mark.skipif(platform.machine().lower() not in ("x86_64", "amd64"), reason="the pin is for x86-64")


@x86
def test_an_avx512_machine_gets_the_avx2_kernels():
    env: dict[str, str] = {}
    pin_kernels(env, frozenset({"sse2", "avx", "avx2", "fma", "avx512f", "avx512bw"}))
    assert env == {"NPY_DISABLE_CPU_FEATURES": NUMPY_FEATURES_OFF, "OPENBLAS_CORETYPE": OPENBLAS_CORE}


@x86
def test_a_machine_without_avx2_and_a_users_own_choice_are_left_alone():
    env: dict[str, str] = {}
    pin_kernels(env, frozenset({"sse2", "avx"}))
    assert env == {}
    env = {"OPENBLAS_CORETYPE": "Zen"}
    pin_kernels(env, frozenset({"avx2", "fma"}))
    assert env["OPENBLAS_CORETYPE"] == "Zen"


@x86
def test_numpy_loaded_after_hakoniwa_runs_without_its_avx512_targets_and_without_a_warning():
    code = ("import hakoniwa, numpy\n"
            "from numpy._core._multiarray_umath import __cpu_features__ as f\n"
            "print(f['X86_V4'], f['AVX512_ICL'], f['AVX512_SPR'])")
    out = subprocess.run([sys.executable, "-W", "error", "-c", code], capture_output=True, text=True, check=True,
                         env={"PATH": "/usr/bin:/bin"})
    assert out.stdout.split() == ["False", "False", "False"]
