"""`hako build --raspike-art`: a team's RasPike-ART workspace folder into `asp`, by RasPike-ART's own make,
cached.

RasPike-ART's make writes into its own tree (the workspace's `asp`, `sdk/OBJ/`, `sdk/common/library/
libkernel.a`, `libraspike-art/lib/`), so it runs in a scratch copy of the RasPike-ART folder beside the cache
entry, with the team's folder copied in as the workspace folder `hako_app`, exactly as the team runs
`make img=NAME` in `sdk/workspace`. Neither the team's folder nor the RasPike-ART folder is written.

Two things of the build are not the team's, and both are done to the scratch copy only:
- `configure.rb` requires Ruby's `shell` library, which Ruby 3 no longer has: the same two-line change that
  scripts/ev3rt-patches/raspike-gcc12-ruby3.diff makes to ET Robocon's other tree (`RUBY3_FIX`);
- libraspike-art's `build/Makefile.common` calls `gcc` by name, so a folder whose `gcc` is the aarch64 cross
  compiler comes first on PATH (the kernel and the app take `GCC_TARGET`, as RasPike-ART's make offers).

A tuned program's -D definitions (`define` parameters) come in as COPTS from the environment, each value a
build of its own in the cache. The product is the aarch64 `asp` and, beside it, the `libssetjmp.so` that
RasPike-ART's `make start` preloads (`sdk/common/setjmp/aarch64`) and the device config it passes (`sdk/common/
device_config_raspike-art.txt`): what a run needs (`launch.py`). The cache key is the team's source files by
their paths in its folder, every file of the RasPike-ART folder, this module, the make command and the cross
compiler's identity.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from athrill_sim.native.workspace import MAKEFILE_INC
from athrill_sim.programs.build_cache import CacheKey, cache_root, cached_build
from athrill_sim.programs.third_party import RASPIKE_ART
from athrill_sim.raspike_art import AspError
from athrill_sim.v850.build import (
    APP_NAME,
    BUILD_LOG,
    SOURCE_SUFFIXES,
    run_make,
    staged_sources,
    writable_copy,
)
from athrill_sim.v850.toolchain import INSTALL_RUBY, SHARED, chosen_folder
from hakoniwa.wire.protocol import RASPIKE_VERSION

RASPIKE_ART_ENV = "RASPIKE_ART"
DEFAULT_FOLDER = SHARED / "raspike-art" / "RasPike-ART"
TARGET = "aarch64-linux-gnu"  # Debian's cross toolchain's prefix, and RasPike-ART's GCC_TARGET for it
CROSS_GCC = f"{TARGET}-gcc"
CROSS_TOOLS = (CROSS_GCC, f"{TARGET}-g++")
INSTALL_CROSS = ("no aarch64 cross compiler (RasPike-ART's asp is built for aarch64 and runs under qemu-user): "
                 "apt-get install gcc-aarch64-linux-gnu g++-aarch64-linux-gnu qemu-user (Debian's packages)")
MAKE = ("make", f"img={APP_NAME}", f"GCC_TARGET={TARGET}")
EXPECTED_VERSION = Path("libraspike-art/src/expected_spike_version")  # the hub protocol its asp checks for
ASP = "asp"
SETJMP = Path("sdk/common/setjmp/aarch64/libssetjmp.so")  # what RasPike-ART's `make start` preloads
DEVICE_CONFIG = Path("sdk/common/device_config_raspike-art.txt")  # what `make start` passes with -d
# configure.rb's use of Ruby's removed `shell` library, and what replaces it (scripts/ev3rt-patches/
# raspike-gcc12-ruby3.diff makes the same change to ET Robocon's other tree).
RUBY3_FIX = (('require "shell"', '# require "shell"  # removed in Ruby 3'), ("Shell.new.cwd", "Dir.pwd"))
# What marks a RasPike-ART folder: its workspace, its make, and the libraspike-art submodule checked out.
MARKS = ("sdk/workspace/Makefile", "sdk/common/Makefile.workspace", "configure.rb",
         "libraspike-art/build/obj-libraspike-art/Makefile", str(SETJMP), str(DEVICE_CONFIG))


@dataclass(frozen=True)
class Tools:
    """What a build needs, found and checked."""

    raspike_art: Path  # the RasPike-ART folder (holds sdk/workspace and libraspike-art)
    gcc: Path  # aarch64-linux-gnu-gcc


def find_raspike_art(given: Path | None) -> Path:
    """The RasPike-ART folder: --sdk, else $RASPIKE_ART, else ../shared/third_party/raspike-art/RasPike-ART;
    one whose libraspike-art expects another version of the hub than the bench plays is refused in one line
    (its asp would print "SPIKE version mismatched" and stop at the handshake of every test)."""
    folder, origin = chosen_folder(given, RASPIKE_ART_ENV, DEFAULT_FOLDER)
    if not all((folder / mark).exists() for mark in MARKS):
        raise AspError(f"no RasPike-ART at {folder} ({origin}); {RASPIKE_ART.source()}")
    expected = folder / EXPECTED_VERSION
    if expected.is_file():  # older libraspike-art has none, and no check at the handshake either
        wanted = expected.read_text(encoding="utf-8", errors="replace").strip()
        plays = ".".join(map(str, RASPIKE_VERSION))
        if wanted != plays:
            raise AspError(f"RasPike-ART at {folder}: its libraspike-art expects the hub's protocol {wanted} "
                           f"({EXPECTED_VERSION}); the bench's hub speaks {plays} (libraspike-art 28f3f38, the 2025 "
                           "season's): build with a RasPike-ART of that libraspike-art")
    return folder.resolve()


def find_tools(given: Path | None) -> Tools:
    """RasPike-ART and the aarch64 cross compilers, Ruby (ASP3's configure.rb and cfg) and make; the first
    missing is said in one line, with what to install."""
    raspike_art = find_raspike_art(given)
    if not all(shutil.which(tool) for tool in CROSS_TOOLS):
        raise AspError(INSTALL_CROSS)
    if not shutil.which("ruby"):
        raise AspError(INSTALL_RUBY.replace("EV3RT's cfg and tecsgen generators", "ASP3's configure.rb and cfg"))
    if not shutil.which("make"):
        raise AspError("make is not installed (RasPike-ART builds with GNU make): apt-get install make")
    return Tools(raspike_art, Path(str(shutil.which(CROSS_GCC))))


def app_files(app: Path) -> tuple[Path, list[Path]]:
    """The team's workspace folder (as `make img=NAME` takes it: app.c or app.cpp, app.cfg, Makefile.inc) and
    its source files."""
    root = app.resolve()
    if not root.is_dir():
        raise AspError(f"{app}: not a folder; RasPike-ART builds a workspace folder (app.c, app.h, app.cfg, "
                       "Makefile.inc), as `make img=NAME` in its sdk/workspace does")
    missing = [name for name in ("app.cfg", MAKEFILE_INC) if not (root / name).is_file()]
    if not any((root / main).is_file() for main in ("app.c", "app.cpp")):
        missing.insert(0, "app.c")
    if missing:
        raise AspError(f"{root}: no {' or '.join(missing)}; a RasPike-ART workspace folder holds app.c (app.cpp "
                       "in C++), app.h, app.cfg and Makefile.inc")
    files = sorted(f for f in root.rglob("*")
                   if f.is_file() and (f.suffix in SOURCE_SUFFIXES or f.name == MAKEFILE_INC))
    return root, files


def build_asp(app: Path, *, sdk: Path | None = None, announce: Callable[[str], None] | None = None,
              flags: tuple[str, ...] = ()) -> Path:
    """The aarch64 `asp` of the team's workspace folder `app`, built now unless cached (`libssetjmp.so`
    beside it), with the extra compiler `flags` (a tuned program's -D definitions); `announce` hears what is
    being built before a build starts (it takes half a minute)."""
    root, files = app_files(Path(app))
    tools = find_tools(sdk)
    entry = cache_root() / "raspike-art" / cache_key(root, files, tools, flags)
    if (entry / ASP).is_file():
        return entry / ASP
    if announce is not None:
        announce(f"building {root} with RasPike-ART at {tools.raspike_art} and {tools.gcc}")
    return cached_build(entry, ASP, lambda scratch: _build(root, files, tools, scratch, flags))


def cache_key(root: Path, files: list[Path], tools: Tools, flags: tuple[str, ...] = ()) -> str:
    key = CacheKey()
    add = key.add
    if flags:
        add("flags", "\0".join(flags).encode())
    try:
        version = subprocess.run([str(tools.gcc), "--version"], capture_output=True, text=True, timeout=60,
                                 env={**os.environ, "LC_ALL": "C"}).stdout
    except (OSError, subprocess.TimeoutExpired) as e:
        raise AspError(f"cannot run {tools.gcc}: {e}") from None
    add("compiler", f"{tools.gcc}\n{version}".encode())
    add("make", "\0".join(MAKE).encode())
    add("builder", Path(__file__).read_bytes())
    for f in sorted(p for p in tools.raspike_art.rglob("*") if p.is_file()):
        add(f"raspike-art/{f.relative_to(tools.raspike_art)}", f.read_bytes())
    for f in files:
        add(f"app/{f.relative_to(root)}", f.read_bytes())
    return key.name()


def _build(root: Path, files: list[Path], tools: Tools, scratch: Path, flags: tuple[str, ...]) -> None:
    tree = writable_copy(tools.raspike_art, scratch)
    configure = tree / "configure.rb"
    text = configure.read_text(encoding="utf-8")
    for old, new in RUBY3_FIX:
        text = text.replace(old, new)
    configure.write_text(text, encoding="utf-8")
    workspace = tree / "sdk" / "workspace"
    staged = workspace / APP_NAME
    for f in files:
        target = staged / f.relative_to(root)
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(f, target)
    shims = scratch / "bin"  # libraspike-art's Makefile.common says `gcc`
    shims.mkdir()
    (shims / "gcc").symlink_to(tools.gcc)
    # COPTS from the environment is where RasPike-ART's Makefile.img starts its own (`COPTS := -g @(COPTS)
    # $(COPTS)`), and reaches the C and the C++ compiles alike; on make's command line it would replace them.
    # SOURCE_DATE_EPOCH makes ASP3's banner (__DATE__, __TIME__) the same in every build, so that two builds of
    # the same sources are the same program (a `define` that changes nothing is then seen to).
    extra = {"SOURCE_DATE_EPOCH": "0", **({"COPTS": " ".join(flags)} if flags else {})}
    run_make(MAKE, workspace, shims, extra, scratch / BUILD_LOG, ASP, root, staged_sources(root, files, False))
    (workspace / ASP).rename(scratch / ASP)
    for beside in (SETJMP, DEVICE_CONFIG):
        shutil.copyfile(tree / beside, scratch / beside.name)
    shutil.rmtree(tree)
    shutil.rmtree(shims)
