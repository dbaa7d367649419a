"""A v850 ELF image (an EV3RT application built for the real emulator) run as it is in the real TOPPERS
athrill2 (`athrill_sim.programs.athrill2`), started with its own test. Nothing rebuilds it, so a parameter reaches it
as a global's initial value or through a data file, not as a `#define` or a source constant."""

from __future__ import annotations

from athrill_sim.programs.athrill2 import elf_program
from athrill_sim.programs.kinds.kind import (
    DATA_FILE,
    IMAGE,
    AppSpec,
    Emulator,
    ProgramKind,
    RealEmulator,
    Recipe,
    given,
)
from athrill_sim.programs.program import ProgramError


class ElfKind(ProgramKind):
    noun = "a v850 image"
    needs_met = frozenset({IMAGE, DATA_FILE})

    def claims(self, app: AppSpec) -> bool:
        return app.c_source is None and app.path.is_file() and app.real

    def recipe(self, app: AppSpec, real: RealEmulator) -> Recipe:
        if app.emulator == Emulator.NATIVE:
            raise ProgramError(f"--app {app.spec}: a v850 image runs only in the real emulator (--emulator athrill2)")
        return Recipe(self, app.path,
                      lambda image, _flags: elf_program(given(image), real.athrill2, real.sync, real.udp), real.sync)

    def refusal(self, forms: set[str]) -> str:
        return ("define and source parameters rebuild the program: give its sources (--app FOLDER --emulator "
                "athrill2), not a built image")


ELF = ElfKind()
