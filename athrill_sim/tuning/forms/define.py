"""`define = "KP"`: the program is built with `-DKP=value`, a build per value (cached here and on disk), so
the program must not `#define KP` itself without `#ifndef KP`. best.patch sets the value where the program's
files `#define` it (or its Makefile.inc's `-DKP=`)."""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from athrill_sim.programs.kinds.kind import REBUILD
from athrill_sim.tuning.elf_symbols import loaded_bytes
from athrill_sim.tuning.forms.form import Binding, BindingError, Edit, NamedForm, TunedProgram, file_text
from athrill_sim.tuning.forms.values import literal

TEXT_SUFFIXES = (".c", ".h", ".cpp", ".hpp", ".cc", ".hh", ".cxx", ".inc", ".cfg")


@dataclass(frozen=True)
class Define(NamedForm):
    """`target`: the macro."""

    key = "define"
    needs = REBUILD

    def check_built(self, b: Binding, program: TunedProgram) -> None:
        """The program built at the low end and at the high end must differ, or the value reaches nothing."""
        low = program.lows
        high = {**low, b.name: b.high if b.high != b.low else b.low + 1}
        images = [program.built(v).image for v in (low, high)]
        assert images[0] is not None and images[1] is not None
        if loaded_bytes(images[0]) == loaded_bytes(images[1]):
            texts = [program.texts(v)[b.name] for v in (low, high)]
            raise BindingError(f"define {self.target} has no effect: the program built with {self.target}={texts[0]} "
                               f"and with {self.target}={texts[1]} is the same (does it #define {self.target} without "
                               f"#ifndef {self.target}, or not use it?)")

    def build_flags(self, b: Binding, text: str) -> tuple[str, ...]:
        return (f"-D{self.target}={text}",)

    def shown(self, b: Binding, text: str) -> str:
        return f"{self.target}={text}"

    def edits(self, b: Binding, texts: dict[str, str], program: TunedProgram) -> tuple[list[Edit], list[str]]:
        text = texts[b.name]
        what = f"{b.name}={text}"
        found = list(self._sites(program.files))
        if not found:
            return [], [f"{what}: no file of the program defines {self.target}; build it with -D{self.target}={text}"]
        return [Edit(p, s, e, literal(old, text, b.integer), f"{what} (#define {self.target})")
                for p, s, e, old in found], []

    def _sites(self, files: Iterable[Path]) -> Iterable[tuple[Path, int, int, str]]:
        """The value of every `#define NAME value` in the program's files, and of -DNAME=value in Makefile.inc."""
        name = re.escape(self.target)
        define = re.compile(rf"^[ \t]*#[ \t]*define[ \t]+{name}[ \t]+(.*?)[ \t]*(?://.*|/\*.*)?$", re.MULTILINE)
        flag = re.compile(rf"-D{name}=(\S+)")
        for f in files:
            pattern = flag if f.name == "Makefile.inc" else define if f.suffix in TEXT_SUFFIXES else None
            if pattern is not None:
                text = file_text(f)
                for m in pattern.finditer(text):
                    yield f, m.start(1), m.end(1), m.group(1)
