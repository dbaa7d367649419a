"""`row = { file = "datafiles/LineTraceLeft.csv", key = "LineTrace", column = 5 }`: a number in a row of a command
file the program reads at run time, as ET Robocon teams keep a gain per section of the course (CSV rows, or
whitespace-separated ones). The row is the line whose first field is `key` (its `occurrence`-th such line), or
the `line`-th line; `column` counts its fields from 1 (`athrill_sim.tuning.command_files`). Each test runs with a
copy of the file whose cells hold the test's values, every other byte as it was, in the program's working folder
(`athrill_sim.programs.working_folder`: its SD card, the app folder's copy in it); best.patch changes those cells of
the user's file."""

from __future__ import annotations

from abc import abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

from athrill_sim.programs.kinds.kind import DATA_FILE
from athrill_sim.tuning.command_files import Cell, CellError, replace_cells, row_cell
from athrill_sim.tuning.forms.form import Binding, BindingError, Edit, Form, TunedProgram, file_text, string_value
from athrill_sim.tuning.forms.values import literal


@dataclass(frozen=True)
class CellForm(Form):
    """A form whose value is one number in a text file of the program's, found by `cell`."""

    needs = DATA_FILE  # the file lies on the program's SD card, in the app folder's copy there
    example: ClassVar[str]  # the form's table as the error messages show it

    file: str  # relative to the program's folder

    @classmethod
    def _table(cls, name: str, table: Mapping[str, Any], allowed: set[str], required: set[str]) -> Mapping[str, Any]:
        spec = table[cls.key]
        example = cls.example
        if not isinstance(spec, Mapping):
            raise BindingError(f"{name!r}: {cls.key} is a table, as {cls.key} = {example}")
        unknown = sorted(set(spec) - allowed)
        missing = sorted(required - set(spec))
        if unknown or missing:
            what = f"unknown key {unknown[0]}" if unknown else f"no {missing[0]}"
            raise BindingError(f"{name!r}: {cls.key} has {what}; write it as {cls.key} = {example}")
        string_value("file", name, spec)
        return spec

    @abstractmethod
    def cell(self, text: str) -> Cell:
        """The number's place in the file's `text` (CellError, one line naming the file and the row)."""

    def files(self, root: Path) -> list[Path]:
        return [root / self.file]

    def check(self, b: Binding, program: TunedProgram) -> None:
        """The file is the program's, the cell is there and a number, and no other parameter is on it."""
        if not (program.root / "app.cfg").is_file() and not (program.root / "Makefile.inc").is_file():
            raise BindingError(f"{b.name!r}: {self.key} parameters reach a program run from its folder (app.cfg or "
                               f"Makefile.inc beside its sources), whose files are copied for each test")
        self._cells(program)

    def data_file(self, b: Binding, texts: dict[str, str], program: TunedProgram) -> tuple[str, str] | None:
        """The file with every cell of it set, once: by the first parameter in it. It lies in the app folder,
        which is in the working folder under its own name."""
        group = self._cells(program)
        if group[0][0] != b:
            return None
        text = file_text(self._path(program))
        return (f"{program.root.name}/{self.file}",
                replace_cells(text, [(cell, literal(cell.text, texts[x.name], x.integer)) for x, cell in group]))

    def edits(self, b: Binding, texts: dict[str, str], program: TunedProgram) -> tuple[list[Edit], list[str]]:
        cell = dict(self._cells(program))[b]
        text = literal(cell.text, texts[b.name], b.integer)
        return [Edit(self._path(program), cell.start, cell.end, text, f"{b.name}={text} ({cell.where})")], []

    def _path(self, program: TunedProgram) -> Path:
        return (program.root / self.file).resolve()

    def _cells(self, program: TunedProgram) -> list[tuple[Binding, Cell]]:
        """Every cell form's parameter in this file with its cell, checked: found, and one parameter a cell."""
        def found() -> list[tuple[Binding, Cell]]:
            out = []
            for x in program.bindings:
                if isinstance(x.form, CellForm) and x.form.file == self.file:
                    path = program.inside(x, self.file)
                    if not path.is_file():
                        raise BindingError(f"{x.name!r}: {self.file} does not exist in {program.root}")
                    try:
                        out.append((x, x.form.cell(file_text(path))))
                    except CellError as e:
                        raise BindingError(f"{x.name!r}: {e}") from None
            taken: dict[int, Binding] = {}
            for x, cell in out:
                if cell.start in taken:
                    raise BindingError(f"{taken[cell.start].name!r} and {x.name!r} are two parameters on one cell "
                                       f"({cell.where})")
                taken[cell.start] = x
            return out

        return program.remember(("cells", self.file), found)


@dataclass(frozen=True)
class Row(CellForm):
    key = "row"
    example = '{ file = "datafiles/LineTraceLeft.csv", key = "LineTrace", column = 5 }'

    row_key: str | None = None  # the row's first field
    line: int | None = None  # or its line number, from 1
    column: int = 1
    occurrence: int = 1

    @classmethod
    def parse(cls, name: str, table: Mapping[str, Any]) -> Row:
        spec = cls._table(name, table, {"file", "key", "line", "column", "occurrence"}, {"file", "column"})
        numbers = {k: spec[k] for k in ("line", "column", "occurrence") if k in spec}
        if any(isinstance(v, bool) or not isinstance(v, int) or v < 1 for v in numbers.values()):
            raise BindingError(f"{name!r}: row's line, column and occurrence are whole numbers from 1")
        if ("key" in spec) == ("line" in spec):
            raise BindingError(f"{name!r}: a row is found by its key (its first field) or by its line number: give "
                               "one of key and line")
        if "key" in spec:
            string_value("key", name, spec)
        elif "occurrence" in spec:
            raise BindingError(f"{name!r}: occurrence counts the rows of one key; a line number needs none")
        return cls(spec["file"], spec.get("key"), spec.get("line"), spec["column"], spec.get("occurrence", 1))

    def toml(self) -> dict[str, Any]:
        spec: dict[str, Any] = {"file": self.file}
        spec.update({"key": self.row_key} if self.row_key is not None else {"line": self.line})
        spec["column"] = self.column
        if self.occurrence != 1:
            spec["occurrence"] = self.occurrence
        return {"row": spec}

    def describe(self) -> str:
        row = f"line {self.line}" if self.row_key is None else self.row_key
        nth = f" #{self.occurrence}" if self.occurrence != 1 else ""
        return f"row {self.file} {row}{nth} column {self.column}"

    def cell(self, text: str) -> Cell:
        return row_cell(text, self.file, key=self.row_key, line=self.line, column=self.column,
                        occurrence=self.occurrence)
