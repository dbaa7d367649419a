"""Building a user's EV3RT C or C++ program into a native Athrill, once per campaign and cached.

The cache key is a hash of everything that goes into the binary: the program's files (`AppSources.hashed`, by
their paths relative to the program's folder, so a copy elsewhere is the same program, and the makefiles its
`Makefile.inc` read), the runtime's sources and headers, the generated headers, the generator's own code, the
flags, and the compilers' identities (their paths and `--version`). A build happens in a scratch folder beside
the cache entry and is renamed into place when it is whole, so two benches building the same program at once
both end up with a good binary. Entries live in `${XDG_CACHE_HOME:-~/.cache}/hakoniwa-py/native/<key>/`, with
the compilers' output in `build.log`.

Each source is compiled on its own (C with `$CC`, C++ with `$CXX`, two at a time), so that sources of the
same name in different folders (EV3RT keeps a library's objects apart too) never collide, and the objects are
linked by the C++ driver when any source is C++. The flags keep float arithmetic strict, so that a program
computes what its source says, operation by operation: `-ffp-contract=off` (no fused multiply-add) and no
fast-math. `-fno-strict-aliasing`, because embedded code type-puns freely; integer-to-pointer casts are not
warned about, because EV3RT programs use guest addresses. C++ is gcc 12's default dialect, `-std=gnu++17`,
which the v850 toolchain compiles EV3RT's C++ programs with; a `-std=` in the program's `COPTS` wins.
The POSIX layer's definitions (`posix_*.c`: `clock`, `time`, `sleep`, `open`, `system`, ...) are made weak
with `objcopy --weaken`, so that a program's own global of the same name (ET Robocon's tutorial has
`Clock clock;` beside main_task) wins, as it wins over the C library's on the robot; every other caller, the
C library and libstdc++ included, still reaches the runtime's (docs/DESIGN-NOTES.md, "A program's own names").
ET Robocon's programs define `void *__dso_handle = 0;` (EV3RT links without the C runtime's start files,
which define it); natively that name is the C runtime's, so the program's is renamed by a macro.
"""

from __future__ import annotations

import dataclasses
import os
import re
import shutil
import subprocess
from collections.abc import Collection
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from athrill_sim.native import NativeBuildError, appcfg, headers, makefile, spike, workspace
from athrill_sim.native.appcfg import KERNEL_CFG_C, KERNEL_CFG_H, kernel_config
from athrill_sim.native.makefile import ETROBOC_COMMON
from athrill_sim.native.workspace import CXX_SUFFIX, AppSources, find_app
from athrill_sim.programs.build_cache import CacheKey, cache_root, cached_build

RUNTIME = Path(__file__).with_name("runtime")
RUNTIME_INCLUDE = RUNTIME / "include"
RUNTIME_SRC = RUNTIME / "src"
POSIX_LAYER = "posix_*.c"  # the C library's functions on simulated time: weak, so a program's own names win
GENERATORS = (Path(__file__), Path(appcfg.__file__), Path(headers.__file__), Path(workspace.__file__),
              Path(makefile.__file__), Path(spike.__file__))
STRICT_FLAGS = ("-O2", "-ffp-contract=off", "-fno-fast-math", "-fno-strict-aliasing", "-Wall",
                "-Wno-int-to-pointer-cast")
C_STD = "-std=gnu11"
CXX_STD = "-std=gnu++17"
CXX_FLAGS = ("-D__dso_handle=hako_program_dso_handle",)
LIBS = ("-lm", "-ldl")
EXECUTABLE = "athrill-native"
BUILD_LOG = "build.log"
OBJECTS = "objects"
COMPILE_TIMEOUT_S = 300
INSTALL_CXX = "install one (apt-get install g++) or set CXX"

