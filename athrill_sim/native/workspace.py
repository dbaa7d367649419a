"""What an `--app` program consists of: one `.c` or `.cpp` file, or a folder in EV3RT's `sdk/workspace` shape.

A workspace folder holds `app.c` (or `app.cpp` when its `Makefile.inc` says `SRCLANG := c++`, as EV3RT then
builds `app.o` from it), and usually `app.h`, `app.cfg` (the kernel objects) and `Makefile.inc`, which GNU make
evaluates as EV3RT's build does (`athrill_sim.native.makefile`). Of what it sets, these decide the build:
`APPL_COBJS` / `APPL_CXXOBJS` (`foo.o` is built from `foo.c` / `foo.cpp`, found as EV3RT's vpath finds it: in
the folder, in any `src/` folder under it, then in `APPL_DIRS`), `INCLUDES` (and any `include/` folder under
the program's, as EV3RT adds them), the libraries it includes (`libcpp-ev3`), `-l` libraries in `APPL_LIBS`,
and of `COPTS` / `CDEFS` only `-D`, `-U`, `-I` and `-std=`: nothing may loosen the strict float semantics the
build relies on. Assembly sources are refused.

A lone `.c` file is a program whose `main_task` is the one task; a lone `.cpp` file is the same in C++, with
`libcpp-ev3`. `path/app.c` (or `app.cpp`) beside an `app.cfg` is taken as its workspace folder.
"""

from __future__ import annotations

import dataclasses
import re
import tempfile
from dataclasses import dataclass
from pathlib import Path

from athrill_sim.native import NativeBuildError, spike
from athrill_sim.native.makefile import NO_MAKEFILE, MakeVars, evaluate

APP_SOURCE = "app.c"
APP_CXX_SOURCE = "app.cpp"
APP_CFG = "app.cfg"
MAKEFILE_INC = "Makefile.inc"
C_SUFFIX, CXX_SUFFIX = ".c", ".cpp"
SOURCE_SUFFIXES = (C_SUFFIX, CXX_SUFFIX)
HASHED_SUFFIXES = (".c", ".h", ".cfg", ".inc", ".cpp", ".hpp", ".cc", ".hh", ".cxx", ".hxx", ".cdl")
# What a lone .cpp file is built as: EV3RT's C++ language and its C++ library, as a workspace would say it.
LONE_CXX_MAKEFILE_INC = """SRCLANG := c++
ifdef CONFIG_EV3RT_APPLICATION
include $(EV3RT_SDK_LIB_DIR)/libcpp-ev3/Makefile
endif
"""
_STD = re.compile(r"-std=(?P<cxx>(?:gnu|c)\+\+)?\w+")


@dataclass(frozen=True)
class AppSources:
    """Everything the build needs to know about a program; paths are absolute."""

    root: Path  # the program's folder: the compiler runs there, and it is on the include path
    sources: tuple[Path, ...]  # .c and .cpp files
    cfg: Path | None  # None: one task, main_task
    include_dirs: tuple[Path, ...]  # besides `root`
    defines: tuple[str, ...]  # -D / -U flags
    hashed: tuple[Path, ...]  # the files whose content makes the cache key
    libs: tuple[str, ...] = ()  # -l flags
    c_std: str | None = None  # a -std= of COPTS for C ...
    cxx_std: str | None = None  # ... and for C++
    spike: bool = False  # a SPIKE program: built with the SPIKE-RT headers and runtime too (native/spike.py)
    library_sources: tuple[Path, ...] = ()  # of the EV3RT libraries it includes, linked as archives are
    hub: bool = False  # built in SPIKE-RT's own SDK for the hub (the Basic class): SPIKE-RT's libcpp too (spike.py)

    @property
    def cxx(self) -> bool:
        """Whether any source is C++ (then the program links with the C++ library)."""
        return any(s.suffix == CXX_SUFFIX for s in (*self.sources, *self.library_sources))


def find_app(path: Path) -> AppSources:
    """The program `path` names (NativeBuildError if it names none)."""
    path = Path(path).resolve()
    if path.is_file() and not (path.name in (APP_SOURCE, APP_CXX_SOURCE) and (path.parent / APP_CFG).is_file()):
        if path.suffix not in SOURCE_SUFFIXES:
            raise NativeBuildError(f"{path}: not a C or C++ source file (.c, .cpp)")
        return _lone_app(path)
    root = path if path.is_dir() else path.parent
    return _workspace_app(root, program_makefile(root))


def program_makefile(root: Path) -> MakeVars:
    """What the workspace folder's `Makefile.inc` sets. A folder without one is built as if it had an empty
    one: EV3RT's samples with nothing to add ship it empty, so its absence says nothing else. `hako try`
    (native) and `hako build` (v850) both read a program through this, so they take the same folders."""
    return evaluate(root / MAKEFILE_INC) if (root / MAKEFILE_INC).is_file() else NO_MAKEFILE


def _lone_app(source: Path) -> AppSources:
    root = source.parent
    hashed = [source, *sorted(root.glob("*.h"))]
    if source.suffix == C_SUFFIX:
        is_spike = spike.is_spike_program(NO_MAKEFILE, hashed)
        return AppSources(root, (source,), None, (), spike.DEFINES if is_spike else (), tuple(hashed), spike=is_spike)
    with tempfile.TemporaryDirectory(prefix="hako-lone-") as scratch:
        inc = Path(scratch) / "app" / MAKEFILE_INC
        inc.parent.mkdir()
        inc.write_text(LONE_CXX_MAKEFILE_INC)
        make = evaluate(inc)
    make = dataclasses.replace(make, makefiles=tuple(m for m in make.makefiles if m != inc.resolve()))
    app = _workspace_sources(root, make, [source], hashed)
    return AppSources(root, app.sources, None, app.include_dirs, app.defines, app.hashed, spike=app.spike,
                      library_sources=app.library_sources, hub=app.hub)


