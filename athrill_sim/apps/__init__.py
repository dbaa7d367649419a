"""Robot programs that run on the mock Athrill, by name. A user program is given as `module:function`.

`C_BUILTIN` names the C programs shipped beside them, which run natively (see `athrill_sim.native`).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from pathlib import Path

from athrill_sim.mock.ev3api import Ev3Api
from athrill_sim.programs.program import ProgramError

App = Callable[[Ev3Api], None]

BUILTIN = {"line_trace": "athrill_sim.apps.line_trace:main_task"}
C_BUILTIN = {"line_trace_c": Path(__file__).with_name("line_trace.c")}


def load_app(spec: str) -> App:
    """The robot program `spec` names: a built-in name or module:function.

    Raises:
        ProgramError: `spec` names no app, or its module cannot be imported.
    """
    target = BUILTIN.get(spec, spec)
    module_name, _, func_name = target.partition(":")
    if not func_name:
        raise ProgramError(f"unknown app {spec!r}: use one of {', '.join(BUILTIN)} or module:function")
    try:
        func = getattr(importlib.import_module(module_name), func_name)
    except (ImportError, AttributeError) as e:
        raise ProgramError(f"cannot load app {spec!r}: {e}") from None
    return func
