"""`source = { file = "app/pid.h", match = "KP = (.*);" }`: the text the pattern's one group captures, matched
exactly once in one of the program's files, is replaced by the value in a scratch copy of the program, which
is built (a build per value, cached). best.patch replaces it in the user's file."""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from athrill_sim.programs.kinds.kind import REBUILD
from athrill_sim.tuning.forms.form import Binding, BindingError, Edit, Form, TunedProgram, file_text
from athrill_sim.tuning.forms.values import literal


@dataclass(frozen=True)
class Source(Form):
    key = "source"
    needs = REBUILD

    file: str  # relative to the program's folder
    match: str  # a regular expression whose one group is the value

    @classmethod
    def parse(cls, name: str, table: Mapping[str, Any]) -> Source:
        value = table[cls.key]
        if not isinstance(value, Mapping) or set(value) != {"file", "match"} or not all(
                isinstance(v, str) and v for v in value.values()):
            raise BindingError(f"{name!r}: source must be {{ file = \"app/pid.h\", match = \"KP = (.*);\" }}")
        return cls(value["file"], value["match"])

    def toml(self) -> dict[str, Any]:
        return {"source": {"file": self.file, "match": self.match}}

    def describe(self) -> str:
        return f"source {self.file} {self.match!r}"

    def files(self, root: Path) -> list[Path]:
        return [root / self.file]

    def check(self, b: Binding, program: TunedProgram) -> None:
        """Its match is found exactly once, and overlaps no earlier source parameter's."""
        path, start, end, _ = self.site(b, program)
        for x in program.bindings[:program.bindings.index(b)]:
            if isinstance(x.form, Source):
                p, s, e, _ = x.form.site(x, program)
                if p == path and s < end and start < e:
                    raise BindingError(f"{x.name!r} and {b.name!r} are two parameters on one target: their matches "
                                       f"overlap in {program.rel(path)}")

    def source_edit(self, b: Binding, text: str, program: TunedProgram) -> tuple[Path, int, int, str]:
        path, start, end, old = self.site(b, program)
        return path, start, end, literal(old, text, b.integer)

    def edits(self, b: Binding, texts: dict[str, str], program: TunedProgram) -> tuple[list[Edit], list[str]]:
        path, start, end, text = self.source_edit(b, texts[b.name], program)
        return [Edit(path, start, end, text, f"{b.name}={texts[b.name]} ({self.match})")], []

    def site(self, b: Binding, program: TunedProgram) -> tuple[Path, int, int, str]:
        """Where the one group of the match lies in its file: exactly one match, or an error with the lines."""
        path = program.inside(b, self.file)
        if not path.is_file():
            raise BindingError(f"{b.name!r}: source file {self.file} does not exist in {program.root}")
        try:
            pattern = re.compile(self.match, re.MULTILINE)
        except re.error as e:
            raise BindingError(f"{b.name!r}: match {self.match!r} is not a regular expression: {e}") from None
        if pattern.groups != 1:
            raise BindingError(f"{b.name!r}: match {self.match!r} must have exactly one group, (...), around the "
                               "value")
        text = file_text(path)
        found = list(pattern.finditer(text))
        if len(found) != 1:
            lines = "; ".join(f"line {text.count(chr(10), 0, m.start()) + 1}: {_line_at(text, m.start())!r}"
                              for m in found[:5])
            raise BindingError(f"{b.name!r}: match {self.match!r} matches {len(found)} times in {self.file}"
                               + (f" ({lines})" if found else "") + "; it must match exactly once")
        m = found[0]
        return path, m.start(1), m.end(1), m.group(1)


def _line_at(text: str, offset: int) -> str:
    start = text.rfind("\n", 0, offset) + 1
    end = text.find("\n", offset)
    return text[start:end if end >= 0 else len(text)].strip()
