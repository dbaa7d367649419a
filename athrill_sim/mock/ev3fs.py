"""The SD card for the Python mock: the run directory's sdcard/ folder, as in the C runtime (runtime/src/sdcard.c),
where it is the program's working directory. A relative path here is taken from that folder. Argument checks
and error codes are EV3RT's (ev3api_fs.c): memfile_load with no path is E_PAR, with no memfile E_NOMEM, a file
that does not open E_PAR (and a warning); memfile_free of nothing E_PAR, of a freed one E_OBJ. Folders are
numbered 1..16 as the C runtime numbers them; readdir past the last entry is E_OBJ.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Callable
from pathlib import Path
from typing import Protocol

from athrill_sim.mock.ev3types import E_ID, E_NOID, E_NOMEM, E_OBJ, E_OK, E_PAR, FileInfo, MemFile
from hakoniwa.wire.rundir import SDCARD_DIR

MAX_DIRS = 16  # open folders at once, as runtime/src/sdcard.c allows



class _OpenDir(Protocol):
    """What `os.scandir` returns, as the directory calls use it: typeshed names its class privately."""

    def __next__(self) -> os.DirEntry[str]: ...

    def close(self) -> None: ...

class FsApi:
    """EV3RT's ev3_memfile_* and ev3_sdcard_* (the Ev3Api's part that owns the SD card)."""

    run_dir: Path
    syslog: Callable[[str], None]

    def __init__(self) -> None:
        self._dirs: dict[int, tuple[Path, _OpenDir]] = {}

    @property
    def sdcard(self) -> Path:
        """The folder standing in for the SD card (created as the C runtime creates it at start)."""
        folder = self.run_dir / SDCARD_DIR
        folder.mkdir(exist_ok=True)
        return folder

    def ev3_memfile_load(self, path: str | None, memfile: MemFile | None) -> int:
        if path is None:
            return E_PAR
        if memfile is None:
            return E_NOMEM
        memfile.buffer = None
        try:
            data = (self.sdcard / path).read_bytes()
        except OSError:
            self.syslog(f"API ev3_memfile_load() warning: Path '{path}' is invalid.")
            return E_PAR
        memfile.buffer, memfile.filesz, memfile.buffersz = data, len(data), len(data)
        return E_OK

    def ev3_memfile_free(self, memfile: MemFile | None) -> int:
        if memfile is None:
            return E_PAR
        if memfile.buffer is None:
            return E_OBJ
        memfile.buffer = None
        return E_OK

    def ev3_sdcard_opendir(self, path: str | None) -> int:
        if path is None:
            return E_PAR
        free = [i for i in range(1, MAX_DIRS + 1) if i not in self._dirs]
        if not free:
            return E_NOID
        folder = self.sdcard / path
        try:
            entries = os.scandir(folder)
        except OSError:
            return E_PAR
        self._dirs[free[0]] = (folder, entries)
        return free[0]

    def ev3_sdcard_readdir(self, dirid: int, info: FileInfo | None) -> int:
        if dirid not in self._dirs:
            return E_ID
        if info is None:
            return E_PAR
        entry = next(self._dirs[dirid][1], None)
        if entry is None:
            return E_OBJ  # no more entries
        try:
            mode = entry.stat().st_mode
            size = entry.stat().st_size
        except OSError:
            mode = size = 0
        info.name, info.date, info.time = entry.name, 0, 0
        info.size = size if stat.S_ISREG(mode) else 0
        info.is_dir = stat.S_ISDIR(mode)
        info.is_readonly = bool(mode) and not mode & stat.S_IWUSR
        info.is_hidden = entry.name.startswith(".")
        return E_OK

    def ev3_sdcard_closedir(self, dirid: int) -> int:
        if dirid not in self._dirs:
            return E_ID
        self._dirs.pop(dirid)[1].close()
        return E_OK
