"""Whether a file is a whole v850 ELF image, checked before athrill2 is given it.

athrill2 loads what it is given and dies, loops or misreads when it is not a v850 image (an x86 program) or
is cut short (a copy that stopped): each would be charged to the parameters of a test. The ELF header says
the CPU, and its program and section header tables say how long the file must be.
"""

from __future__ import annotations

import struct
from pathlib import Path

from athrill_sim.v850 import ImageError

ELF_MAGIC = b"\x7fELF"
ELFCLASS32, ELFDATA2LSB = 1, 1
# e_machine of v850 images: EM_V800 (what the TOPPERS toolchain writes), EM_V850, old GNU
V850_MACHINES = (36, 87, 0x9080)
MACHINE_NAMES = {3: "x86", 8: "MIPS", 20: "PowerPC", 40: "ARM", 62: "x86-64", 183: "AArch64", 243: "RISC-V"}
_EHDR = struct.Struct("<16sHHIIIIIHHHHHH")  # e_ident, type, machine, version, entry, phoff, shoff, flags, ehsize,
# phentsize, phnum, shentsize, shnum, shstrndx
_PHDR = struct.Struct("<IIIIIIII")  # type, offset, vaddr, paddr, filesz, memsz, flags, align
PT_LOAD = 1


def is_elf(path: Path) -> bool:
    try:
        with open(path, "rb") as f:
            return f.read(4) == ELF_MAGIC
    except OSError:
        return False


def check_image(path: Path) -> None:
    """Raise ImageError, saying what is wrong in one line, unless `path` is a whole 32-bit little-endian v850
    ELF whose loadable segments and section table lie inside the file."""
    try:
        data = path.read_bytes()
    except OSError as e:
        raise ImageError(f"{path}: {e.strerror}") from None
    if data[:4] != ELF_MAGIC:
        raise ImageError(f"{path}: not an ELF file (a v850 image is EV3RT's `asp`; build one with hako build)")
    if len(data) < 20:
        raise ImageError(f"{path}: truncated: {len(data)} bytes, shorter than an ELF header")
    machine = int.from_bytes(data[18:20], "little" if data[5] == ELFDATA2LSB else "big")
    if machine not in V850_MACHINES or data[4] != ELFCLASS32 or data[5] != ELFDATA2LSB:
        bits = {1: "32-bit", 2: "64-bit"}.get(data[4], "odd-class")
        name = MACHINE_NAMES.get(machine, f"e_machine {machine}")
        raise ImageError(f"{path}: a {bits} ELF for {name}, not a v850 image")
    if len(data) < _EHDR.size:
        raise ImageError(f"{path}: truncated: {len(data)} bytes, shorter than an ELF header")
    *_, phoff, shoff, _, _, phentsize, phnum, shentsize, shnum, _ = _EHDR.unpack_from(data)
    ends = [("its program headers", phoff + phentsize * phnum), ("its section headers", shoff + shentsize * shnum)]
    if phoff + phentsize * phnum <= len(data) and phentsize >= _PHDR.size:
        for i in range(phnum):
            kind, offset, _, _, filesz, *_ = _PHDR.unpack_from(data, phoff + i * phentsize)
            if kind == PT_LOAD:
                ends.append((f"segment {i}", offset + filesz))
    for what, end in ends:
        if end > len(data):
            raise ImageError(f"{path}: truncated: {what} end at byte {end}, the file has {len(data)}")
