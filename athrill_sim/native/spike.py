"""SPIKE programs: which programs are, and what their build adds (docs/NATIVE.md, "SPIKE").

ET Robocon's SPIKE SDK for Athrill builds every program against the SPIKE-RT API (`pup_*`, `hub_*`) and
defines USE_RASPIKE_ART; RasPike-ART's samples say so in their Makefile.inc (`USE_RASPIKE_ART=1`) and include
`spikeapi.h`. A program that does either, includes a SPIKE-RT or pbio header, or includes libcpp-spike's Makefile,
is built with our SPIKE-RT headers and runtime (`runtime/spike`) in addition to the EV3RT ones, which stay available
as on RasPike-ART.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from pathlib import Path

from athrill_sim.native.makefile import MakeVars

SPIKE = Path(__file__).with_name("runtime") / "spike"
INCLUDE_DIRS = (SPIKE / "include", SPIKE / "include" / "spike")  # <spike/pup/motor.h> and the SDK's <pup/motor.h>
SOURCE_DIR = SPIKE / "src"
DEFINES = ("-DUSE_RASPIKE_ART",)  # as the SDK's Makefile.img defines it
MAKE_VARIABLE = "USE_RASPIKE_ART"
CXX_LIBRARY = "libcpp-spike"  # ET Robocon's C++ classes over SPIKE-RT: a program that includes them is one
SOURCES = (".c", ".h", ".cpp", ".hpp", ".cc", ".hh")  # what may include a SPIKE header

_SPIKE_INCLUDE = re.compile(r'^\s*#\s*include\s*[<"](?:spikeapi\.h|spike/|pbio/)', re.M)


def is_spike_program(make: MakeVars, files: Iterable[Path]) -> bool:
    """Whether Makefile.inc sets USE_RASPIKE_ART (make's `ifdef` sense: to anything) or includes libcpp-spike,
    or one of the program's C or C++ files includes a SPIKE header."""
    if make.words(MAKE_VARIABLE) or any(lib.name == CXX_LIBRARY for lib in make.libraries):
        return True
    return any(_SPIKE_INCLUDE.search(f.read_text(errors="replace")) for f in files if f.suffix in SOURCES)


def sources() -> list[Path]:
    return sorted(SOURCE_DIR.glob("*.c"))


def declared_in(name: str) -> str | None:
    """The SPIKE-RT header that declares `name` (`spike/pup/motor.h` for `pup_motor_t`), as a program includes
    it: RasPike-ART's `spikeapi.h` declares no device, so a program that includes only it and uses a motor
    fails to compile, on the robot as here, and the error names the header it lacks."""
    declaring = re.compile(rf"typedef\b[^;]*\b{name}\s*;|\}}\s*{name}\s*;|#define\s+{name}\b|^\s*{name}\s*[=,]"
                           rf"|^[\w\s*]*\b{name}\s*\(", re.M)
    root = INCLUDE_DIRS[0]
    for header in sorted(root.rglob("*.h")):
        if header.name != "spikeapi.h" and declaring.search(header.read_text(errors="replace")):
            return header.relative_to(root).as_posix()
    return None
