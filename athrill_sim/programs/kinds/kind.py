"""What every kind of robot program answers, and what they all look at: the interface of `athrill_sim.programs.kinds`.

A kind recognises an `--app` (`claims`), builds it (`Recipe.make`: the `Program` that starts it for each test,
which says how the launcher starts it: ahead of its test, forked, in the run directory), and says which
parameter forms reach its programs (`takes`, with `refusal` for those that do not) and what the forms need of
it (the files a build reads, the flags that keep a global findable, where a tuned copy of its image goes).
Adding a kind is one module and one line of `athrill_sim.programs.resolve.KINDS`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path
from typing import Protocol

from athrill_sim.programs.program import Program
from hakoniwa.wire.protocol import SyncMode
from hakoniwa.wire.vdev_udp import UdpLink


class Emulator(StrEnum):
    """What a C program runs on (`--emulator`): it decides the kind where one folder could be built either way."""

    NATIVE = "native"  # compiled for this machine, on the bench's runtime
    ATHRILL2 = "athrill2"  # built into a v850 image and run in the real TOPPERS emulator
    RASPIKE_ART = "raspike-art"  # a RasPike-ART workspace run as the robot's own asp under qemu-user


# What a parameter form needs of a program (`athrill_sim.tuning.forms.form.Form.needs`), and so of its kind:
REBUILD = "rebuild"  # its value is built in: the program is rebuilt from its sources for each value
IMAGE = "image"  # its value is set in the program's image (a global's initial value)
DATA_FILE = "data file"  # its value is written into a data file the program reads on its SD card


@dataclass(frozen=True)
class AppSpec:
    """What `--app` names, with the emulator asked for, as each kind looks at it."""

    spec: str
    emulator: Emulator | None  # None: by the kind of --app
    c_source: Path | None  # a C or C++ program: a built-in C name's file, a folder, a .c or .cpp file
    real: bool  # the program runs in the real emulator: --emulator athrill2, or a v850 image

    @property
    def path(self) -> Path:
        return Path(self.spec)

    @classmethod
    def of(cls, spec: str, emulator: Emulator | None) -> AppSpec:
        from athrill_sim.apps import C_BUILTIN
        from athrill_sim.native.workspace import SOURCE_SUFFIXES
        from athrill_sim.v850.elf import is_elf

        path = Path(spec)
        c_source = C_BUILTIN.get(spec) or (path if path.is_dir() or (path.is_file() and path.suffix in SOURCE_SUFFIXES)
                                           else None)
        real = emulator == Emulator.ATHRILL2 or (c_source is None and path.is_file() and is_elf(path))
        return cls(spec, emulator, None if c_source is None else Path(c_source), real)


@dataclass(frozen=True)
class RealEmulator:
    """How the real emulator runs a program, as the options ask (checked against each other already)."""

    athrill2: str | None  # --athrill2; None: on PATH, else the project's build
    sync: SyncMode
    udp: UdpLink | None  # None: over the mapped files


@dataclass(frozen=True)
class Recipe:
    """How the program `--app` names is made: `make(path, flags)` builds it from `path` (its sources, or a
    scratch copy of them) with extra compiler flags; a Python program or a v850 image is taken as it is."""

    kind: ProgramKind
    path: Path | None  # the C program (file or folder), or the v850 image; None for a Python program
    make: Callable[[Path | None, tuple[str, ...]], Program]
    sync: SyncMode = SyncMode.LOCKSTEP  # how the program keeps time with physics


class ProgramKind(Protocol):
    """One kind of robot program. A kind module subclasses this, and overrides the defaults that differ."""

    noun: str = "program"  # what it is, for people: "a v850 image"
    needs_met: frozenset[str] = frozenset()  # what a parameter form may need of it (REBUILD, IMAGE, DATA_FILE)
    symbol_flags: tuple[str, ...] = ()  # compiler flags that keep a global findable, with no change to the code
    finds_reads: bool = False  # its image tells which globals the program reads (one it never reads is refused)
    # Where a copy of its image with other initial values goes: the run directory (the emulator loads it from
    # there), or the cache (an executable: a run directory may not allow running programs).
    image_in_run_dir: bool = True

    def claims(self, app: AppSpec) -> bool:
        """Whether `--app` names a program of this kind (where two kinds claim it, the first in
        `athrill_sim.programs.resolve.KINDS` makes it: a built-in Python name beats a folder of that name)."""
        ...

    def recipe(self, app: AppSpec, real: RealEmulator) -> Recipe:
        """How to make the program; ProgramError (one line) for options it cannot run with."""
        ...

    def files(self, path: Path) -> tuple[Path, ...]:
        """The files a build of the program at `path` reads (for a scratch copy, and the journal's hash);
        BindingError (one line) if they cannot be found. By default the one file `path` is."""
        return (path.resolve(),)

    def refusal(self, forms: set[str]) -> str:
        """Why parameters of `forms`, which need what this kind does not have, cannot reach its programs."""
        return f"{', '.join(sorted(forms))} parameters cannot reach {self.noun}"

    def takes(self, needs: str | None) -> bool:
        """Whether a parameter form that needs `needs` of a program (None: nothing) reaches this kind's."""
        return needs is None or needs in self.needs_met


def given(path: Path | None) -> Path:
    """A recipe's path, which every kind's recipe has but the Python program's."""
    assert path is not None
    return path