def _workspace_app(root: Path, make: MakeVars) -> AppSources:
    cxx = make.words("SRCLANG") == ["c++"]
    main = root / (APP_CXX_SOURCE if cxx else APP_SOURCE)
    if not main.is_file():
        other = root / (APP_SOURCE if cxx else APP_CXX_SOURCE)
        if other.is_file():
            raise NativeBuildError(f"{root}: {other.name}, but {MAKEFILE_INC} says SRCLANG {'c++' if cxx else 'c'}: "
                                   f"EV3RT builds app.o from {main.name} then (set SRCLANG := "
                                   f"{'c' if cxx else 'c++'} in {MAKEFILE_INC})")
        raise NativeBuildError(f"{root}: no {main.name}; an EV3RT workspace folder holds {main.name}, app.h, "
                               "app.cfg and Makefile.inc")
    if make.words("APPL_ASMOBJS"):
        raise NativeBuildError(f"{root / MAKEFILE_INC}: assembly sources are not supported by the native mock")
    hashed = sorted(f for f in root.rglob("*") if f.is_file() and f.suffix in HASHED_SUFFIXES)
    return _workspace_sources(root, make, [main], hashed)


def _workspace_sources(root: Path, make: MakeVars, main: list[Path], hashed: list[Path]) -> AppSources:
    inc = root / MAKEFILE_INC
    flags = make.words("COPTS") + make.words("CDEFS")
    auto = sorted(d for d in root.rglob("*") if d.is_dir() and d.name in ("src", "include"))
    dirs = [root] + [d for d in auto if d.name == "src"] + _folders(root, make.words("APPL_DIRS"))
    includes = [d for d in auto if d.name == "include"] + _folders(root, _option_values(make.words("INCLUDES"), "-I")
                                                                    + _option_values(flags, "-I"))
    sources = list(main)
    sources += [_source_of(obj, C_SUFFIX, dirs, inc, "APPL_COBJS") for obj in make.words("APPL_COBJS")]
    sources += [_source_of(obj, CXX_SUFFIX, dirs, inc, "APPL_CXXOBJS") for obj in make.words("APPL_CXXOBJS")]
    library = []
    for lib in make.libraries:
        lib_dirs = [lib.folder / "src"]
        library += [_source_of(o, C_SUFFIX, lib_dirs, lib.folder / "Makefile", "THIS_LIB_OBJS") for o in lib.c_objects]
        library += [_source_of(o, CXX_SUFFIX, lib_dirs, lib.folder / "Makefile", "THIS_LIB_CXXOBJS")
                    for o in lib.cxx_objects]
    defines = tuple(f for f in _split_options(flags) if f[:2] in ("-D", "-U"))
    stds = [m for f in flags if (m := _STD.fullmatch(f))]
    c_std = next((m[0] for m in reversed(stds) if not m["cxx"]), None)
    cxx_std = next((m[0] for m in reversed(stds) if m["cxx"]), None)
    libs = tuple(_libs(make.words("APPL_LIBS"), inc))
    files = {*hashed, *make.makefiles, *sources, *library}
    files |= {f for d in (*dirs, *includes) for f in d.iterdir() if f.is_file() and f.suffix in HASHED_SUFFIXES}
    is_hub = spike.is_hub_program(root, sorted(files))
    is_spike = is_hub or spike.is_spike_program(make, sorted(files))
    defines = (*spike.DEFINES, *defines) if is_spike and not is_hub else defines
    return AppSources(root, tuple(dict.fromkeys(sources)), root / APP_CFG if (root / APP_CFG).is_file() else None,
                      tuple(dict.fromkeys(d for d in includes if d != root)), defines, tuple(sorted(files)), libs,
                      c_std, cxx_std, is_spike, tuple(dict.fromkeys(library)), is_hub)


def _split_options(words: list[str]) -> list[str]:
    """`-D NAME` and `-I dir` as one word each, as the compiler reads them."""
    out: list[str] = []
    for word in words:
        if out and out[-1] in ("-D", "-U", "-I"):
            out[-1] += word
        else:
            out.append(word)
    return out


def _option_values(words: list[str], option: str) -> list[str]:
    return [w[len(option):] for w in _split_options(words) if w.startswith(option) and len(w) > len(option)]


def _folders(root: Path, names: list[str]) -> list[Path]:
    """The folders `names` say, relative to the program's folder; like the compiler and make's vpath, a name
    that is no folder is passed over (a missing header is then the compiler's error, naming it)."""
    return [folder for name in names if (folder := (root / name).resolve()).is_dir()]


def _source_of(obj: str, suffix: str, dirs: list[Path], makefile: Path, variable: str) -> Path:
    stem = Path(obj).with_suffix(suffix)
    for d in dirs:
        if (d / stem).is_file():
            return (d / stem).resolve()
    raise NativeBuildError(f"{makefile}: {variable} names {obj}, but there is no {stem} in "
                           + ", ".join(str(d) for d in dirs))


def _libs(words: list[str], makefile: Path) -> list[str]:
    """The `-l` libraries of APPL_LIBS; a prebuilt archive or object is a v850 file no native build can link."""
    libs = []
    for word in words:
        if word.startswith("-l"):
            libs.append(word)
        elif word.endswith((".a", ".o")):
            raise NativeBuildError(f"{makefile}: APPL_LIBS names {word}, a prebuilt library, which a native build "
                                   "cannot link (add its sources to APPL_COBJS or APPL_CXXOBJS)")
    return libs