_ERROR = re.compile(r"\berror: |undefined reference to |multiple definition of ")
_LINKER_LOCATION = re.compile(r"^.*?:\(\.\w+[^)]*\): ")
_UNDEFINED = re.compile(r"undefined reference to [`'\u2018]([A-Za-z_]\w*)['\u2019]")
_UNDECLARED = re.compile(r"(?:unknown type name |implicit declaration of function )[`'\u2018](?P<c>[A-Za-z_]\w*)"
                         r"['\u2019]|[`'\u2018](?P<cxx>[A-Za-z_]\w*)['\u2019] was not declared")


def find_compiler() -> Path:
    """The system C compiler: $CC, else cc, else gcc."""
    return _find(("CC", "cc", "gcc"), "no C compiler (cc or gcc) on PATH to build a native app; install one or set CC")


def find_cxx_compiler() -> Path:
    """The system C++ compiler: $CXX, else c++, else g++."""
    return _find(("CXX", "c++", "g++"), f"no C++ compiler (c++ or g++) on PATH to build a C++ app; {INSTALL_CXX}")


def _find(names: tuple[str, str, str], missing: str) -> Path:
    env, *defaults = names
    for name in (os.environ.get(env), *defaults):
        if name and (found := shutil.which(name)):
            return Path(found)
    raise NativeBuildError(missing)


class Compilers:
    """The C compiler, and the C++ one when the program has C++ sources."""

    def __init__(self, app: AppSources) -> None:
        self.cc = find_compiler()
        self.cxx = find_cxx_compiler() if app.cxx else None

    def identity(self) -> str:
        return "\n".join(f"{c}\n{_compiler_identity(c)}" for c in (self.cc, self.cxx) if c is not None)


def build_app(path: Path, *, flags: tuple[str, ...] = ()) -> Path:
    """The native Athrill for the program at `path`, built now unless the cache holds it. `flags` are extra
    compiler flags after the program's own (a tuned program's -DNAME=value, athrill_sim.tuning)."""
    app = find_app(path)
    app = dataclasses.replace(app, defines=(*app.defines, *flags)) if flags else app
    compilers = Compilers(app)
    generated = headers.generated_headers()
    return cached_build(cache_root() / "native" / cache_key(app, compilers, generated), EXECUTABLE,
                        lambda scratch: _build(app, compilers, generated, scratch))


def cache_key(app: AppSources, compilers: Compilers, generated: dict[str, str]) -> str:
    key = CacheKey()
    add = key.add

    def rel(path: Path | None) -> str:
        return os.path.relpath(path, app.root) if path else ""

    add("compiler", compilers.identity().encode())
    add("flags", "\0".join((*STRICT_FLAGS, *_c_flags(app), *_cxx_flags(app), *LIBS, *app.libs, *app.defines)).encode())
    add("layout", repr(([rel(s) for s in app.sources], [rel(s) for s in app.library_sources], rel(app.cfg),
                        [rel(d) for d in app.include_dirs])).encode())
    for f in (*sorted(RUNTIME.rglob("*.[ch]")), *sorted(f for f in spike.SPIKE_RT.rglob("*") if f.is_file()),
              *GENERATORS):
        add(os.path.relpath(f, RUNTIME.parent), f.read_bytes())
    for f in app.hashed:
        add(rel(f), f.read_bytes())
    for name, text in sorted(generated.items()):
        add(name, text.encode())
    return key.name()


def _c_flags(app: AppSources) -> tuple[str, ...]:
    return (app.c_std or C_STD, *STRICT_FLAGS)


def _cxx_flags(app: AppSources) -> tuple[str, ...]:
    return (app.cxx_std or CXX_STD, *STRICT_FLAGS, *CXX_FLAGS)


def _compile_flags(app: AppSources) -> list[str]:
    """The program's -D/-U, and extra flags (a tuned program's); of those, the linker's (-Wl,) go to the link."""
    return [f for f in app.defines if not f.startswith("-Wl,")]


def _link_flags(app: AppSources) -> list[str]:
    return [f for f in app.defines if f.startswith("-Wl,")]


