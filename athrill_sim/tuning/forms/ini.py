"""`ini = { file = "tracer.ini", section = "pid", key = "kp" }`: the number a key's value starts with in an INI file
the program reads at run time (`[section]` headers, `key = value` or `key: value` lines; without `section`, a key
before the first header). Each test runs with a copy of the file holding its value, every other byte as it was;
best.patch changes the value in the user's file. It is a `row`'s sibling (`athrill_sim.tuning.forms.row`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from athrill_sim.tuning.command_files import Cell, ini_cell
from athrill_sim.tuning.forms.form import string_value
from athrill_sim.tuning.forms.row import CellForm


@dataclass(frozen=True)
class Ini(CellForm):
    key = "ini"
    example = '{ file = "tracer.ini", section = "pid", key = "kp" }'

    ini_key: str = ""
    section: str | None = None

    @classmethod
    def parse(cls, name: str, table: Mapping[str, Any]) -> Ini:
        spec = cls._table(name, table, {"file", "section", "key"}, {"file", "key"})
        if "section" in spec:
            string_value("section", name, spec)
        return cls(spec["file"], string_value("key", name, spec), spec.get("section"))

    def toml(self) -> dict[str, Any]:
        return {"ini": {"file": self.file, **({"section": self.section} if self.section is not None else {}),
                        "key": self.ini_key}}

    def describe(self) -> str:
        return f"ini {self.file} " + (f"[{self.section}] " if self.section is not None else "") + self.ini_key

    def cell(self, text: str) -> Cell:
        return ini_cell(text, self.file, key=self.ini_key, section=self.section)
