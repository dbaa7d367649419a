"""A team's RasPike-ART workspace folder (`--emulator raspike-art`): built by RasPike-ART's own make into the
aarch64 `asp` the robot runs (`athrill_sim.raspike_art`), started afresh for each test under qemu-user, on the
bench's clock, with the physics side playing its SPIKE hub on a pseudo-terminal."""

from __future__ import annotations

from pathlib import Path

from athrill_sim.programs.kinds.kind import (
    DATA_FILE,
    REBUILD,
    AppSpec,
    Emulator,
    ProgramKind,
    RealEmulator,
    Recipe,
    given,
)
from athrill_sim.programs.program import Program, ProgramError
from hakoniwa.wire.protocol import SyncMode
from hakoniwa.wire.rundir import RASPIKE_PORT


class RaspikeArtKind(ProgramKind):
    noun = "a RasPike-ART program (asp)"
    # A data file reaches it as it does a native program: written into each test's copy of its workspace, asp's
    # working directory; a rebuilding form's value is a build of its own by RasPike-ART's make (cached). Image
    # forms (a global's initial value in asp) do not reach it yet.
    needs_met = frozenset({DATA_FILE, REBUILD})

    def claims(self, app: AppSpec) -> bool:
        return app.emulator == Emulator.RASPIKE_ART

    def recipe(self, app: AppSpec, real: RealEmulator) -> Recipe:
        if not app.path.is_dir():
            what = "a file" if app.path.exists() else "no such folder"
            raise ProgramError(f"--app {app.spec}: {what}; --emulator raspike-art runs a RasPike-ART workspace "
                               "folder (app.c or app.cpp, app.cfg, Makefile.inc)")
        return Recipe(self, app.path, lambda folder, flags: asp_program(given(folder), flags))

    def files(self, path: Path) -> tuple[Path, ...]:
        from athrill_sim.raspike_art import AspError
        from athrill_sim.raspike_art.build import app_files
        from athrill_sim.tuning.forms.form import BindingError

        try:
            return tuple(app_files(path)[1])
        except AspError as e:
            raise BindingError(str(e)) from None

    def refusal(self, forms: set[str]) -> str:
        return (f"{', '.join(sorted(forms))} parameters do not reach a RasPike-ART program yet (row, ini, file, "
                "define and source parameters do); run it natively (--emulator native) to tune it so")


def asp_program(folder: Path, flags: tuple[str, ...] = ()) -> Program:
    """`folder`'s asp, built now with the extra compiler `flags` (or found in the cache), with the clock
    library that puts it on the bench's time; each test's asp reaches the hub at the run directory's
    RASPIKE_PORT through qemu's prefix."""
    from athrill_sim.programs.working_folder import WorkingFolder, WorkingFolderError
    from athrill_sim.raspike_art import AspError
    from athrill_sim.raspike_art.build import app_files, build_asp
    from athrill_sim.raspike_art.clock import RUN_DIR_ENV, TEST_ENV, build_clock_library
    from athrill_sim.raspike_art.launch import PREFIX, asp_argv, prefix_links

    try:
        asp = build_asp(folder, flags=flags)
        clock = build_clock_library()
        links = prefix_links(f"../../{RASPIKE_PORT}")  # from PREFIX/dev/USB_SPIKE
        argv = asp_argv(asp, f"{{run_dir}}/{PREFIX}", (clock,), ((RUN_DIR_ENV, "{run_dir}"), (TEST_ENV, "{test}")))
        files = tuple(app_files(folder)[1])
        workspace = WorkingFolder.of(folder, None)  # `make start` runs asp from the workspace
    except (AspError, WorkingFolderError) as e:
        raise ProgramError(str(e)) from None
    prefix = tuple((f"{PREFIX}/{name}", target) for name, target in links.items())
    return Program(f"RasPike-ART app {folder}", SyncMode.LOCKSTEP, False, tuple(argv), files=files,
                   working_folder=workspace, image=asp, links=prefix, serial_hub=True)


RASPIKE_ART_KIND = RaspikeArtKind()
