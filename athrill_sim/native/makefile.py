"""A program's `Makefile.inc`, evaluated by GNU make itself, as EV3RT's build evaluates it.

Teams' `Makefile.inc` files are real GNU make: `$(shell ls ...)`, `include` of the SDK's library Makefiles,
`ifeq`, `$(abspath $(lastword $(MAKEFILE_LIST)))`, variables from the environment. Only make reads them right,
so the bench hands the file to make in the context EV3RT's `Makefile.img` gives it (`SRCLANG := c`,
`CONFIG_EV3RT_APPLICATION = 1`, `EV3RT_SDK_LIB_DIR`, the file included by its absolute path so that
`MAKEFILE_LIST` names it), and reads back the variables that say what to build. Nothing is built by make.

- `EV3RT_SDK_LIB_DIR` is the bench's copy of EV3RT's libraries (`athrill_sim/native/sdk/library`), whose
  `../Makefile.slib` records each library a program includes instead of making its archive.
- ET Robocon's environment variables (`ETROBO_ROOT`, `ETROBO_HRP3_WORKSPACE`, ...) are the user's where set,
  and otherwise name a folder whose `etroboc_common/` holds the bench's `etroboc_ext.h`, so ET Robocon's
  samples (`-I$(ETROBO_HRP3_WORKSPACE)/etroboc_common`) build with nothing set.
- Every `$(shell ...)` runs through a recording shell (`make_shell.sh`): one that fails, or a file listing
  (`ls`, `find`) that names no files, is an error naming the command, where make itself would go on with an
  empty list and the build would fail later with a link error that says nothing of the cause.
- A make error is one line naming the file and line (`Makefile.inc:3: missing separator`).
"""

from __future__ import annotations

import os
import re
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

from athrill_sim.native import NativeBuildError

HERE = Path(__file__).resolve().parent
SDK = HERE / "sdk"  # EV3RT's sdk/common, as far as the native build needs it
LIBRARY_DIR = SDK / "library"
RUNTIME_INCLUDE = HERE / "runtime" / "include"
# ET Robocon's environment (its setup script) points these at its SDK's workspace, which holds etroboc_common/.
ETROBO_VARIABLES = ("ETROBO_ROOT", "ETROBO_HRP3_WORKSPACE", "ETROBO_ATHRILL_WORKSPACE")
ETROBO_DEFAULT = RUNTIME_INCLUDE.parent
ETROBOC_COMMON = ETROBO_DEFAULT / "etroboc_common"  # the bench's etroboc_ext.h
# What a Makefile.inc sets that decides what is built.
VARIABLES = ("SRCLANG", "APPL_COBJS", "APPL_CXXOBJS", "APPL_ASMOBJS", "APPL_DIRS", "APPL_LIBS", "INCLUDES",
             "COPTS", "CDEFS", "USE_RASPIKE_ART")
MARK = "hako-make>"
MAKE_TIMEOUT_S = 60
_MAKE_ENV_DROPPED = ("MAKEFLAGS", "MFLAGS", "MAKELEVEL", "MAKEFILES", "GNUMAKEFLAGS", "MAKEOVERRIDES")
_LISTING = re.compile(r"(^|[|;&(`\s])(ls|find)(\s|$)")
_MAKE_ERROR = re.compile(r"^(?P<file>[^:\n]+):(?P<line>\d+): (?:\*\*\* )?(?P<message>.+?)(?:\.  Stop\.)?$")


@dataclass(frozen=True)
class Library:
    """An EV3RT static library the program includes (`include $(EV3RT_SDK_LIB_DIR)/libcpp-ev3/Makefile`)."""

    name: str
    folder: Path  # holds include/ and src/
    c_objects: tuple[str, ...]  # THIS_LIB_OBJS
    cxx_objects: tuple[str, ...]  # THIS_LIB_CXXOBJS


@dataclass(frozen=True)
class MakeVars:
    values: dict[str, list[str]]  # VARIABLES, as words
    libraries: tuple[Library, ...]
    makefiles: tuple[Path, ...]  # every file make read: the key of a cached build hashes them

    def words(self, name: str) -> list[str]:
        return self.values.get(name, [])


NO_MAKEFILE = MakeVars({}, (), ())  # a program without Makefile.inc sets nothing


