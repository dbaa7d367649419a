"""`hako build`: a user's EV3RT program into a v850 image, by the SDK's own make, cached.

The SDK's build writes into its own tree (the workspace, `OBJ/`, the cfg pass's output), so it runs in a
scratch copy of the SDK beside the cache entry, with the program copied in as the workspace folder `hako_app`
and `../../../athrill` linked to Athrill's sources (EV3RT's Makefile.img takes the guest half of Athrill's
devices from there). No source tree is written. The image is cached as the native build's binary is
(`athrill_sim.programs.build_cache`).

The cache key mirrors the native build's (`athrill_sim.native.build`): the program's files by their paths
relative to its folder, every file of the SDK and of Athrill's guest library, this module, the make command
and the compiler's identity (its path and `--version`). Only the program's source files are copied in
(`SOURCE_SUFFIXES`, `Makefile.inc`), so what the key covers is exactly what the build can read of it.

A folder or `.c` file without `app.cfg` is a program whose `main_task` is its one task, as for the native
build: `app.cfg`, `app.h` (unless it has one) and an empty `Makefile.inc` are written for it (a lone `.cpp`
gets the C++ language and `libcpp-ev3`, as natively). A workspace folder without `Makefile.inc` gets an empty
one, as the native build reads it (`athrill_sim.native.workspace.program_makefile`).

C++ programs (`SRCLANG := c++`, whose main file is `app.cpp`) build with the SDK's own C++ path. EV3RT runs
their static constructors itself (`_app_init_task`, before the program's tasks: `sdk/common/ev3api/src/ev3api.c`),
so nothing is added to them. athrill2 asserts while reading C++ DWARF (`elf_dwarf_build_struct_member`), so
the image is `--strip-debug`ed; the unstripped image stays beside it as `asp.debug`.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from athrill_sim.native import NativeBuildError, spike
from athrill_sim.native.build import no_entry_point, undefined_name
from athrill_sim.native.headers import LAYOUT_HEADER
from athrill_sim.native.makefile import ETROBO_VARIABLES, ETROBOC_COMMON, NO_MAKEFILE
from athrill_sim.native.workspace import LONE_CXX_MAKEFILE_INC, MAKEFILE_INC, program_makefile
from athrill_sim.programs.build_cache import CacheKey, cache_root, cached_build
from athrill_sim.tuning.elf_symbols import DEBUG_SUFFIX
from athrill_sim.v850 import ImageError
from athrill_sim.v850.toolchain import Tools, check_build_tools, find_tools
from hakoniwa.wire.protocol import c_header

APP_NAME = "hako_app"  # the workspace folder the program is built as (no SDK sample has this name)
IMAGE = "asp"
DEBUG_IMAGE = IMAGE + DEBUG_SUFFIX  # the image before --strip-debug: for a debugger, and a global's type
ETROBO_FOLDER = "etrobo"
ETROBOC_EXT = ETROBOC_COMMON / "etroboc_ext.h"
BUILD_LOG = "build.log"
MAKE = ("make", f"img={APP_NAME}")
BUILD_TIMEOUT_S = 600
SOURCE_SUFFIXES = (".c", ".h", ".cfg", ".inc", ".cdl", ".S", ".s", ".cpp", ".hpp")
LONE_APP_CFG = """INCLUDE("app_common.cfg");
INCLUDE("tecsgen.cfg");

#include "app.h"
#include "ev3.h"

