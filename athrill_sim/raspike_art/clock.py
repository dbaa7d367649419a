"""asp's clock library: the native runtime's simulated clock, lockstep and mapped files, with asp's timer tick
(athrill_sim/native/runtime/asp/asp_time.c) and asp's serial port counted into the lockstep (asp_serial.c),
compiled for aarch64 into a library that qemu-user preloads into asp beside RasPike-ART's `libssetjmp.so`. One
mechanism for both paths: the same C files the native runtime links, and the same generated headers
(athrill_sim/native/headers.py), so that the step, the cost of a call and the file layout cannot differ between
them. Cached by those sources and the cross compiler's identity.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

from athrill_sim.native.build import C_STD, STRICT_FLAGS
from athrill_sim.native.headers import generated_headers
from athrill_sim.programs.build_cache import CacheKey, cache_root, cached_build
from athrill_sim.raspike_art import AspError
from athrill_sim.raspike_art.build import CROSS_GCC, INSTALL_CROSS

RUNTIME = Path(__file__).parent.parent / "native" / "runtime"
# The runtime's files asp takes as they are; asp_time.c stands where kernel.c does for the native runtime.
SHARED_SOURCES = ("sim_time.c", "lockstep.c", "mapped_files.c", "real.c", "lines.c", "posix_time.c")
ASP_SOURCES = ("asp_time.c", "asp_threads.c", "asp_serial.c", "asp_spin.c")
EXPORTS = RUNTIME / "asp" / "exports.map"
LIBRARY = "libhakotime.so"
RUN_DIR_ENV = "HAKO_RUN_DIR"  # asp_time.c: the run directory, and the test it waits for (asp's argv is asp's)
TEST_ENV = "HAKO_TEST"


def sources() -> list[Path]:
    return [RUNTIME / "src" / name for name in SHARED_SOURCES] + [RUNTIME / "asp" / name for name in ASP_SOURCES]


def build_clock_library() -> Path:
    """The aarch64 clock library, built now unless cached."""
    gcc = shutil.which(CROSS_GCC)
    if gcc is None:
        raise AspError(INSTALL_CROSS)
    headers = generated_headers()
    key = CacheKey()
    try:
        version = subprocess.run([gcc, "--version"], capture_output=True, text=True, timeout=60,
                                 env={**os.environ, "LC_ALL": "C"}).stdout
    except (OSError, subprocess.TimeoutExpired) as e:
        raise AspError(f"cannot run {gcc}: {e}") from None
    key.add("compiler", f"{gcc}\n{version}".encode())
    key.add("builder", Path(__file__).read_bytes())
    for f in sorted(RUNTIME.rglob("*.[ch]")) + [EXPORTS]:
        key.add(str(f.relative_to(RUNTIME)), f.read_bytes())
    for name, text in sorted(headers.items()):
        key.add(f"generated/{name}", text.encode())
    entry = cache_root() / "raspike-art-clock" / key.name()
    return cached_build(entry, LIBRARY, lambda scratch: _build(gcc, headers, scratch))


def _build(gcc: str, headers: dict[str, str], scratch: Path) -> None:
    generated = scratch / "include"
    generated.mkdir()
    for name, text in headers.items():
        (generated / name).write_text(text)
    cmd = [gcc, "-shared", "-fPIC", C_STD, *STRICT_FLAGS, f"-I{generated}",
           f"-I{RUNTIME / 'src'}", f"-I{RUNTIME / 'include'}", *map(str, sources()), "-o", str(scratch / LIBRARY),
           "-Wl,-z,defs", f"-Wl,--version-script={EXPORTS}", "-lpthread", "-ldl"]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    if done.returncode != 0:
        first = next((line for line in done.stderr.splitlines() if "error" in line), done.stderr.strip())
        raise AspError(f"asp's clock library does not build ({CROSS_GCC}): {first}")
