"""Users' EV3RT C programs, compiled for this machine and run as the Athrill process (docs/NATIVE.md).

`--app path/to/app.c` (or an EV3RT `sdk/workspace` folder) is built once per campaign with the system C
compiler against our own `ev3api.h` and a small C runtime (`runtime/`), and cached. The result maps the bench
files itself and keeps the same deterministic lockstep as the Python mock, with no Python in the loop.
"""

from __future__ import annotations

from hakoniwa.wire.errors import HakoError


class NativeBuildError(HakoError, ValueError):
    """The program cannot be built; the message is one line (the compiler's first error, if it got that far)."""
