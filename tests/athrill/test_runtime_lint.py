"""The native runtime's own C is kept to one style and free of the compiler's warnings: what .ci/run checks
with clang-format, and every source compiled with -Wall -Wextra as errors (the program's code is not ours, so
the build itself only warns)."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from athrill_sim.native import spike
from athrill_sim.native.build import POSIX_LAYER, RUNTIME_INCLUDE, RUNTIME_SRC, find_compiler
from athrill_sim.native.headers import generated_headers
from athrill_sim.native.makefile import ETROBOC_COMMON
from tests.helpers.paths import REPO

RUNTIME_C = sorted([*RUNTIME_SRC.glob("*.[ch]"), *spike.SOURCE_DIR.glob("*.[ch]")])


@pytest.mark.parametrize("source", [s for s in RUNTIME_C if s.suffix == ".c"], ids=lambda s: s.name)
def test_the_runtime_compiles_without_a_warning(source, tmp_path):
    for name, text in generated_headers().items():
        (tmp_path / name).write_text(text)
    (tmp_path / "kernel_cfg.h").write_text("#define TNUM_TSKID 1\n")  # what app.cfg would generate
    includes = [f"-I{d}" for d in (tmp_path, RUNTIME_INCLUDE, *spike.INCLUDE_DIRS, ETROBOC_COMMON)]
    out = subprocess.run([str(find_compiler()), "-std=gnu11", "-O2", "-fsyntax-only", "-Wall", "-Wextra", "-Werror",
                          "-Wno-int-to-pointer-cast", *includes, str(source)], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr


@pytest.mark.skipif(shutil.which("clang-format") is None,
                    reason="clang-format is not installed (pip install -e '.[test]' brings it)")
def test_the_runtime_is_formatted_as_clang_format_says():
    out = subprocess.run(["clang-format", "--dry-run", "--Werror", *map(str, RUNTIME_C)], cwd=REPO,
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr[:2000]


def test_the_format_check_covers_the_runtime_alone():
    """Third-party C (EV3RT's libcpp-ev3, ET Robocon's libcpp-spike, the SDK headers) keeps its own style."""
    assert all(Path(s).is_relative_to(RUNTIME_SRC.parent) for s in RUNTIME_C)
    assert not any("sdk" in s.parts for s in RUNTIME_C)


# The program-facing device calls: EV3RT's (ev3api.h) and Athrill's own (athrill_syscall.h,
# athrill_serial_driver.h). A runtime source outside the kernel that defines one is a device module, as every
# SPIKE source is (the kernel's cyclic.c defines EV3RT's ev3_sta_cyc, a kernel service).
DEVICE_CALLS = ("ev3_", "athrill_")


def symbols(source: Path, tmp_path: Path, undefined: bool) -> set[str]:
    for name, text in generated_headers().items():
        (tmp_path / name).write_text(text)
    (tmp_path / "kernel_cfg.h").write_text("#define TNUM_TSKID 1\n")
    obj = tmp_path / (source.name + ".o")
    includes = [f"-I{d}" for d in (tmp_path, RUNTIME_INCLUDE, *spike.INCLUDE_DIRS, ETROBOC_COMMON)]
    subprocess.run([str(find_compiler()), "-std=gnu11", "-O2", "-c", *includes, str(source), "-o", str(obj)],
                   check=True, capture_output=True)
    out = subprocess.run(["nm", "--undefined-only" if undefined else "--defined-only", str(obj)],
                         capture_output=True, text=True, check=True).stdout
    return {line.split()[-1] for line in out.splitlines() if line.strip()}


def kernel_modules() -> list[Path]:
    """The kernel's modules: the sources that share its state (kernel_impl.h), as TOPPERS' kernel's do."""
    return [s for s in sorted(RUNTIME_SRC.glob("*.c")) if '#include "kernel_impl.h"' in s.read_text()]


@pytest.mark.skipif(shutil.which("nm") is None, reason="needs nm (binutils) to read the objects' symbols")
def test_the_kernel_calls_no_device_by_name(tmp_path):
    """The devices register hooks (devices.h); no module of the kernel reaches one of their functions by name,
    so a device may use the kernel's services without a circle. The devices are found from what they define,
    not listed by hand."""
    modules = kernel_modules()
    assert {m.name for m in modules} >= {"kernel.c", "task.c", "task_sync.c", "thread.c", "cyclic.c",
                                         "time_event.c"}
    called = set().union(*(symbols(m, tmp_path, undefined=True) for m in modules))
    devices = [s for s in sorted(RUNTIME_SRC.glob("*.c")) if s not in modules
               and any(name.startswith(DEVICE_CALLS) for name in symbols(s, tmp_path, undefined=False))]
    assert {d.name for d in devices} >= {"brick.c", "ev3api.c", "lcd.c", "serial.c"}
    for device in devices + sorted(spike.SOURCE_DIR.glob("*.c")):
        assert not called & symbols(device, tmp_path, undefined=False), device.name


def test_each_kernel_module_holds_one_concern():
    """kernel.c dispatches; tasks, their synchronisation, threads, cyclic handlers and time events each have a
    module of their own, none of them the size kernel.c was (821 lines) when it held them all."""
    assert all(len(m.read_text().splitlines()) < 300 for m in kernel_modules())


def named(tool: list[str], source: Path, tmp_path: Path) -> list[str]:
    """The lines `tool` prints of `source`'s object (compiled by `symbols`)."""
    symbols(source, tmp_path, undefined=True)
    out = subprocess.run([*tool, str(tmp_path / (source.name + ".o"))], capture_output=True, text=True, check=True)
    return out.stdout.splitlines()


@pytest.mark.skipif(shutil.which("nm") is None or shutil.which("objdump") is None,
                    reason="needs nm and objdump (binutils) to read the objects' symbols")
def test_the_runtime_reaches_no_c_library_name_it_defines(tmp_path):
    """The POSIX layer's C library names are weak, so that a program's own `clock` or `open` wins (build.py);
    a call the runtime made by such a name would then reach the program's. The runtime reaches its own through
    their hako_ names, and the C library's through hako_real(), from whichever object calls."""
    interposed = {line.split()[-1] for source in sorted(RUNTIME_SRC.glob(POSIX_LAYER))
                  for line in named(["nm", "--defined-only", "--extern-only"], source, tmp_path)
                  if not line.split()[-1].startswith("hako_")}
    assert {"clock", "time", "sleep", "signal", "open", "system", "fopen"} <= interposed
    for source in [s for s in RUNTIME_C if s.suffix == ".c"]:
        relocations = [line for line in named(["objdump", "-r"], source, tmp_path) if line[:1].isdigit()]
        reached = {re.split(r"[-+]", line.split()[-1])[0] for line in relocations}
        assert not reached & interposed, source.name
