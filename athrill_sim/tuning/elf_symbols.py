"""A program's globals in its ELF image: where a global's initial value lies, what type it is, whether the
program reads it at run time at all, and a copy of the image with new initial values.

The same for both programs the bench runs: the native Athrill (an x86-64 PIE) and a v850 image for the real
emulator. A global's initial value is in its section's bytes in the file (`.data`; the loader maps them, or
EV3RT's start-up copies them into RAM), so setting it there sets it before the first instruction of the
program runs, C++ static constructors included. Types come from the debug information (DWARF: native tuned
builds get `-g`, EV3RT builds its images with it), or from the space file where an image has none.

"Is it read at run time": a `const` or a `static` nothing writes is folded into the code by the compiler, and
setting its bytes would change nothing. The native tuned build keeps its link-time relocations
(`--emit-relocs`), so a global that no relocation of the code or data refers to is one nothing reads.
"""

from __future__ import annotations

import shutil
import subprocess
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

from elftools.common.exceptions import ELFError
from elftools.dwarf.compileunit import CompileUnit
from elftools.dwarf.die import DIE
from elftools.elf.elffile import ELFFile
from elftools.elf.relocation import RelocationSection
from elftools.elf.sections import Symbol, SymbolTableSection

from athrill_sim.tuning.forms.form import BindingError

V850_MACHINES = ("EM_V800", "EM_V850", 0x9080)  # pyelftools' names of athrill_sim.v850.elf's machines

SHF_WRITE, SHF_ALLOC = 0x1, 0x2
DEBUG_SUFFIX = ".debug"  # athrill_sim.v850.build's DEBUG_IMAGE is IMAGE + this
# What a relocation against a section symbol reaches, S + A + one of these: an absolute one S + A; an x86-64
# RIP-relative one the end of its instruction, after the 4-byte displacement and up to 4 bytes of immediate.
_X86_64_PC_RELATIVE = (2, 4, 9, 24, 41, 42)  # R_X86_64_PC32, PLT32, GOTPCREL, PC64, GOTPCRELX, REX_GOTPCRELX
_PC_REACH: tuple[int, ...] = (4, 5, 6, 8)
_ABSOLUTE_REACH: tuple[int, ...] = (0,)
_ANY_REACH = (*_ABSOLUTE_REACH, *_PC_REACH)
_NUMBER_ENCODINGS = {0x04: "f", 0x05: "i", 0x06: "i", 0x07: "u", 0x08: "u", 0x02: "u"}  # DW_ATE_*: float,
# signed, signed char, unsigned, unsigned char, boolean
FOLD_FIX = "make it a non-const global, e.g. float g_kp = 0.8f;"


@dataclass(frozen=True)
class Global:
    """A global variable the bench can set: where its initial bytes are in the file, and its type."""

    name: str
    address: int
    size: int
    file_offset: int
    storage: str | None  # f32, f64, i8 .. u64 from the debug information; None without it
    decl_file: str | None  # the file name (no folders) and line of its definition, from the debug information
    decl_line: int | None


def find_global(image: Path, name: str, *, need_reads: bool) -> Global:
    """The global `name` of `image` (C++: its qualified name, `ns::Pid::kp`), or a BindingError saying why it
    cannot be set, with the fix. `need_reads`: refuse one no relocation refers to (the image kept them). The
    types come from the image's debug information, or from the unstripped copy beside a C++ image that `hako
    build` stripped of it (`asp.debug`)."""
    debug = image.with_name(image.name + DEBUG_SUFFIX)
    with open(image, "rb") as f, open(debug if debug.is_file() else image, "rb") as d:
        try:
            elf, typed = ELFFile(f), ELFFile(d)
        except ELFError as e:
            raise BindingError(f"symbol {name}: {image} is not an ELF image: {e}") from None
        symtab = elf.get_section_by_name(".symtab")
        if not isinstance(symtab, SymbolTableSection):
            raise BindingError(f"symbol {name}: {image} has no symbol table (stripped?); build it without -s")
        variables = _variables(typed) if typed.has_dwarf_info() else {}
        prefix = "_" if elf.header["e_machine"] in V850_MACHINES else ""  # the v850 ABI's C names begin with _
        found = [(i, s) for i, s in _named(symtab, name, prefix)
                 if s["st_info"]["type"] in ("STT_OBJECT", "STT_NOTYPE")]
        if not found:
            if name in variables:
                raise BindingError(f"symbol {name}: the compiler folded every use of it into the code (a const, "
                                   f"or a static nothing writes), so setting it would change nothing: {FOLD_FIX}")
            raise BindingError(f"symbol {name}: the program has no global variable of that name (give a global's "
                               "name as the program spells it; C++: its qualified name, ns::Class::member)")
        if len(found) > 1:
            raise BindingError(f"symbol {name}: {len(found)} globals of that name (statics of several files): "
                               "rename one, or make the one to tune a global of its own name")
        index, sym = found[0]
        section = elf.get_section(sym["st_shndx"]) if isinstance(sym["st_shndx"], int) else None
        if section is None:
            raise BindingError(f"symbol {name}: not defined in the program (an undefined or absolute symbol)")
        where = f"symbol {name}: in {section.name}"
        if not section["sh_flags"] & SHF_ALLOC or not section["sh_flags"] & SHF_WRITE:
            raise BindingError(f"{where}, read-only data (a const?), which the compiler may fold into the "
                               f"code: {FOLD_FIX}")
        if section["sh_type"] == "SHT_NOBITS":
            raise BindingError(f"{where}, zero-filled at start-up, so it has no initial value to set: give it "
                               f"an initializer (float {name.rpartition(':')[2]} = 0.8f;), which each test "
                               "then sets")
        die = variables.get(name)
        if die is not None and _is_const(die):
            raise BindingError(f"symbol {name}: it is const, so the compiler may fold it into the code: {FOLD_FIX}")
        if need_reads and not _referenced(elf, symtab, index, sym):
            raise BindingError(f"symbol {name}: nothing in the program reads it (no instruction or data refers "
                               "to it): tune a global the program uses")
        storage, decl = (_storage(die), _decl(typed, die)) if die is not None else (None, (None, None))
        return Global(name, sym["st_value"], sym["st_size"],
                      section["sh_offset"] + sym["st_value"] - section["sh_addr"], storage, *decl)


