"""An EV3RT C or C++ program built into a v850 image with the EV3RT SDK (`athrill_sim.v850`, cached) and run
in the real TOPPERS athrill2 (`--emulator athrill2`), started with its own test."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from athrill_sim.programs.athrill2 import elf_program
from athrill_sim.programs.kinds.kind import DATA_FILE, IMAGE, REBUILD, AppSpec, ProgramKind, RealEmulator, Recipe, given
from athrill_sim.programs.program import Program, ProgramError, card_files, program_sdcard
from hakoniwa.wire.protocol import SyncMode
from hakoniwa.wire.vdev_udp import UdpLink


class ImageKind(ProgramKind):
    noun = "a C or C++ program built into a v850 image"
    needs_met = frozenset({REBUILD, IMAGE, DATA_FILE})
    symbol_flags = ("-fno-zero-initialized-in-bss",)  # EV3RT builds with -g already

    def claims(self, app: AppSpec) -> bool:
        return app.c_source is not None and app.real

    def recipe(self, app: AppSpec, real: RealEmulator) -> Recipe:
        return Recipe(self, app.c_source,
                      lambda source, flags: image_program(given(source), real.athrill2, real.sync, real.udp, flags),
                      real.sync)

    def files(self, path: Path) -> tuple[Path, ...]:
        from athrill_sim.tuning.forms.form import BindingError
        from athrill_sim.v850 import ImageError
        from athrill_sim.v850.build import app_files

        try:
            return tuple(app_files(path)[1])
        except ImageError as e:
            raise BindingError(str(e)) from None


def image_program(source: Path, athrill2: str | None, sync: SyncMode, udp: UdpLink | None = None,
                  flags: tuple[str, ...] = ()) -> Program:
    """A user's EV3RT C or C++ program, built now into a v850 image (cached) with the extra compiler `flags`,
    and run in the real emulator."""
    from athrill_sim.v850 import ImageError
    from athrill_sim.v850.build import build_image

    try:
        image = build_image(source, flags=flags)
    except ImageError as e:
        raise ProgramError(str(e)) from None
    card = program_sdcard(source)
    program = elf_program(image, athrill2, sync, udp)
    return replace(program, sdcard=card, files=(*program.files, *card_files(card)))


IMAGE_KIND = ImageKind()
