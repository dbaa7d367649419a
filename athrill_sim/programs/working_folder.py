"""The folder a native program runs in, as it runs on the robot: a scratch copy of its workspace, one per test.

On the robot, ET Robocon's `make app=NAME start` runs the program from the workspace, the folder that holds the
app folder NAME: so the program opens `./NAME/datafiles/LineTraceLeft.csv`, or `getcwd()` + "/tracer.ini", and
writes its logs beside them. Each test gets its own copy of that, made when its process is started (a test
ahead, as the process is), so that what one test writes never reaches the next and the user's own tree is never
written: the files the workspace holds itself (not its other folders: other apps, the SDK), the app folder
(without its `.git` and other hidden folders), and the program's own SD card folder's contents at the root, as
EV3RT's SD card is the working directory of an EV3RT program (its relative `fopen`, `ev3_memfile_load`). The
last test's copy, with what the program wrote into it, is kept in the run directory (`WORKSPACE_DIR`).
"""

from __future__ import annotations

import os
import shutil
from dataclasses import dataclass
from pathlib import Path

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.rundir import WORKSPACE_DIR, WORKSPACES_DIR

MAX_BYTES = 256 * 2**20  # copied for every test: beyond this the copies would cost more than the tests


class WorkingFolderError(HakoError, ValueError):
    """The program's workspace cannot be copied for its tests; the message is one line."""


def _hidden(_folder: str, names: list[str]) -> set[str]:
    return {n for n in names if n.startswith(".")}


@dataclass(frozen=True)
class WorkingFolder:
    """What each test's copy holds."""

    root_files: tuple[Path, ...]  # the workspace's own files, beside the app folder
    app: Path | None  # the app folder, copied under its own name; None for a lone source file
    sdcard: Path | None  # the program's SD card folder, whose contents are copied to the root

    @staticmethod
    def of(source: Path, sdcard: Path | None) -> WorkingFolder:
        """The workspace of the program at `source`: an app folder (or its app.c / app.cpp beside an app.cfg)
        in its workspace, or a lone source file, which has none."""
        source = source.resolve()
        app = source if source.is_dir() else source.parent if (source.parent / "app.cfg").is_file() else None
        root_files = tuple(sorted(f for f in app.parent.iterdir() if f.is_file())) if app is not None else ()
        workspace = WorkingFolder(root_files, app, sdcard)
        size = workspace.size()
        if size > MAX_BYTES:
            raise WorkingFolderError(f"{app}: its workspace holds {size / 2**20:.0f} MiB, copied for every test; keep "
                                 f"it under {MAX_BYTES / 2**20:.0f} MiB (large data outside the app folder, or in a "
                                 "hidden folder)")
        return workspace

    def size(self) -> int:
        return sum(f.stat().st_size for f in self.files())

    def files(self) -> list[Path]:
        """Every file a copy holds (a campaign's journal hashes them: what each test starts from)."""
        return [*self.root_files, *(_tree_files(self.app) if self.app else ()),
                *(_tree_files(self.sdcard) if self.sdcard else ())]

    def make(self, folder: Path) -> Path:
        """A fresh copy in `folder`."""
        folder.mkdir(parents=True)
        if self.sdcard is not None:
            shutil.copytree(self.sdcard, folder, dirs_exist_ok=True, symlinks=True)
        for f in self.root_files:
            shutil.copy2(f, folder / f.name)
        if self.app is not None:
            shutil.copytree(self.app, folder / self.app.name, ignore=_hidden, symlinks=True, dirs_exist_ok=True)
        return folder

    def app_folder(self, folder: Path) -> Path:
        """Where the app folder is in the copy `folder` (the copy itself for a lone source file)."""
        return folder / self.app.name if self.app is not None else folder


def _tree_files(folder: Path) -> list[Path]:
    out = []
    for parent, dirs, files in os.walk(folder):
        dirs[:] = [d for d in dirs if not d.startswith(".")]
        out += [Path(parent) / f for f in files if not os.path.islink(Path(parent) / f)]
    return out


def test_folder(run_dir: Path, seq: int) -> Path:
    return run_dir / WORKSPACES_DIR / f"test-{seq}"


def keep(run_dir: Path, folder: Path) -> None:
    """The test's copy becomes the run directory's WORKSPACE_DIR, the one before it gone."""
    kept = run_dir / WORKSPACE_DIR
    if kept.exists():
        shutil.rmtree(kept)
    folder.rename(kept)


def discard(folder: Path) -> None:
    shutil.rmtree(folder, ignore_errors=True)
