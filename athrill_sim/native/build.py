"""Building a user's EV3RT C program into a native Athrill, once per campaign and cached.

The cache key is a hash of everything that goes into the binary: the program's files (`AppSources.hashed`, by
their paths relative to the program's folder, so a copy elsewhere is the same program), the runtime's sources
and headers, the generated headers, the generator's own code, the flags, and the compiler's identity (its path
and `--version`). A build happens in a scratch folder beside the cache entry and is renamed into place when it
is whole, so two benches building the same program at once both end up with a good binary. Entries live in
`${XDG_CACHE_HOME:-~/.cache}/hakoniwa-py/native/<key>/`, with the compiler's output in `build.log`.

The flags keep float arithmetic strict, so that a program computes what its C says, operation by operation:
`-ffp-contract=off` (no fused multiply-add) and no fast-math. `-fno-strict-aliasing`, because embedded code
type-puns freely; integer-to-pointer casts are not warned about, because EV3RT programs use guest addresses.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from collections.abc import Collection
from pathlib import Path

from athrill_sim.build_cache import CacheKey, cache_root, cached_build
from athrill_sim.native import NativeBuildError, appcfg, headers, spike, workspace
from athrill_sim.native.appcfg import KERNEL_CFG_C, KERNEL_CFG_H, kernel_config
from athrill_sim.native.workspace import AppSources, find_app

RUNTIME = Path(__file__).with_name("runtime")
RUNTIME_INCLUDE = RUNTIME / "include"
RUNTIME_SRC = RUNTIME / "src"
GENERATORS = (Path(__file__), Path(appcfg.__file__), Path(headers.__file__), Path(workspace.__file__),
              Path(spike.__file__))
CFLAGS = ("-std=gnu11", "-O2", "-ffp-contract=off", "-fno-fast-math", "-fno-strict-aliasing", "-Wall",
          "-Wno-int-to-pointer-cast")
LIBS = ("-lm",)
EXECUTABLE = "athrill-native"
BUILD_LOG = "build.log"
COMPILE_TIMEOUT_S = 300

_ERROR = re.compile(r"\berror: |undefined reference to |multiple definition of ")
_LINKER_LOCATION = re.compile(r"^.*?:\(\.\w+[^)]*\): ")
_UNDEFINED = re.compile(r"undefined reference to [`'\u2018]([A-Za-z_]\w*)['\u2019]")


def find_compiler() -> Path:
    """The system C compiler: $CC, else cc, else gcc."""
    for name in (os.environ.get("CC"), "cc", "gcc"):
        if name and (found := shutil.which(name)):
            return Path(found)
    raise NativeBuildError("no C compiler (cc or gcc) on PATH to build a native app; install one or set CC")


def build_app(path: Path) -> Path:
    """The native Athrill for the program at `path`, built now unless the cache holds it."""
    app = find_app(path)
    cc = find_compiler()
    generated = headers.generated_headers()
    return cached_build(cache_root() / "native" / cache_key(app, cc, generated), EXECUTABLE,
                        lambda scratch: _build(app, cc, generated, scratch))


def cache_key(app: AppSources, cc: Path, generated: dict[str, str]) -> str:
    key = CacheKey()
    add = key.add

    def rel(path: Path | None) -> str:
        return os.path.relpath(path, app.root) if path else ""

    add("compiler", f"{cc}\n{_compiler_identity(cc)}".encode())
    add("flags", "\0".join((*CFLAGS, *LIBS, *app.defines)).encode())
    add("layout", repr(([rel(s) for s in app.sources], rel(app.cfg), [rel(d) for d in app.include_dirs])).encode())
    for f in (*sorted(RUNTIME.rglob("*.[ch]")), *GENERATORS):
        add(os.path.relpath(f, RUNTIME.parent), f.read_bytes())
    for f in app.hashed:
        add(rel(f), f.read_bytes())
    for name, text in sorted(generated.items()):
        add(name, text.encode())
    return key.name()


def _compiler_identity(cc: Path) -> str:
    try:
        out = subprocess.run([str(cc), "--version"], capture_output=True, text=True, timeout=60, env=_compiler_env())
    except OSError as e:
        raise NativeBuildError(f"cannot run the C compiler {cc}: {e.strerror}") from None
    return out.stdout


def _compiler_env() -> dict[str, str]:
    return {**os.environ, "LC_ALL": "C"}  # plain ASCII messages, whatever the user's locale


def _include_flags(app: AppSources, build_dir: Path) -> list[str]:
    """Ours first: a stray kernel_cfg.h from a real EV3RT build in the program's folder must not win."""
    ours = (RUNTIME_INCLUDE, *(spike.INCLUDE_DIRS if app.spike else ()))
    return [f"-I{d}" for d in (build_dir, *ours, app.root, *app.include_dirs)]


