"""`symbol = "g_kp"`: the value is a global's initial value, set in a copy of the built image
(`athrill_sim.tuning.elf_symbols`): no build per value. The global must be a writable scalar the program reads, of a
type the parameter's values fit. best.patch sets the initializer on the global's definition."""

from __future__ import annotations

import re
import struct
from dataclasses import dataclass, replace
from pathlib import Path

from athrill_sim.programs.kinds.kind import IMAGE
from athrill_sim.tuning.elf_symbols import Global, find_global
from athrill_sim.tuning.forms.form import Binding, BindingError, Edit, NamedForm, TunedProgram, file_text
from athrill_sim.tuning.forms.values import literal, typed_value
from hakoniwa.wire.params import FLOAT_TYPES, SLOT_FORMATS, int_range


@dataclass(frozen=True)
class Symbol(NamedForm):
    """`target`: the global's name (a C++ one qualified: `tuning::kp`)."""

    key = "symbol"
    needs = IMAGE

    def image_patch(self, b: Binding, value: float, image: Path, program: TunedProgram) -> tuple[int, bytes]:
        g = self._global(b, image, program)
        assert g.storage is not None
        return g.file_offset, struct.pack("<" + SLOT_FORMATS[g.storage], typed_value(value, g.storage))

    def edits(self, b: Binding, texts: dict[str, str], program: TunedProgram) -> tuple[list[Edit], list[str]]:
        what = f"{b.name}={texts[b.name]}"
        site = self._initializer(b, program)
        if site is None:
            return [], [f"{what}: the definition of {self.target} (TYPE {self.target} = VALUE;) was not found in the "
                        "program's files; set it there by hand"]
        path, start, end, old = site
        return [Edit(path, start, end, literal(old, texts[b.name], b.integer), f"{what} (global {self.target})")], []

    def _global(self, b: Binding, image: Path, program: TunedProgram) -> Global:
        """The global in `image`, checked: writable, read by the program, of a type the values fit."""
        return program.remember((self.key, image, self.target), lambda: _with_storage(
            find_global(image, self.target, need_reads=program.kind.finds_reads), b, self.target))

    def _initializer(self, b: Binding, program: TunedProgram) -> tuple[Path, int, int, str] | None:
        """Where the global's initial value is written in the program's sources: on its definition's line
        (from the debug information), `NAME = VALUE` or `NAME{VALUE}`."""
        image = program.variant(program.lows).image
        assert image is not None
        g = self._global(b, image, program)
        short = re.escape(self.target.rpartition("::")[2])
        pattern = re.compile(rf"\b{short}\s*(?:\[[^\]]*\]\s*)?(?:=\s*([^;,{{}}]+?)|\{{\s*([^;{{}}]+?)\s*\}})\s*[;,]")
        candidates = [f for f in program.files if f.name == g.decl_file] if g.decl_file else []
        for f in candidates:
            text = file_text(f)
            lines = text.split("\n")
            if g.decl_line is None or g.decl_line > len(lines):
                continue
            start = sum(len(line) + 1 for line in lines[:g.decl_line - 1])
            m = pattern.search(text, start)
            if m is not None and text.count("\n", start, m.start()) <= 2:
                group = 1 if m.group(1) is not None else 2
                return f, m.start(group), m.end(group), m.group(group)
        return None


def _with_storage(g: Global, b: Binding, symbol: str) -> Global:
    """The global with the storage type the parameter is written as: its debug information's, which a type
    in the space must agree with, or the space's where the image has none."""
    given = b.type if b.type not in ("float", "int") else None
    storage = g.storage or given
    if storage is None:
        raise BindingError(f"symbol {symbol}: the image has no debug information to say its type; give it: "
                           'type = "f32" (float), "f64" (double), "i32" (int), ...')
    if given is not None and given != storage:
        raise BindingError(f"symbol {symbol} is {storage} in the program, but the space says type = {given!r}")
    if storage in FLOAT_TYPES and b.integer:
        raise BindingError(f"symbol {symbol} is a {storage} float, but {b.name!r} is an integer parameter: "
                           'drop type = "int"')
    if storage not in FLOAT_TYPES:
        if not b.integer:
            raise BindingError(f"symbol {symbol} is an integer ({storage}): make {b.name!r} an integer "
                               'parameter (type = "int")')
        lo, hi = int_range(storage)
        if not (lo <= b.low and b.high <= hi):
            raise BindingError(f"{b.name!r}: {b.low:g}..{b.high:g} does not fit symbol {symbol} ({storage}: "
                               f"{lo}..{hi})")
    if g.size and g.size != struct.calcsize(SLOT_FORMATS[storage]):
        raise BindingError(f"symbol {symbol} is {g.size} bytes, not one {storage}: tune a scalar global")
    return replace(g, storage=storage)