CRE_TSK(MAIN_TASK, { TA_ACT, 0, main_task, TMIN_APP_TPRI + 1, STACK_SIZE, NULL });
"""
LONE_APP_H = """#include "target_test.h"
#ifndef STACK_SIZE
#define STACK_SIZE 4096
#endif
#ifndef TOPPERS_MACRO_ONLY
extern void main_task(intptr_t exinf);
#endif
"""

_ERROR = re.compile(r"\berror: |undefined reference to |multiple definition of |No rule to make|\b[A-Z]\w*Error\b")
_MAKE_SUMMARY = re.compile(r"^make(\[\d+\])?: \*\*\* .*Error \d+")
_NO_RULE = re.compile(r"No rule to make target [`'\u2018](?P<target>[^'\u2019]+)['\u2019]"
                      r"(?:, needed by [`'\u2018](?P<by>[^'\u2019]+)['\u2019])?")
_STAGED_PATH = re.compile(r"(?:[^\s:'\"`\u2018\u2019]*/)?" + APP_NAME + r"/([^\s:'\"`\u2018\u2019]+)")
KERNEL_CFG = "kernel_cfg.o"  # what the SDK's cfg pass makes of app.cfg: what it references are app.cfg's entries


def build_image(app: Path, *, sdk: Path | None = None, toolchain: Path | None = None,
                announce: Callable[[str], None] | None = None, flags: tuple[str, ...] = ()) -> Path:
    """The v850 image of the program at `app` (an app.c or a workspace folder), built now unless cached;
    `announce` hears what is being built before a build starts (it takes seconds). `flags` are extra
    compiler flags for the program (a tuned program's -DNAME=value, athrill_sim.tuning), added to its
    Makefile.inc's COPTS in the scratch copy."""
    root, files, lone = app_files(Path(app))
    traits = source_traits(root, files, lone)
    tools = find_tools(sdk, toolchain, spike=traits.spike)
    entry = cache_root() / "v850" / cache_key(root, files, lone, tools, flags)
    if (entry / IMAGE).is_file():
        return entry / IMAGE
    check_build_tools()
    if announce is not None:
        announce(f"building {root} with the {'SPIKE' if traits.spike else 'EV3RT'} SDK at {tools.sdk} and {tools.gcc}")
    return cached_build(entry, IMAGE, lambda scratch: _build(root, files, lone, tools, scratch, traits.cxx, flags))


def app_files(app: Path) -> tuple[Path, list[Path], bool]:
    """The program's folder, its source files, and whether it is a lone .c or .cpp file (the first of the
    files, built as app.c or app.cpp beside the headers of its folder)."""
    app = app.resolve()
    if app.is_file() and app.suffix not in (".c", ".cpp"):
        raise ImageError(f"{app}: not a C or C++ source file (.c, .cpp) or an EV3RT workspace folder")
    root = app.parent if app.is_file() else app
    if not (root / "app.cfg").is_file():
        source = app if app.is_file() else root / "app.c"
        if not source.is_file():
            raise ImageError(f"{root}: no app.c; an EV3RT workspace folder holds app.c, app.h, app.cfg and "
                             "Makefile.inc")
        return root, [source, *sorted(root.glob("*.h"))], True
    if not any((root / main).is_file() for main in ("app.c", "app.cpp")):
        raise ImageError(f"{root}: no app.c or app.cpp; an EV3RT workspace folder holds app.c (app.cpp in C++), "
                         "app.h, app.cfg and Makefile.inc")
    files = sorted(f for f in root.rglob("*")
                   if f.is_file() and (f.suffix in SOURCE_SUFFIXES or f.name == MAKEFILE_INC))
    return root, files, False


@dataclass(frozen=True)
class SourceTraits:
    cxx: bool  # EV3RT builds it as C++: `SRCLANG := c++` (its main file app.cpp), or a lone .cpp file
    spike: bool  # written against the SPIKE API: built with ET Robocon's SPIKE SDK unless --sdk says otherwise


def source_traits(root: Path, files: list[Path], lone: bool) -> SourceTraits:
    """What the program's Makefile.inc (read by GNU make, as the SDK reads it) and sources say it is: the
    same rules as the native build's (`athrill_sim.native.spike`)."""
    if lone:
        return SourceTraits(files[0].suffix == ".cpp", spike.is_spike_program(NO_MAKEFILE, files))
    try:
        make = program_makefile(root)
    except NativeBuildError as e:
        raise ImageError(str(e)) from None
    is_spike = spike.is_spike_program(make, files)
    return SourceTraits(make.words("SRCLANG") == ["c++"], is_spike)


def cache_key(root: Path, files: list[Path], lone: bool, tools: Tools, flags: tuple[str, ...] = ()) -> str:
    key = CacheKey()
    add = key.add
    if flags:
        add("flags", "\0".join(flags).encode())
    version = _run([str(tools.gcc), "--version"], root, "cannot run " + str(tools.gcc))
    add("compiler", f"{tools.gcc}\n{version}".encode())
    add("make", "\0".join(MAKE).encode())
    add("builder", Path(__file__).read_bytes())
    add("lone", b"1" if lone else b"0")
    for tree, label in ((tools.sdk, "sdk"), (tools.athrill / "apl", "apl")):
        for f in sorted(p for p in tree.rglob("*") if p.is_file()):
            add(f"{label}/{f.relative_to(tree)}", f.read_bytes())
    for f in files:
        add(f"app/{f.relative_to(root)}", f.read_bytes())
    add("etrobo", repr({name: os.environ.get(name) for name in ETROBO_VARIABLES}).encode())
    for name, text in sorted(etroboc_files().items()):
        add(f"etroboc_common/{name}", text.encode())
    return key.name()


def _build(root: Path, files: list[Path], lone: bool, tools: Tools, scratch: Path, cxx: bool,
           flags: tuple[str, ...]) -> None:
    _make_image(root, files, lone, tools, scratch, flags, cxx)
    if cxx:
        shutil.copyfile(scratch / IMAGE, scratch / DEBUG_IMAGE)
        strip = tools.gcc.with_name(tools.gcc.name.replace("gcc", "strip"))
        try:
            subprocess.run([str(strip), "--strip-debug", str(scratch / IMAGE)], check=True, capture_output=True,
                           timeout=60)
        except (OSError, subprocess.SubprocessError) as e:
            raise ImageError(f"{root}: cannot strip the C++ debug information athrill2 cannot read: {e}") from None


def _make_image(root: Path, files: list[Path], lone: bool, tools: Tools, scratch: Path,
                flags: tuple[str, ...], cxx: bool) -> None:
    sdk = writable_copy(tools.sdk, scratch)
    (scratch / "athrill").symlink_to(tools.athrill)
    workspace = sdk / "sdk" / "workspace"
    staged = workspace / APP_NAME
    shutil.rmtree(staged, ignore_errors=True)
    if lone:
        staged.mkdir()
        shutil.copyfile(files[0], staged / f"app{files[0].suffix}")
        for h in files[1:]:
            shutil.copyfile(h, staged / h.name)
        (staged / "app.cfg").write_text(LONE_APP_CFG)
        if not (staged / "app.h").exists():
            (staged / "app.h").write_text(LONE_APP_H)
        (staged / MAKEFILE_INC).write_text(LONE_CXX_MAKEFILE_INC if files[0].suffix == ".cpp" else "")
    else:
        for f in files:
            target = staged / f.relative_to(root)
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(f, target)
        if not (staged / MAKEFILE_INC).is_file():  # the SDK includes it: empty, as program_makefile reads none
            (staged / MAKEFILE_INC).write_text("")
    if flags:
        with open(staged / MAKEFILE_INC, "a") as inc:
            inc.write("\nCOPTS += " + " ".join(shlex.quote(f).replace("$", "$$") for f in flags) + "\n")
    run_make(MAKE, workspace, tools.gcc.parent, _etrobo_env(scratch), scratch / BUILD_LOG, IMAGE,
             root, staged_sources(root, files, lone), cxx)
    (workspace / IMAGE).rename(scratch / IMAGE)
    shutil.rmtree(sdk)
    shutil.rmtree(scratch / ETROBO_FOLDER)
    (scratch / "athrill").unlink()


def run_make(make: tuple[str, ...], workspace: Path, tools: Path, env: dict[str, str], log: Path, product: str,
             root: Path, sources: dict[str, Path], cxx: bool = False) -> None:
    """The SDK's make in its workspace folder, with the folder `tools` first on PATH and `env` added, its
    output kept in `log`; a build that fails or leaves no `product` there is said as its first error, with
    the user's own file for each staged one (`sources`)."""
    env = {**os.environ, "LC_ALL": "C.UTF-8", "PWD": str(workspace),  # Ruby reads the SDK's UTF-8; make $(PWD)
           "PATH": f"{tools}{os.pathsep}{os.environ.get('PATH', '')}", **env}
    try:
        out = subprocess.run(make, cwd=workspace, capture_output=True, text=True, timeout=BUILD_TIMEOUT_S, env=env)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise ImageError(f"{root}: make failed to run: {e}") from None
    log.write_text(out.stdout + out.stderr)
    if out.returncode != 0 or not (workspace / product).is_file():
        message = first_error(out.stdout + "\n" + out.stderr, cxx)
        raise ImageError(f"{root} does not build: {user_paths(message, sources)}")


def writable_copy(tree: Path, into: Path) -> Path:
    """A copy of `tree` in the folder `into`, writable: a build in it writes beside its sources, and a
    read-only source tree (../shared) copies read-only."""
    copy = into / tree.name
    shutil.copytree(tree, copy, symlinks=True)
    for d, _, names in os.walk(copy):
        os.chmod(d, 0o755)
        for n in names:
            p = Path(d) / n
            if not p.is_symlink():
                os.chmod(p, 0o644 | (p.stat().st_mode & 0o111))
    return copy


def _etrobo_env(scratch: Path) -> dict[str, str]:
    """ET Robocon's variables the user has not set, naming a folder whose `etroboc_common/` holds the bench's
    `etroboc_ext.h` (and the layout header it reads), as the native build's do: ET Robocon's samples say
    `-I$(ETROBO_HRP3_WORKSPACE)/etroboc_common`."""
    common = scratch / ETROBO_FOLDER / "etroboc_common"
    common.mkdir(parents=True)
    for name, text in etroboc_files().items():
        (common / name).write_text(text)
    return {name: str(common.parent) for name in ETROBO_VARIABLES if not os.environ.get(name)}


def etroboc_files() -> dict[str, str]:
    return {ETROBOC_EXT.name: ETROBOC_EXT.read_text(), LAYOUT_HEADER: c_header()}


def first_error(output: str, cxx: bool = False) -> str:
    """The build's first error as one line; make's own closing lines ("*** [...] Error 1") are never it, and
    its "No rule to make target" is said as the file that is missing. A function the cfg pass's kernel_cfg.o
    cannot find is a task app.cfg names: said as the native build says it."""
    lines = [line.strip() for line in output.splitlines() if line.strip()]
    errors = [line for line in lines if _ERROR.search(line) and not _MAKE_SUMMARY.match(line)
              and not line.startswith("collect2:")]
    line = (errors or [line for line in lines if not _MAKE_SUMMARY.match(line)] or ["the build failed"])[0]
    if no_rule := _NO_RULE.search(line):  # make's own words name no cause a user knows: say it as a missing file
        needed = f", which {no_rule['by']} needs" if no_rule["by"] else ""
        return f"no file {no_rule['target']}{needed}, and the SDK's make has no rule to make it"
    missing = undefined_name(line)
    return no_entry_point(missing, cxx) if missing and KERNEL_CFG in line else line


def staged_sources(root: Path, files: list[Path], lone: bool) -> dict[str, Path]:
    """The user's file behind each path in the staged workspace folder (a lone file is staged as app.c)."""
    if lone:
        return {f"app{files[0].suffix}": files[0], **{h.name: h for h in files[1:]}}
    return {f.relative_to(root).as_posix(): f for f in files}


def user_paths(message: str, sources: dict[str, Path]) -> str:
    """The message with each path into the scratch copy's workspace folder (`../workspace/hako_app/app.c`)
    replaced by the user's file it was copied from, so an editor can jump to it; a file the build wrote (a lone
    file's app.cfg) keeps its name."""
    return _STAGED_PATH.sub(lambda m: str(sources.get(m.group(1), m.group(1))), message)


def _run(cmd: list[str], cwd: Path, failure: str) -> str:
    try:
        return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=60,
                              env={**os.environ, "LC_ALL": "C"}).stdout
    except (OSError, subprocess.TimeoutExpired) as e:
        raise ImageError(f"{failure}: {e}") from None