def patched_copy(image: Path, values: dict[int, bytes], out: Path) -> None:
    """`image` copied to `out` with `values` ({file offset: bytes}) written into it."""
    data = bytearray(image.read_bytes())
    for offset, raw in values.items():
        data[offset:offset + len(raw)] = raw
    out.write_bytes(bytes(data))


BUILD_ID = ".note.gnu.build-id"


def loaded_bytes(image: Path) -> bytes:
    """Everything the loader maps of `image` (its allocated sections), in order: two builds that agree here
    run alike, whatever their symbol tables, build paths or debug information say. The build ID is left out:
    a hash of the whole output, debug information and recorded compiler switches included (Debian's
    aarch64 linker writes one), it tells builds apart, not programs."""
    with open(image, "rb") as f:
        elf = ELFFile(f)
        return b"".join(s.name.encode() + b"\0" + (s.data() if s["sh_type"] != "SHT_NOBITS" else b"")
                        for s in elf.iter_sections() if s["sh_flags"] & SHF_ALLOC and s.name != BUILD_ID)


def _named(symtab: SymbolTableSection, name: str, prefix: str) -> list[tuple[int, Symbol]]:
    """The symbols spelt `name` (after the target's `prefix`), or, for a C++ name, those whose mangled name
    demangles to it."""
    spelt = [(i, s, s.name.removeprefix(prefix)) for i, s in enumerate(symtab.iter_symbols())
             if s.name.startswith(prefix)]
    direct = [(i, s) for i, s, plain in spelt if plain == name]
    if direct or "::" not in name:
        return direct
    mangled = [(i, s, plain) for i, s, plain in spelt if plain.startswith("_Z")]
    names = demangle([plain for _, _, plain in mangled])
    return [(i, s) for i, s, plain in mangled if names.get(plain) == name]


def demangle(names: Iterable[str]) -> dict[str, str]:
    """{mangled: demangled} by c++filt (binutils; the Itanium ABI is the same for every target)."""
    names = list(dict.fromkeys(names))
    tool = shutil.which("c++filt")
    if not names or tool is None:
        return {}
    out = subprocess.run([tool], input="\n".join(names) + "\n", capture_output=True, text=True, timeout=60).stdout
    return dict(zip(names, out.splitlines()))


def _referenced(elf: ELFFile, symtab: SymbolTableSection, index: int, sym) -> bool:
    start, end = sym["st_value"], sym["st_value"] + max(sym["st_size"], 1)
    for section in elf.iter_sections():
        if not isinstance(section, RelocationSection) or not section["sh_info"]:
            continue
        target = elf.get_section(section["sh_info"])
        if not target["sh_flags"] & SHF_ALLOC:  # debug information refers to every variable
            continue
        for r in section.iter_relocations():
            if r["r_info_sym"] == index:
                return True
            s = symtab.get_symbol(r["r_info_sym"])
            if s["st_info"]["type"] == "STT_SECTION" and s["st_shndx"] == sym["st_shndx"]:
                base = s["st_value"] + r.entry.get("r_addend", 0)
                if elf.header["e_machine"] == "EM_X86_64":
                    reach = _PC_REACH if r["r_info_type"] in _X86_64_PC_RELATIVE else _ABSOLUTE_REACH
                else:
                    reach = _ANY_REACH
                if any(start <= base + d < end for d in reach):
                    return True
    return False