def evaluate(makefile: Path) -> MakeVars:
    """What `makefile` sets, evaluated by GNU make in EV3RT's context (NativeBuildError, one line, if make
    fails, a `$(shell ...)` fails or a file listing names no files)."""
    makefile = makefile.resolve()
    with tempfile.TemporaryDirectory(prefix="hako-make-") as scratch:
        driver = Path(scratch) / "evaluate.mk"
        shell_log = Path(scratch) / "shell"
        shell_log.mkdir()
        driver.write_text(_driver(makefile))
        env = {k: v for k, v in os.environ.items() if k not in _MAKE_ENV_DROPPED}
        env |= {"LC_ALL": "C", "PWD": str(makefile.parent.parent), "HAKO_SHELL_LOG": str(shell_log)}
        try:
            out = subprocess.run(["make", "-r", "-s", "--no-print-directory", "-f", str(driver), "hako-evaluated"],
                                 cwd=makefile.parent.parent, capture_output=True, timeout=MAKE_TIMEOUT_S, env=env)
        except FileNotFoundError:
            raise NativeBuildError(f"{makefile}: GNU make is not installed, and EV3RT's Makefile.inc is read by it: "
                                   "apt-get install make") from None
        except subprocess.TimeoutExpired:
            raise NativeBuildError(f"{makefile}: make did not finish reading it within {MAKE_TIMEOUT_S} s") from None
        stdout = out.stdout.decode(errors="surrogateescape")
        stderr = out.stderr.decode(errors="surrogateescape")
        if out.returncode != 0:
            raise NativeBuildError(make_error(stderr, makefile, driver))
        _check_shell_calls(shell_log, makefile)
    return _parse(stdout, driver)


def _driver(makefile: Path) -> str:
    """The makefile that gives `makefile` EV3RT's context, includes it and prints what it set."""
    defaults = "\n".join(f"{name} ?= {ETROBO_DEFAULT}" for name in ETROBO_VARIABLES)
    prints = "\n".join(f"$(info {MARK}{name}=$({name}))" for name in VARIABLES)
    return f"""\
SHELL := /bin/sh
.SHELLFLAGS := {HERE / 'make_shell.sh'} -c
SRCLANG := c
CONFIG_EV3RT_APPLICATION = 1
EV3RT_SDK_LIB_DIR := {LIBRARY_DIR}
{defaults}
include {makefile}
{prints}
$(foreach lib,$(HAKO_LIBRARIES),$(info {MARK}LIBRARY=$(lib)|$(HAKO_LIB_$(lib))))
$(info {MARK}MAKEFILE_LIST=$(MAKEFILE_LIST))
.PHONY: hako-evaluated
hako-evaluated: ;
"""


def _parse(stdout: str, driver: Path) -> MakeVars:
    values: dict[str, list[str]] = {}
    libraries = []
    makefiles: tuple[Path, ...] = ()
    for line in stdout.splitlines():
        if not line.startswith(MARK):
            continue  # the file's own $(info ...)
        name, _, value = line[len(MARK):].partition("=")
        if name == "LIBRARY":
            lib, folder, c_objects, cxx_objects = (part.strip() for part in value.split("|"))
            libraries.append(Library(lib, Path(folder), tuple(c_objects.split()), tuple(cxx_objects.split())))
        elif name == "MAKEFILE_LIST":
            makefiles = tuple(dict.fromkeys(Path(f).resolve() for f in value.split() if Path(f) != driver))
        else:
            values[name] = value.split()
    return MakeVars(values, tuple(libraries), makefiles)


def make_error(stderr: str, makefile: Path, driver: Path) -> str:
    """make's first error as one line, naming the user's file and line; a library the bench does not have is
    said in those words."""
    lines = [line.strip() for line in stderr.splitlines() if line.strip()]
    for line in lines:
        m = _MAKE_ERROR.match(line)
        if m is None or Path(m["file"]) == driver:
            continue
        message = m["message"]
        missing = re.match(r"(\S+): No such file or directory$", message)
        if missing and Path(missing[1]).parent.parent == LIBRARY_DIR:
            have = ", ".join(sorted(d.name for d in LIBRARY_DIR.iterdir() if (d / "Makefile").is_file()))
            message = (f"includes {Path(missing[1]).parent.name}/Makefile, a library the bench does not have "
                       f"(it has {have})")
        return f"{m['file']}:{m['line']}: {message}"
    first = next((line for line in lines if "***" in line), lines[0] if lines else "make failed")
    return f"{makefile}: {first.replace('make: *** ', '').removesuffix('.  Stop.')}"


def _check_shell_calls(log: Path, makefile: Path) -> None:
    """The `$(shell ...)` commands make ran, in order: one that failed, or a listing that named no files."""
    for call in sorted(log.iterdir()):
        command = (call / "command").read_text(errors="replace").strip()
        status = (call / "status").read_text().strip() if (call / "status").is_file() else "?"
        errors = [line for line in (call / "err").read_text(errors="replace").splitlines() if line.strip()]
        if status != "0" or errors:
            why = errors[0].strip() if errors else f"exit status {status}"
            raise NativeBuildError(f"{makefile}: $(shell {command}) failed: {why}")
        if _LISTING.search(command) and not (call / "out").read_text(errors="replace").strip():
            raise NativeBuildError(f"{makefile}: $(shell {command}) names no files")
