"""An EV3RT C or C++ program (a `.c` or `.cpp` file, a workspace folder, or `line_trace_c`) compiled for this
machine against our `ev3api.h`, EV3RT's libraries and our C runtime, SPIKE programs against SPIKE-RT's
headers too (`athrill_sim.native`): built once before any test, then started one test ahead."""

from __future__ import annotations

from pathlib import Path

from athrill_sim.programs.kinds.kind import DATA_FILE, IMAGE, REBUILD, AppSpec, ProgramKind, RealEmulator, Recipe, given
from athrill_sim.programs.program import Program, ProgramError, card_files, program_sdcard
from hakoniwa.wire.protocol import SyncMode

NATIVE_DIR = Path(__file__).resolve().parents[2] / "native"  # the bench's runtime and libraries, not the user's
NATIVE_ENV = (("TZ", "UTC0"),)  # localtime() of the simulated clock: the same on every machine (docs/NATIVE.md)


class NativeKind(ProgramKind):
    noun = "a C or C++ program compiled for this machine"
    needs_met = frozenset({REBUILD, IMAGE, DATA_FILE})
    # A build whose globals are set keeps what finding them needs: the debug information (types), the
    # link-time relocations (what reads them) and zero initial values in .data (which a file can hold; .bss is
    # zero-filled at start). None of the three changes the code the compiler makes.
    symbol_flags = ("-g", "-Wl,--emit-relocs", "-fno-zero-initialized-in-bss")
    finds_reads = True
    image_in_run_dir = False

    def claims(self, app: AppSpec) -> bool:
        return app.c_source is not None and not app.real

    def recipe(self, app: AppSpec, real: RealEmulator) -> Recipe:
        return Recipe(self, app.c_source, lambda source, flags: native_program(given(source), flags))

    def files(self, path: Path) -> tuple[Path, ...]:
        from athrill_sim.native import NativeBuildError
        from athrill_sim.native.workspace import MAKEFILE_INC, find_app
        from athrill_sim.tuning.forms.form import BindingError

        try:
            app = find_app(path)
        except NativeBuildError as e:
            raise BindingError(str(e)) from None
        make = [app.root / MAKEFILE_INC] if (app.root / MAKEFILE_INC).is_file() else []
        return tuple(sorted({*app.hashed, *make, *app.sources}))


def native_program(source: Path, flags: tuple[str, ...] = ()) -> Program:
    """A user's EV3RT C program (a .c file or a workspace folder), built now, before any test starts, with
    the extra compiler `flags` (a tuned program's -D definitions)."""
    from athrill_sim.native import NativeBuildError
    from athrill_sim.native.build import build_app
    from athrill_sim.native.workspace import find_app
    from athrill_sim.programs.working_folder import WorkingFolder, WorkingFolderError

    try:
        exe = build_app(source, flags=flags)
        files = tuple(f for f in find_app(source).hashed if not f.is_relative_to(NATIVE_DIR))  # the user's
        card = program_sdcard(source)
        folder = WorkingFolder.of(source, card)
    except (NativeBuildError, WorkingFolderError) as e:
        raise ProgramError(str(e)) from None
    return Program(f"native C app {source}", SyncMode.LOCKSTEP, True,
                   (str(exe), "--run-dir", "{run_dir}", "--test", "{test}"), files=(*files, *card_files(card)),
                   image=exe, working_folder=folder, interrupted_at_end=True, env=NATIVE_ENV)


NATIVE = NativeKind()
