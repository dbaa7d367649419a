"""The compiled move graph and fastest-path queries (maze/fastpath/kernel.c), built at first use and cached.

Why: every query went through scipy's Dijkstra from Python, three calls and a few dozen numpy operations a
query, and importing scipy alone cost a whole-process `mazelog explore --objective time` 0.2-0.3 s. The C file
is compiled with the system C compiler ($CC, else cc, else gcc), as users' native robot programs already are,
into `${XDG_CACHE_HOME:-~/.cache}/mazelog/` under a name hashed from the source and the compiler, and loaded
with ctypes. Where no compiler works, the queries take the scipy path (the same routes, slower), and the
first query says so once on stderr.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
from functools import cache
from importlib.resources import files
from pathlib import Path
from typing import Any

SOURCE = "kernel.c"
FLAGS = ("-O2", "-shared", "-fPIC", "-ffp-contract=off", "-fno-fast-math")  # no fused rounding: routes to the bit
COMPILE_TIMEOUT_S = 60
FALLBACK = "so fastest-path queries use scipy (the same routes, slower)"
NO_COMPILER = f"note: no C compiler ($CC, cc or gcc), {FALLBACK}"

_double_p = ctypes.POINTER(ctypes.c_double)
_void_p = ctypes.c_void_p


def cache_dir() -> Path:
    """Where built kernels are kept: `${XDG_CACHE_HOME:-~/.cache}/mazelog`."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "mazelog"


def compiler() -> Path | None:
    for name in (os.environ.get("CC"), "cc", "gcc"):
        if name and (found := shutil.which(name)):
            return Path(found)
    return None


def _library_path(source: bytes, cc: Path) -> Path:
    """The cached library's name: a hash of the source, the flags and the compiler (its path, size and date:
    asking it its version would cost every process a run of it)."""
    stat = cc.stat()
    key = hashlib.sha256(b"\0".join([source, " ".join(FLAGS).encode(), str(cc).encode(),
                                     f"{stat.st_size}:{stat.st_mtime_ns}".encode()])).hexdigest()[:24]
    return cache_dir() / f"fastpath-{key}.so"


def _build(source: bytes, cc: Path, target: Path) -> None:
    """Compile into a scratch file beside `target` and rename it into place, so that two processes building at
    once both end up with a whole library."""
    target.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=target.parent) as scratch:
        c_file, so_file = Path(scratch) / SOURCE, Path(scratch) / target.name
        c_file.write_bytes(source)
        subprocess.run([str(cc), *FLAGS, "-o", str(so_file), str(c_file), "-lm"], check=True,
                       capture_output=True, timeout=COMPILE_TIMEOUT_S)
        so_file.replace(target)


_i32_p = ctypes.POINTER(ctypes.c_int32)


class Spec(ctypes.Structure):
    """What fp_graph reads to build a query graph (spec_t in maze/fastpath/kernel.c, field for field)."""

    _fields_ = [("size", ctypes.c_int32), ("has", ctypes.c_int32 * 8), ("k", ctypes.c_int32 * 8),
                ("max_n", ctypes.c_int32), ("to_turn", _double_p), ("to_goal", _double_p),
                ("speed_up", ctypes.c_double * 8), ("cruise", ctypes.c_double * 8), ("unit", ctypes.c_double * 8),
                ("nshapes", ctypes.c_int32), ("shape_in", _i32_p), ("shape_out", _i32_p), ("shape_parity", _i32_p),
                ("shape_noffsets", _i32_p), ("shape_offsets", _i32_p), ("shape_seconds", _double_p),
                ("nstart", ctypes.c_int32), ("start_dst", _i32_p), ("start_run_from", _i32_p),
                ("start_open_needed", _i32_p), ("start_first_wall", _i32_p), ("start_seconds", _double_p),
                ("ngoals", ctypes.c_int32), ("goal_cells", _i32_p), ("wall_at", _i32_p), ("slack", ctypes.c_double)]


def _bind(lib: ctypes.CDLL) -> ctypes.CDLL:
    lib.fp_graph.argtypes, lib.fp_graph.restype = [ctypes.POINTER(Spec)], _void_p
    lib.fp_graph_free.argtypes, lib.fp_graph_free.restype = [_void_p], None
    lib.fp_graph_nodes.argtypes, lib.fp_graph_nodes.restype = [_void_p], ctypes.c_int32
    lib.fp_query.argtypes = [_void_p, ctypes.c_char_p, _void_p, _void_p]
    lib.fp_query.restype = ctypes.c_int32
    i32 = ctypes.c_int32
    decode: list[type[ctypes._SimpleCData[Any]]] = [_void_p, _void_p, _void_p, i32, i32, i32]
    lib.fp_decode.argtypes = decode + [_void_p] * 10
    lib.fp_decode.restype = i32
    return lib


@cache
def kernel() -> ctypes.CDLL | None:
    """The compiled kernel, built on first use; None (said once on stderr) where it cannot be built or loaded.
    MAZELOG_KERNEL=off forces the scipy path (the tests compare the two)."""
    if os.environ.get("MAZELOG_KERNEL") == "off":
        return None
    source = files("maze.fastpath").joinpath(SOURCE).read_bytes()
    cc = compiler()
    if cc is None:
        print(NO_COMPILER, file=sys.stderr)
        return None
    try:
        target = _library_path(source, cc)
        if not target.is_file():
            _build(source, cc, target)
        return _bind(ctypes.CDLL(str(target)))
    except subprocess.CalledProcessError as e:
        said = e.stderr.decode(errors="replace").splitlines()
        why = next((line for line in said if "error" in line), said[0] if said else f"exit status {e.returncode}")
    except subprocess.TimeoutExpired:
        why = f"{cc} ran over {COMPILE_TIMEOUT_S} s"
    except OSError as e:
        why = f"{e.filename or e}: {e.strerror}" if e.strerror else str(e)
    print(f"note: the fastest-path kernel could not be built ({why}), {FALLBACK}", file=sys.stderr)
    return None
