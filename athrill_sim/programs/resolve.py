"""What `--app` names: the kinds of robot program (`athrill_sim.programs.kinds`) in one table, and the options that
decide between them and how the real emulator runs one.

A Python program runs on the mock Athrill; an EV3RT C or C++ program natively or, with `--emulator athrill2`,
built into a v850 image for the real TOPPERS `athrill2`; a v850 ELF image in `athrill2`. The kind decides
how time is kept (`SyncMode`): our own programs run in the deterministic lockstep, the real emulator in
`--sync`'s mode over `--transport` (`athrill_sim.programs.athrill2`). Everything here is checked before the first
test, so a bad `--app` is one clear error instead of a campaign of crashed tests.
"""

from __future__ import annotations

from athrill_sim.programs.athrill2 import AthrillTransport, RealSync, udp_link
from athrill_sim.programs.kinds.elf import ELF
from athrill_sim.programs.kinds.image import IMAGE_KIND
from athrill_sim.programs.kinds.kind import AppSpec, Emulator, ProgramKind, RealEmulator, Recipe
from athrill_sim.programs.kinds.native import NATIVE
from athrill_sim.programs.kinds.python import PYTHON
from athrill_sim.programs.kinds.raspike_art import RASPIKE_ART_KIND
from athrill_sim.programs.program import Program, ProgramError

# Each --app is claimed by one, or by none; the first that claims it makes it (--emulator raspike-art first).
KINDS: tuple[ProgramKind, ...] = (RASPIKE_ART_KIND, PYTHON, NATIVE, IMAGE_KIND, ELF)


def resolve_program(spec: str, *, athrill2: str | None = None, emulator: Emulator | None = None,
                    sync: RealSync | None = None, transport: AthrillTransport | None = None,
                    device_config: str | None = None, bindings: str | None = None) -> Program:
    """The program `--app SPEC` names: a built-in or `module:function` Python program, an EV3RT C or C++
    program (a .c or .cpp file, a workspace folder or a built-in C name), or a v850 ELF. `emulator` athrill2
    builds a C or C++ program into a v850 image; `sync` (repeatable, hakoniwa) is how a real emulator keeps
    time, `transport` (mmap, udp) and `device_config` how its packets travel. `bindings`
    (JSON, `athrill_sim.tuning.bindings`) says how parameters of other forms than `offset` reach the program: they
    are checked against it now, and each test then runs the program as its values make it."""
    recipe = program_recipe(spec, athrill2=athrill2, emulator=emulator, sync=sync, transport=transport,
                            device_config=device_config)
    if bindings:
        from athrill_sim.tuning.bindings import from_json
        from athrill_sim.tuning.forms.form import BindingError
        from athrill_sim.tuning.tune import tune

        try:
            return tune(recipe, from_json(bindings))
        except BindingError as e:
            raise ProgramError(f"--space: {e}") from None
    return recipe.make(recipe.path, ())


def program_recipe(spec: str, *, athrill2: str | None = None, emulator: Emulator | None = None,
                   sync: RealSync | None = None, transport: AthrillTransport | None = None,
                   device_config: str | None = None) -> Recipe:
    """How to make the program `--app SPEC` names (see `resolve_program`)."""
    from athrill_sim.apps import BUILTIN, C_BUILTIN

    app = AppSpec.of(spec, emulator)
    if sync is not None and not app.real:
        raise ProgramError(f"--sync {sync} is for the real emulator (a v850 image, or --emulator athrill2); "
                           f"{spec} runs in the lockstep")
    udp = udp_link(transport, device_config)
    if udp is not None and not app.real:
        raise ProgramError(f"--transport udp is for the real emulator (a v850 image, or --emulator athrill2); "
                           f"{spec} runs in the lockstep over the mapped files")
    if udp is not None and sync == RealSync.REPEATABLE:
        raise ProgramError("--sync repeatable needs --transport mmap (the wait is patched into athrill2's mmap "
                           "device); over UDP athrill2 keeps TOPPERS' protocol: --sync hakoniwa")
    real = RealEmulator(athrill2, (sync or (RealSync.HAKONIWA if udp is not None else RealSync.REPEATABLE)).mode, udp)
    for kind in KINDS:
        if kind.claims(app):
            return kind.recipe(app, real)
    builtins = ", ".join([*BUILTIN, *C_BUILTIN])
    if app.path.is_file():
        raise ProgramError(f"--app {spec}: not a v850 ELF image, a C or C++ file (.c, .cpp), a built-in app "
                           f"({builtins}) or module:function")
    if emulator == Emulator.ATHRILL2:
        raise ProgramError(f"--app {spec}: --emulator athrill2 runs EV3RT C and C++ programs (app.c, app.cpp, a "
                           "workspace folder, line_trace_c) and v850 images, not Python programs")
    raise ProgramError(f"--app {spec}: no such file or folder, and not a built-in app ({builtins}) "
                       "or module:function")
