"""Robot programs that run on the mock Athrill, by name. A user program is given as `module:function`.

`C_BUILTIN` names the C programs shipped beside them, which run natively (see `athrill_sim.native`).
"""

from __future__ import annotations

import importlib
from pathlib import Path
from typing import Callable

from athrill_sim.ev3api import Ev3Api

App = Callable[[Ev3Api], None]

BUILTIN = {"line_trace": "athrill_sim.apps.line_trace:main_task"}
C_BUILTIN = {"line_trace_c": Path(__file__).with_name("line_trace.c")}


def load_app(spec: str) -> App:
    target = BUILTIN.get(spec, spec)
    module_name, _, func_name = target.partition(":")
    if not func_name:
        raise ValueError(f"unknown app {spec!r}: use one of {', '.join(BUILTIN)} or module:function")
    try:
        func = getattr(importlib.import_module(module_name), func_name)
    except (ImportError, AttributeError) as e:
        raise ValueError(f"cannot load app {spec!r}: {e}") from None
    return func