def _compiler_identity(cc: Path) -> str:
    try:
        out = subprocess.run([str(cc), "--version"], capture_output=True, text=True, timeout=60, env=_compiler_env())
    except OSError as e:
        raise NativeBuildError(f"cannot run the compiler {cc}: {e.strerror}") from None
    return out.stdout


def _compiler_env() -> dict[str, str]:
    return {**os.environ, "LC_ALL": "C"}  # plain ASCII messages, whatever the user's locale


def _include_flags(app: AppSources, build_dir: Path) -> list[str]:
    """Ours first: a stray kernel_cfg.h from a real EV3RT build in the program's folder, or ET Robocon's own
    etroboc_ext.h on the program's include path, must not win."""
    ours = (RUNTIME_INCLUDE, *(spike.INCLUDE_DIRS if app.spike else ()), *_hub_include_dirs(app), ETROBOC_COMMON)
    return [f"-I{d}" for d in (build_dir, *ours, app.root, *app.include_dirs)]


def _hub_include_dirs(app: AppSources) -> tuple[Path, ...]:
    """SPIKE-RT's libcpp for a hub program, and for a C++ one its folders as the hub SDK's app.mk adds them."""
    if not app.hub:
        return ()
    return (*spike.HUB_INCLUDE_DIRS, *(spike.HUB_CXX_INCLUDE_DIRS if app.cxx else ()))


def _build(app: AppSources, compilers: Compilers, generated: dict[str, str], build_dir: Path) -> None:
    for name, text in generated.items():
        (build_dir / name).write_text(text)
    includes = _include_flags(app, build_dir)

    def preprocess(cfg: Path) -> str:
        cmd = [str(compilers.cc), "-E", "-P", "-x", "c", "-DTOPPERS_MACRO_ONLY", *includes, *_compile_flags(app),
               str(cfg)]
        return _run(cmd, app.root, build_dir, f"{cfg.name} does not preprocess")

    config = kernel_config(app.cfg, preprocess)
    (build_dir / KERNEL_CFG_H).write_text(config.header())
    (build_dir / KERNEL_CFG_C).write_text(config.source())
    sources = [*app.sources, build_dir / KERNEL_CFG_C, *sorted(RUNTIME_SRC.glob("*.c")),
               *(spike.sources() if app.spike else ()), *(spike.hub_cxx_sources() if app.hub and app.cxx else ())]
    objects = _compile_all(app, compilers, includes, [*sources, *app.library_sources], build_dir)
    failure = f"{app.sources[0].name} does not build"
    for source, obj in zip(sources, objects):
        if source.parent == RUNTIME_SRC and source.match(POSIX_LAYER):
            _run(["objcopy", "--weaken", str(obj)], app.root, build_dir, failure)
    archive = []
    if app.library_sources:  # an archive, as EV3RT links its libraries: what the program does not use stays out
        archive = [build_dir / OBJECTS / "libraries.a"]
        _run(["ar", "rcs", str(archive[0]), *map(str, objects[len(sources):])], app.root, build_dir, failure)
    linker = compilers.cxx or compilers.cc
    entries = {t.entry for t in config.tasks} | {c.handler for c in config.cyclics if c.handler}
    _run([str(linker), *_link_flags(app), *map(str, objects[:len(sources)]), *map(str, archive), "-o",
          str(build_dir / EXECUTABLE), *app.libs, *LIBS], app.root, build_dir, failure, entries, cxx=app.cxx,
         subset=_subset(app))
    shutil.rmtree(build_dir / OBJECTS)


