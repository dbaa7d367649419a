"""Athrill's guest memory as the robot program sees it: plain addresses backed by the two mapped files.

The body of `unity_mmap.bin` appears at RX_GUEST_BASE (0x090F0000, EV3RT's VDEV base), so a program reads Kp
with `read_f32(0x090F0000 + 540)`; the body of `athrill_mmap.bin` appears at TX_GUEST_BASE (0x090F1000).
Each window is 4 KiB, as in the real emulator; anything outside them is a BusError (a wild pointer).
"""

from __future__ import annotations

from pathlib import Path

from hakoniwa.wire.protocol import (
    ATHRILL_FILE,
    UNITY_FILE,
    LayoutError,
    MappedFile,
    guest_to_body,
    open_athrill,
    open_unity,
)


class BusError(LayoutError):
    """An access outside the mapped guest memory (a wild pointer in the robot program)."""


class MemoryBus:
    def __init__(self, run_dir: Path) -> None:
        self.run_dir = Path(run_dir)  # where the program's other files go: lcd.txt, serial logs, the SD card
        self.unity = open_unity(run_dir)
        self.athrill = open_athrill(run_dir)
        self._files: dict[str, MappedFile] = {UNITY_FILE: self.unity, ATHRILL_FILE: self.athrill}

    def _resolve(self, addr: int) -> tuple[MappedFile, int]:
        try:
            name, offset = guest_to_body(addr)
        except ValueError as e:
            raise BusError(str(e)) from None
        return self._files[name], offset

    def read(self, fmt: str, addr: int) -> int | float:
        """A value of struct format `fmt` ('B', 'h', 'H', 'i', 'I', 'f') at guest address `addr`."""
        f, off = self._resolve(addr)
        try:
            return f.read(fmt, off)
        except LayoutError as e:
            raise BusError(f"0x{addr:08X}: {e}") from None

    def write(self, fmt: str, addr: int, value: int | float) -> None:
        f, off = self._resolve(addr)
        try:
            f.write(fmt, off, value)
        except LayoutError as e:
            raise BusError(f"0x{addr:08X}: {e}") from None

    def read_f32(self, addr: int) -> float:
        return float(self.read("f", addr))

    def close(self) -> None:
        self.unity.close()
        self.athrill.close()