def _build(app: AppSources, cc: Path, generated: dict[str, str], build_dir: Path) -> None:
    for name, text in generated.items():
        (build_dir / name).write_text(text)
    includes = _include_flags(app, build_dir)

    def preprocess(cfg: Path) -> str:
        cmd = [str(cc), "-E", "-P", "-x", "c", "-DTOPPERS_MACRO_ONLY", *includes, *app.defines, str(cfg)]
        return _run(cmd, app.root, build_dir, f"{cfg.name} does not preprocess")

    config = kernel_config(app.cfg, preprocess)
    (build_dir / KERNEL_CFG_H).write_text(config.header())
    (build_dir / KERNEL_CFG_C).write_text(config.source())
    sources = [os.path.relpath(s, app.root) for s in app.sources]
    runtime = [*sorted(RUNTIME_SRC.glob("*.c")), *(spike.sources() if app.spike else ())]
    cmd = [str(cc), *CFLAGS, *includes, *app.defines, *sources, str(build_dir / KERNEL_CFG_C),
           *(str(s) for s in runtime), "-o", str(build_dir / EXECUTABLE), *LIBS]
    entries = {t.entry for t in config.tasks} | {c.handler for c in config.cyclics if c.handler}
    _run(cmd, app.root, build_dir, f"{app.sources[0].name} does not build", entries,
         "SPIKE-RT and EV3RT subsets" if app.spike else "EV3RT subset")


def _run(cmd: list[str], cwd: Path, build_dir: Path, failure: str, entries: Collection[str] = (),
         subset: str = "EV3RT subset") -> str:
    try:
        out = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=COMPILE_TIMEOUT_S,
                             env=_compiler_env())
    except (OSError, subprocess.TimeoutExpired) as e:
        raise NativeBuildError(f"{failure}: the compiler failed to run: {e}") from None
    with open(build_dir / BUILD_LOG, "a") as log:
        log.write(" ".join(cmd) + "\n" + out.stderr)
    if out.returncode != 0:
        raise NativeBuildError(f"{failure}: {first_error(out.stderr, entries, subset)}")
    return out.stdout


def first_error(output: str, entries: Collection[str] = (), subset: str = "EV3RT subset") -> str:
    """The compiler's (or linker's) first error as one line. A missing function is either one of the program's
    own entry points (`entries`: the task and handler functions app.cfg names, main_task without one), which
    the program failed to define, or an API function not in the subset. The compiler driver's closing summary
    ("collect2: error: ld returned 1") is never the first error."""
    lines = [line.strip() for line in output.splitlines() if line.strip()]
    errors = [line for line in lines if _ERROR.search(line) and not line.startswith("collect2:")]
    line = (errors or lines or ["the compiler failed"])[0]
    if "undefined reference to " in line or "multiple definition of " in line:
        line = _LINKER_LOCATION.sub("", line)
    missing = _UNDEFINED.search(line)
    if missing and missing.group(1) in entries:
        line = (f"the program defines no function {missing.group(1)}, a task or handler function that app.cfg "
                "names (a program without app.cfg needs main_task)")
    elif missing:
        line += f" (not in the native mock's {subset}, see docs/NATIVE.md)"
    return line