def _compile_all(app: AppSources, compilers: Compilers, includes: list[str], sources: list[Path],
                 build_dir: Path) -> list[Path]:
    """Every source compiled to its own object; the first error (in source order) is the build's."""
    (build_dir / OBJECTS).mkdir()
    objects = [build_dir / OBJECTS / f"{i:03d}-{s.stem}.o" for i, s in enumerate(sources)]

    def compile_one(source: Path, obj: Path) -> subprocess.CompletedProcess:
        if source.suffix == CXX_SUFFIX:
            cmd = [str(compilers.cxx), *_cxx_flags(app)]
        else:
            cmd = [str(compilers.cc), *_c_flags(app)]
        cmd += [*includes, *_compile_flags(app), "-c", _shown(source, app.root), "-o", str(obj)]
        return _compile(cmd, app.root)

    with ThreadPoolExecutor(max_workers=max(2, os.cpu_count() or 1)) as pool:
        results = list(pool.map(compile_one, sources, objects))
    with open(build_dir / BUILD_LOG, "a") as log:
        for out in results:
            log.write(" ".join(out.args) + "\n" + out.stderr)
    for out in results:
        if out.returncode != 0:
            raise NativeBuildError(f"{app.sources[0].name} does not build: "
                                   f"{first_error(out.stderr, subset=_subset(app))}")
    return objects


def _subset(app: AppSources) -> str:
    """What the API the program is built against is called, in a missing function's error."""
    return "SPIKE-RT and EV3RT subsets" if app.spike else "EV3RT subset"


def _shown(source: Path, root: Path) -> str:
    """A program's source by its path in the program's folder, as its errors then name it; others whole."""
    return os.path.relpath(source, root) if source.is_relative_to(root) else str(source)


def _compile(cmd: list[str], cwd: Path) -> subprocess.CompletedProcess:
    try:
        return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=COMPILE_TIMEOUT_S,
                              env=_compiler_env())
    except (OSError, subprocess.TimeoutExpired) as e:
        raise NativeBuildError(f"the compiler failed to run: {e}") from None


def _run(cmd: list[str], cwd: Path, build_dir: Path, failure: str, entries: Collection[str] = (),
         cxx: bool = False, subset: str = "EV3RT subset") -> str:
    out = _compile(cmd, cwd)
    with open(build_dir / BUILD_LOG, "a") as log:
        log.write(" ".join(cmd) + "\n" + out.stderr)
    if out.returncode != 0:
        raise NativeBuildError(f"{failure}: {first_error(out.stderr, entries, cxx, subset)}")
    return out.stdout


def undefined_name(line: str) -> str | None:
    """The function a linker's `undefined reference to` line names."""
    missing = _UNDEFINED.search(line)
    return missing.group(1) if missing else None


def no_entry_point(name: str, cxx: bool) -> str:
    """A task or handler function app.cfg names that the program lacks, in words (the native and v850 builds)."""
    line = (f"the program defines no function {name}, a task or handler function that app.cfg names (a program "
            "without app.cfg needs main_task)")
    return line + ('; in C++ it must be extern "C", as EV3RT\'s app.h declares it' if cxx else "")


def first_error(output: str, entries: Collection[str] = (), cxx: bool = False, subset: str = "EV3RT subset") -> str:
    """The compiler's (or linker's) first error as one line. A missing function is either one of the program's
    own entry points (`entries`: the task and handler functions app.cfg names, main_task without one), which
    the program failed to define (in C++: to define as `extern "C"`, as app.h declares them), or an API
    function not in the subset. The compiler driver's closing summary ("collect2: error: ld returned 1") is
    never the first error."""
    lines = [line.strip() for line in output.splitlines() if line.strip()]
    errors = [line for line in lines if _ERROR.search(line) and not line.startswith("collect2:")]
    line = (errors or lines or ["the compiler failed"])[0]
    if "undefined reference to " in line or "multiple definition of " in line:
        line = _LINKER_LOCATION.sub("", line)
    undeclared = _UNDECLARED.search(line)
    name = undeclared["c"] or undeclared["cxx"] if undeclared else None
    if name and (header := spike.declared_in(name)):
        line += (f" ({name} is declared in {header}, which the program does not include: RasPike-ART's "
                 "spikeapi.h declares no device)")
    missing = undefined_name(line)
    if missing and missing in entries:
        line = no_entry_point(missing, cxx)
    elif missing:
        line += f" (not in the native mock's {subset}, see docs/NATIVE.md)"
    return line
