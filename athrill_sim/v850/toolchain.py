"""Where the EV3RT SDK, the v850-elf toolchain, Ruby and Athrill's guest library come from.

Each is looked for in the order a user would expect: what the command line says, then the environment, then
the copy in `../shared/third_party` beside the project's checkout (how this project's machines are laid out).
The toolchain tarball that comes with the SDK is relocatable; it is unpacked once into the cache and reused.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import tarfile
from dataclasses import dataclass
from pathlib import Path

from athrill_sim.programs.build_cache import cache_root, cached_folder
from athrill_sim.programs.third_party import ATHRILL, EV3RT_SDK, RASPIKE_SDK, V850_TOOLCHAIN
from athrill_sim.v850 import ImageError

PROJECT = Path(__file__).resolve().parents[2]
SHARED = PROJECT.parent / "shared" / "third_party"
SDK_ENV = "EV3RT_SDK"
SPIKE_SDK_ENV = "RASPIKE_SDK"
# The SDKs' own folder names, under a folder that may also hold toolchain/: TOPPERS' EV3RT, and ET Robocon's
# fork of it for the SPIKE API (third_party/raspike).
SDK_DIRS = ("ev3rt-athrill-v850e2m", "raspike-athrill-v850e2m")
GCC = "v850-elf-gcc"
TOOLCHAIN_TARBALLS = "toolchain/*.tar.gz"
ATHRILL_ENV = "ATHRILL_SRC"  # the same variable scripts/build_athrill2.sh reads
ATHRILL_TARGET = "athrill/src/athrill-target-v850e2m"
INSTALL_RUBY = "Ruby is not installed (EV3RT's cfg and tecsgen generators are Ruby): apt-get install ruby"


@dataclass(frozen=True)
class Tools:
    """What a build needs, found and checked."""

    sdk: Path  # the ev3rt-athrill-v850e2m folder (holds sdk/workspace)
    gcc: Path  # v850-elf-gcc
    athrill: Path  # Athrill's core sources (their apl/ is the guest side of its devices)


def find_sdk(given: Path | None, spike: bool = False) -> Path:
    """The SDK folder (holding sdk/workspace): --sdk, else for a SPIKE program $RASPIKE_SDK or
    ../shared/third_party/raspike (ET Robocon's raspike-athrill-v850e2m), else $EV3RT_SDK or
    ../shared/third_party/ev3rt. Either the SDK folder itself or a folder holding it (and its toolchain) may
    be named."""
    env_name, default, piece = (SPIKE_SDK_ENV, "raspike", RASPIKE_SDK) if spike else (SDK_ENV, "ev3rt", EV3RT_SDK)
    folder, origin = chosen_folder(given, env_name, SHARED / default)
    for sdk in (folder, *(folder / d for d in SDK_DIRS)):
        if (sdk / "sdk" / "workspace").is_dir() and (sdk / "sdk" / "common").is_dir():
            return sdk.resolve()
    kind = "SPIKE (RasPike-ART) SDK for Athrill" if spike else "EV3RT SDK"
    raise ImageError(f"no {kind} at {folder} ({origin}); {piece.source()}")


def chosen_folder(given: Path | None, env_name: str, default: Path) -> tuple[Path, str]:
    """The folder --sdk names, else $`env_name`, else `default` (under ../shared/third_party), and how it was
    chosen, for an error that names it."""
    env = os.environ.get(env_name)
    if given is not None:
        return given, "--sdk"
    if env:
        return Path(env), f"${env_name}"
    return default, f"the default, ../shared/third_party/{default.relative_to(SHARED)}"


def find_toolchain(given: Path | None, sdk: Path) -> Path:
    """v850-elf-gcc: in --toolchain DIR (or DIR/bin), else on PATH, else from the tarball beside the SDK,
    unpacked once into the cache."""
    if given is not None:
        for d in (given, given / "bin"):
            if (d / GCC).is_file() and os.access(d / GCC, os.X_OK):
                return (d / GCC).resolve()
        raise ImageError(f"--toolchain {given}: no {GCC} in it or in its bin/")
    if found := shutil.which(GCC):
        return Path(found)
    # beside the SDK, else EV3RT's: ET Robocon's SPIKE SDK comes without one, and builds with the same
    tarballs = sorted(sdk.parent.glob(TOOLCHAIN_TARBALLS)) or sorted((SHARED / "ev3rt").glob(TOOLCHAIN_TARBALLS))
    if not tarballs:
        raise ImageError(f"no v850 cross compiler: put {GCC} on PATH, pass --toolchain DIR, or place the "
                         f"toolchain tarball in {sdk.parent / 'toolchain'}; {V850_TOOLCHAIN.source()}")
    return unpack_toolchain(tarballs[-1])


def unpack_toolchain(tarball: Path) -> Path:
    """The tarball's v850-elf-gcc, unpacked into the cache under the tarball's hash (once; a concurrent
    unpack of the same tarball leaves the same tree)."""
    digest = hashlib.sha256(tarball.read_bytes()).hexdigest()[:16]

    def gcc(folder: Path) -> Path | None:
        return next(iter(sorted(folder.glob(f"*/bin/{GCC}"))), None)

    def unpack(scratch: Path) -> None:
        with tarfile.open(tarball) as tar:
            tar.extractall(scratch, filter="tar")

    try:
        found = cached_folder(cache_root() / "toolchain" / digest, gcc, unpack)
    except tarfile.ReadError:  # its message lists every compression tried, one line each
        raise ImageError(f"the toolchain {tarball} is not a tar archive (plain, gz, bz2 or xz)") from None
    except (OSError, tarfile.TarError) as e:
        raise ImageError(f"cannot unpack the toolchain {tarball}: {e}") from None
    if found is None:
        raise ImageError(f"the toolchain tarball {tarball} holds no bin/{GCC}")
    return found


def find_athrill() -> Path:
    """Athrill's core sources (`athrill/apl` is compiled into every image): $ATHRILL_SRC's, else
    ../shared/third_party/athrill's."""
    target = Path(os.environ.get(ATHRILL_ENV) or SHARED / ATHRILL_TARGET)
    core = target / "athrill"
    if not (core / "apl" / "include").is_dir():
        raise ImageError(f"no Athrill sources at {target} (their athrill/apl is linked into every image); "
                         f"{ATHRILL.source()}")
    return core.resolve()


def find_tools(sdk: Path | None = None, toolchain: Path | None = None, spike: bool = False) -> Tools:
    found = find_sdk(sdk, spike)
    return Tools(found, find_toolchain(toolchain, found), find_athrill())


def check_build_tools() -> None:
    """What only a build needs (a cached image needs neither)."""
    if shutil.which("ruby") is None:
        raise ImageError(INSTALL_RUBY)
    if shutil.which("make") is None:
        raise ImageError("make is not installed (EV3RT's SDK builds with GNU make): apt-get install make")
