"""SPIKE programs: which programs are, and what their build adds (docs/NATIVE.md, "SPIKE").

ET Robocon's SPIKE SDK for Athrill builds every program against the SPIKE-RT API (`pup_*`, `hub_*`) and
defines USE_RASPIKE_ART; RasPike-ART's samples say so in their Makefile.inc (`USE_RASPIKE_ART=1`) and include
`spikeapi.h`. A program that does either, includes a SPIKE-RT or pbio header, or includes libcpp-spike's Makefile,
is built with our SPIKE-RT headers and runtime (`runtime/spike`) in addition to the EV3RT ones, which stay available
as on RasPike-ART.

The Basic class's programs are built in SPIKE-RT's own SDK for the hub (`spike-rt-hub/sdk`): their folder holds
an `app.cdl` (TECS, which the hub's build reads and a native build has no use for: syslog and the serial ports are
the runtime's), or they include SPIKE-RT's C++ classes (`<libcpp/spike/Motor.h>`). Such a hub program is a SPIKE
program without USE_RASPIKE_ART (the hub's SDK does not define it), with SPIKE-RT's libcpp (`sdk/spike-rt`) on
its include path, and, when it is C++, its include folders and sources as the SDK's `app.mk` adds them.
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
HUB_CDL = "app.cdl"  # a hub program's TECS description
SPIKE_RT = Path(__file__).with_name("sdk") / "spike-rt"  # SPIKE-RT's libcpp, copied (its README.md)
HUB_INCLUDE_DIRS = (SPIKE_RT / "include",)  # <libcpp/spike/Motor.h>
# app.mk's for a C++ program: "Motor.h" and <spike/Motor.h>, before the program's own INCLUDES, as there
HUB_CXX_INCLUDE_DIRS = (SPIKE_RT / "include" / "libcpp", SPIKE_RT / "include" / "libcpp" / "spike")
HUB_CXX_SOURCE_DIR = SPIKE_RT / "libcpp" / "spike"

_SPIKE_INCLUDE = re.compile(r'^\s*#\s*include\s*[<"](?:spikeapi\.h|spike/|pbio/)', re.M)
_LIBCPP_INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]libcpp/', re.M)


def is_spike_program(make: MakeVars, files: Iterable[Path]) -> bool:
    """Whether Makefile.inc sets USE_RASPIKE_ART (make's `ifdef` sense: to anything) or includes libcpp-spike,
    or one of the program's C or C++ files includes a SPIKE header."""
    if make.words(MAKE_VARIABLE) or any(lib.name == CXX_LIBRARY for lib in make.libraries):
        return True
    return _includes(_SPIKE_INCLUDE, files)


def is_hub_program(root: Path, files: Iterable[Path]) -> bool:
    """Whether the program in folder `root` is built in SPIKE-RT's own SDK: an app.cdl there, or a C or C++
    file that includes SPIKE-RT's libcpp."""
    return (root / HUB_CDL).is_file() or _includes(_LIBCPP_INCLUDE, files)


def _includes(pattern: re.Pattern[str], files: Iterable[Path]) -> bool:
    return any(pattern.search(f.read_text(errors="replace")) for f in files if f.suffix in SOURCES)


def sources() -> list[Path]:
    return sorted(SOURCE_DIR.glob("*.c"))


def hub_cxx_sources() -> list[Path]:
    """SPIKE-RT's libcpp sources, which the hub's kernel library builds for a C++ program."""
    return sorted(HUB_CXX_SOURCE_DIR.glob("*.cpp"))


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
