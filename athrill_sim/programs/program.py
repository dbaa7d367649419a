"""A robot program ready to be started once per test, whatever its kind (`athrill_sim.programs.kinds`): the command
that starts it, how it keeps time, what it is made of and what the run directory must hold for it.

The kinds make `Program`s; the launcher (`athrill_sim.programs.launcher`) starts them; the tuning
(`athrill_sim.tuning`) makes variants of them for a test's parameter values. This module imports none of them.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.processes import die_with_parent
from hakoniwa.wire.protocol import SyncMode
from hakoniwa.wire.rundir import SDCARD_DIR
from hakoniwa.wire.vdev_udp import UdpLink

if TYPE_CHECKING:
    from athrill_sim.programs.working_folder import WorkingFolder

MOCK_ARGV = (sys.executable, "-m", "athrill_sim.mock.main")  # the mock Athrill, whose arguments follow


class ProgramError(HakoError, ValueError):
    """`--app` (or `--athrill2`) names nothing that can run; the message is one line."""


@dataclass(frozen=True)
class Program:
    """A robot program, ready to be started once per test."""

    description: str
    sync: SyncMode
    prelaunch: bool  # start test N+1's process while test N runs (it waits for its own test number)
    argv: tuple[str, ...]  # the command; "{test}" and "{run_dir}" are filled in per test
    in_run_dir: bool = False  # run with the run directory as working directory
    config_files: dict[str, str] = field(default_factory=dict)  # written into the run directory once
    check_argv: tuple[str, ...] = ()  # a command that exits non-zero, saying why, if the program cannot run
    files: tuple[Path, ...] = ()  # what the program is made of (its sources, its image), for a campaign's journal
    udp: UdpLink | None = None  # the real emulator over UDP: its endpoints (else the mapped files carry all)
    image: Path | None = None  # the file argv runs: the native Athrill, or the v850 image athrill2 loads
    sdcard: Path | None = None  # the program's own sdcard/ folder, copied onto the bench's SD card
    tuning: Any = field(default=None, compare=False)  # athrill_sim.tuning.tune.Tuning: the parameters' bindings
    forkable: bool = False  # argv is MOCK_ARGV + arguments: `athrill_sim.programs.zygote` can fork it instead
    working_folder: WorkingFolder | None = None  # a scratch copy of the program's workspace per test, its cwd
    interrupted_at_end: bool = False  # a test's end sends SIGINT (Ctrl-C) before the process is stopped
    env: tuple[tuple[str, str], ...] = ()  # set in the process's environment
    links: tuple[tuple[str, str], ...] = ()  # (name in the run directory, target): links made there once
    serial_hub: bool = False  # it talks to a SPIKE hub over a serial port, played by the physics side

    def prepare(self, run_dir: Path) -> None:
        for name, text in self.config_files.items():
            (run_dir / name).write_text(text)
        if self.sdcard is not None:
            shutil.copytree(self.sdcard, run_dir / SDCARD_DIR, dirs_exist_ok=True)
        for name, target in self.links:
            link = run_dir / name
            link.parent.mkdir(parents=True, exist_ok=True)
            link.unlink(missing_ok=True)
            link.symlink_to(target)

    def with_image(self, image: Path) -> Program:
        """The same program run from another copy of its image (one with other initial values)."""
        assert self.image is not None
        return replace(self, argv=tuple(str(image) if a == str(self.image) else a for a in self.argv), image=image,
                       tuning=None)

    def start_check(self) -> subprocess.Popen | None:
        """Start checking, in a process of its own exactly as a test would load it, that the program can
        run; the caller does its own start-up meanwhile and then calls `finish_check`."""
        if not self.check_argv:
            return None
        return subprocess.Popen(self.check_argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True)

    @staticmethod
    def finish_check(check: subprocess.Popen | None) -> None:
        if check is None:
            return
        out, _ = check.communicate()
        if check.returncode != 0:
            lines = [line for line in out.strip().splitlines() if line.strip()]
            raise ProgramError(lines[-1].removeprefix("Error: ") if lines else "the robot program cannot run")

    def args(self, run_dir: Path, test_seq: int) -> list[str]:
        """The command for test `test_seq`; the run directory goes in absolute, since the process starts in a
        working folder of its own (`hako test --out build/x` is relative to the user's shell)."""
        return [a.format(test=test_seq, run_dir=run_dir.resolve()) for a in self.argv]

    def spawn(self, run_dir: Path, test_seq: int, output, cwd: Path | None = None) -> subprocess.Popen:
        """Start the process for test `test_seq` (in `cwd`, its working folder, if it has one). It gets a
        session of its own, so that a Ctrl-C meant for the campaign does not kill it mid-test (the physics
        process stops it), and dies with the physics process, so that nothing is left running if that is
        killed."""
        return subprocess.Popen(self.args(run_dir, test_seq), stdin=subprocess.DEVNULL, stdout=output,
                                stderr=subprocess.STDOUT, cwd=cwd or (run_dir if self.in_run_dir else None),
                                env={**os.environ, **dict(self.env)} if self.env else None,
                                start_new_session=True, preexec_fn=die_with_parent)


def program_sdcard(source: Path) -> Path | None:
    """A C program's own SD card: the sdcard/ folder beside its sources, if it has one."""
    folder = (source if source.is_dir() else source.parent) / SDCARD_DIR
    return folder.resolve() if folder.is_dir() else None


def card_files(card: Path | None) -> tuple[Path, ...]:
    return tuple(sorted(f.resolve() for f in card.rglob("*") if f.is_file())) if card is not None else ()