def _variables(elf: ELFFile) -> dict[str, DIE]:
    """{qualified name: DIE}, the DIE that defines a variable winning over those that only declare it
    (`extern float g_kp;` in a header every file includes)."""
    out: dict[str, DIE] = {}
    for name, die in _dwarf_variables(elf):
        if name not in out or "DW_AT_declaration" in out[name].attributes:
            out[name] = die
    return out


def _dwarf_variables(elf: ELFFile) -> Iterator[tuple[str, DIE]]:
    """(qualified name, DIE) of every variable at file or namespace scope, C++ static members by the DIE that
    defines them."""
    for cu in elf.get_dwarf_info(relocate_dwarf_sections=False).iter_CUs():
        yield from _scope(cu.get_top_DIE(), "")


def _scope(parent: DIE, prefix: str) -> Iterator[tuple[str, DIE]]:
    for die in parent.iter_children():
        if die.tag == "DW_TAG_variable":
            spec = die.get_DIE_from_attribute("DW_AT_specification") if "DW_AT_specification" in die.attributes \
                else None
            named = spec if spec is not None else die
            if "DW_AT_name" in named.attributes:
                yield _qualified(named, prefix if spec is None else None), die
        elif die.tag in ("DW_TAG_namespace", "DW_TAG_structure_type", "DW_TAG_class_type"):
            if "DW_AT_name" in die.attributes:
                yield from _scope(die, f"{prefix}{die.attributes['DW_AT_name'].value.decode()}::")


def _qualified(die: DIE, prefix: str | None) -> str:
    name = die.attributes["DW_AT_name"].value.decode()
    if prefix is not None:
        return prefix + name
    parts, parent = [name], die.get_parent()
    while parent is not None and parent.tag != "DW_TAG_compile_unit":
        if "DW_AT_name" in parent.attributes:
            parts.append(parent.attributes["DW_AT_name"].value.decode())
        parent = parent.get_parent()
    return "::".join(reversed(parts))


def _type_chain(die: DIE) -> Iterator[DIE]:
    """The variable's type and what it is made of: typedefs and qualifiers down to a base type."""
    if "DW_AT_type" not in die.attributes and "DW_AT_specification" in die.attributes:
        die = die.get_DIE_from_attribute("DW_AT_specification")
    while "DW_AT_type" in die.attributes:
        die = die.get_DIE_from_attribute("DW_AT_type")
        yield die


def _is_const(die: DIE) -> bool:
    for t in _type_chain(die):
        if t.tag == "DW_TAG_const_type":
            return True
        if t.tag not in ("DW_TAG_typedef", "DW_TAG_volatile_type"):
            return False
    return False


def _storage(die: DIE) -> str | None:
    """f32, f64, i8 .. u64, or None for what is not a number (a struct, an array, a pointer)."""
    for t in _type_chain(die):
        if t.tag in ("DW_TAG_base_type", "DW_TAG_enumeration_type"):
            size = t.attributes["DW_AT_byte_size"].value
            kind = "i" if t.tag == "DW_TAG_enumeration_type" else _NUMBER_ENCODINGS.get(
                t.attributes["DW_AT_encoding"].value) if "DW_AT_encoding" in t.attributes else None
            if kind is None or (kind == "f" and size not in (4, 8)) or size not in (1, 2, 4, 8):
                return None
            return f"{kind}{8 * size}"
        if t.tag not in ("DW_TAG_typedef", "DW_TAG_volatile_type", "DW_TAG_const_type"):
            return None
    return None


def _decl(elf: ELFFile, die: DIE) -> tuple[str | None, int | None]:
    """The file name and line of the definition; what it does not say is the declaration's (a definition
    after `extern float g_kp;` in the same file names only its line)."""
    spec = die.get_DIE_from_attribute("DW_AT_specification") if "DW_AT_specification" in die.attributes else die
    file_die = die if "DW_AT_decl_file" in die.attributes else spec
    line_die = die if "DW_AT_decl_line" in die.attributes else spec
    if "DW_AT_decl_file" not in file_die.attributes or "DW_AT_decl_line" not in line_die.attributes:
        return None, None
    line = line_die.attributes["DW_AT_decl_line"].value
    cu = file_die.cu
    lines = (elf.get_dwarf_info(relocate_dwarf_sections=False).line_program_for_CU(cu)
             if isinstance(cu, CompileUnit) else None)  # variables come from compile units; a type unit has none
    if lines is None:
        return None, line
    index = file_die.attributes["DW_AT_decl_file"].value
    entries = lines["file_entry"]
    i = index if lines.header["version"] >= 5 else index - 1
    return (Path(entries[i].name.decode()).name if 0 <= i < len(entries) else None), line
