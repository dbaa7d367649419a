"""Athrill's guest memory as the robot program sees it: plain addresses backed by the two mapped files.

The unity data area appears at UNITY_GUEST_BASE (0x090F0000, as in the paper), so a program reads Kp with
`read_f32(0x090F0000 + 540)`; the athrill data area appears at ATHRILL_GUEST_BASE.
"""

from __future__ import annotations

from pathlib import Path

from hakoniwa.protocol import (ATHRILL_FILE, UNITY_FILE, MappedFile, ProtocolError, guest_to_data_offset,
                               open_athrill, open_unity)


class BusError(ProtocolError):
    """An access outside the mapped guest memory (a wild pointer in the robot program)."""


class MemoryBus:
    def __init__(self, run_dir: Path) -> None:
        self.unity = open_unity(run_dir)
        self.athrill = open_athrill(run_dir)
        self._files: dict[str, MappedFile] = {UNITY_FILE: self.unity, ATHRILL_FILE: self.athrill}

    def _resolve(self, addr: int) -> tuple[MappedFile, int]:
        try:
            name, offset = guest_to_data_offset(addr)
        except ValueError as e:
            raise BusError(str(e)) from None
        return self._files[name], offset

    def read_f32(self, addr: int) -> float:
        f, off = self._resolve(addr)
        return f.read_f32(off)

    def read_i32(self, addr: int) -> int:
        f, off = self._resolve(addr)
        return f.read_i32(off)

    def write_i32(self, addr: int, value: int) -> None:
        f, off = self._resolve(addr)
        f.write_i32(off, value)

    def close(self) -> None:
        self.unity.close()
        self.athrill.close()
