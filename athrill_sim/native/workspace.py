"""What an `--app` C program consists of: one `.c` file, or a folder in EV3RT's `sdk/workspace` shape.

A workspace folder holds `app.c`, and usually `app.h`, `app.cfg` (the kernel objects) and `Makefile.inc` (more
sources). Of `Makefile.inc` the variables that say what to compile are honoured: `APPL_COBJS` (`foo.o` is built
from `foo.c`, found in the folder or in `APPL_DIRS`), `APPL_DIRS`, `INCLUDES` (`-I`), and `-D`/`-U` in
`CDEFS`/`COPTS`; other flags are left out, so that nothing can loosen the strict float semantics the build
relies on. C++ and assembly sources are refused. `ifdef`/`ifndef`/`else`/`endif` are followed with the
variables the file itself sets (EV3RT's `USE_CXX` is not set: this is a C build).

A lone `.c` file is a program whose `main_task` is the one task. `path/app.c` beside an `app.cfg` is taken as
its workspace folder.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from athrill_sim.native import NativeBuildError, spike

APP_SOURCE = "app.c"
APP_CFG = "app.cfg"
MAKEFILE_INC = "Makefile.inc"
HASHED_SUFFIXES = (".c", ".h", ".cfg", ".inc")

_ASSIGN = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)\s*(:=|\+=|\?=|=)\s*(.*)")
_MKFILE_PATH = re.compile(r"\$[({]mkfile_path[)}]/?")


@dataclass(frozen=True)
class AppSources:
    """Everything the build needs to know about a program; paths are absolute."""

    root: Path  # the program's folder: the compiler runs there, and it is on the include path
    sources: tuple[Path, ...]
    cfg: Path | None  # None: one task, main_task
    include_dirs: tuple[Path, ...]  # besides `root`
    defines: tuple[str, ...]  # -D / -U flags
    hashed: tuple[Path, ...]  # the files whose content makes the cache key
    spike: bool = False  # a SPIKE program: built with the SPIKE-RT headers and runtime too (native/spike.py)


def find_app(path: Path) -> AppSources:
    """The program `path` names (NativeBuildError if it names none)."""
    path = Path(path).resolve()
    if path.is_file() and not (path.name == APP_SOURCE and (path.parent / APP_CFG).is_file()):
        if path.suffix != ".c":
            raise NativeBuildError(f"{path}: not a C source file (.c)")
        root = path.parent
        hashed = (path, *sorted(root.glob("*.h")))
        is_spike = spike.is_spike_program({}, hashed)
        return AppSources(root, (path,), None, (), spike.DEFINES if is_spike else (), hashed, is_spike)
    root = path if path.is_dir() else path.parent
    if not (root / APP_SOURCE).is_file():
        raise NativeBuildError(f"{root}: no {APP_SOURCE}; an EV3RT workspace folder holds app.c, app.h, app.cfg "
                               "and Makefile.inc")
    make = read_makefile_inc(root / MAKEFILE_INC) if (root / MAKEFILE_INC).is_file() else {}
    if make.get("APPL_CXXOBJS") or make.get("SRCLANG") == ["c++"]:
        raise NativeBuildError(f"{root / MAKEFILE_INC}: C++ sources are not supported by the native mock")
    if make.get("APPL_ASMOBJS"):
        raise NativeBuildError(f"{root / MAKEFILE_INC}: assembly sources are not supported by the native mock")
    dirs = [root] + [_folder(root, d, "APPL_DIRS") for d in make.get("APPL_DIRS", [])]
    includes = tuple(_folder(root, flag.removeprefix("-I"), "INCLUDES")
                     for flag in make.get("INCLUDES", []) if flag.startswith("-I") and flag != "-I")
    defines = tuple(flag for var in ("CDEFS", "COPTS") for flag in make.get(var, []) if flag[:2] in ("-D", "-U"))
    sources = [root / APP_SOURCE] + [_source_of(obj, dirs, root) for obj in make.get("APPL_COBJS", [])]
    cfg = root / APP_CFG if (root / APP_CFG).is_file() else None
    hashed = sorted({f for d in (*dirs, *includes) for f in d.iterdir() if f.is_file() and f.suffix in HASHED_SUFFIXES})
    is_spike = spike.is_spike_program(make, hashed)
    defines = (*spike.DEFINES, *defines) if is_spike else defines
    return AppSources(root, tuple(dict.fromkeys(sources)), cfg, includes, defines, tuple(hashed), is_spike)


def _folder(root: Path, name: str, variable: str) -> Path:
    if "$" in name:
        raise NativeBuildError(f"{root / MAKEFILE_INC}: cannot resolve {name!r} in {variable}")
    folder = (root / name).resolve()
    if not folder.is_dir():
        raise NativeBuildError(f"{root / MAKEFILE_INC}: {variable} names {name!r}, which is not a folder")
    return folder


def _source_of(obj: str, dirs: list[Path], root: Path) -> Path:
    stem = Path(obj).with_suffix(".c").name
    for d in dirs:
        if (d / stem).is_file():
            return d / stem
    raise NativeBuildError(f"{root / MAKEFILE_INC}: APPL_COBJS names {obj}, but there is no {stem} in "
                           + ", ".join(str(d) for d in dirs))


def read_makefile_inc(path: Path) -> dict[str, list[str]]:
    """The variables `path` sets, as lists of words (`$(mkfile_path)` is the folder itself)."""
    values: dict[str, list[str]] = {}
    taken = [True]  # whether each enclosing conditional branch is taken
    text = path.read_text(errors="replace").replace("\\\n", " ")
    for number, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        keyword, _, rest = line.partition(" ")
        if keyword in ("ifdef", "ifndef"):
            is_set = bool(values.get(rest.strip()))
            taken.append(taken[-1] and is_set == (keyword == "ifdef"))
        elif keyword == "else" and len(taken) > 1:
            taken[-1] = taken[-2] and not taken[-1]
        elif keyword == "endif" and len(taken) > 1:
            taken.pop()
        elif keyword in ("ifeq", "ifneq"):
            raise NativeBuildError(f"{path}:{number}: {keyword} is not supported by the native mock's build")
        elif taken[-1] and (m := _ASSIGN.fullmatch(line)):
            name, op, value = m.groups()
            words = _MKFILE_PATH.sub("", value).split()
            if op == "+=":
                values.setdefault(name, []).extend(words)
            elif op != "?=" or name not in values:
                values[name] = words
    return values
