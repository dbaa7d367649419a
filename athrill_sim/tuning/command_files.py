"""The cells of the command files teams keep their gains in, found as a person reading the file finds them.

ET Robocon teams drive each section of the course from a row of a command file, e.g. a CSV row
`LineTrace,S001,500.0,0,0.03,0.001,0.008` or a whitespace-separated one `LineTracer 6000 20 50 50 LEFT_EDGE 1.3
0 0.013 BLUE`, or keep them in an INI file (`[pid]` then `kp = 0.8`). A `row` or `ini` parameter names one
such cell; what is found here is its place in the file's text, so that a test or `best.patch` replaces those
characters and leaves every other byte of the file as it was.

A row is the line whose first field is `key` (its `occurrence`-th such line), or the `line`-th line. Its fields
are separated by commas when the line has one (a comma inside double quotes does not separate), else by runs
of whitespace; `column` counts them from 1. A cell is its field without the whitespace (and double quotes)
around it, and must be a number as C reads one (`strtod`, `atof`: `12`, `-0.5`, `1e-3`, `.5`, `2.0f`).
An INI key is looked up in its `[section]` (or before the first section when none is given), on a line
`key = value` or `key: value`; its cell is the number the value starts with (a comment may follow it).
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass

from hakoniwa.wire.errors import HakoError

NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?[fFlL]?")
_INI_VALUE_END = re.compile(r"\s|[;#]")


class CellError(HakoError, ValueError):
    """A cell cannot be found, or is no number; the message names the file and the row."""


@dataclass(frozen=True)
class Cell:
    """A number's characters in a file's text: text[start:end]."""

    start: int
    end: int
    text: str
    where: str  # how a person finds it: "datafiles/LineTraceLeft.csv line 4, column 5"


def lines(text: str) -> Iterator[tuple[int, str]]:
    """(offset, line without its line ending) for each line of `text`."""
    at = 0
    for raw in text.splitlines(keepends=True):
        yield at, raw.rstrip("\r\n")
        at += len(raw)


def fields(line: str) -> list[tuple[int, int]]:
    """The (start, end) of each field of a row: comma-separated when the line has a comma outside quotes,
    else whitespace-separated."""
    commas = _unquoted_commas(line)
    if commas:
        bounds = [-1, *commas, len(line)]
        return [(bounds[i] + 1, bounds[i + 1]) for i in range(len(bounds) - 1)]
    return [(m.start(), m.end()) for m in re.finditer(r"\S+", line)]


def _unquoted_commas(line: str) -> list[int]:
    found, quoted = [], False
    for i, c in enumerate(line):
        if c == '"':
            quoted = not quoted
        elif c == "," and not quoted:
            found.append(i)
    return found


def _field_text(line: str, start: int, end: int) -> tuple[int, int]:
    """A field's characters without the whitespace and the double quotes around it."""
    start, end = _strip(line, start, end)
    if end - start >= 2 and line[start] == '"' and line[end - 1] == '"':
        start, end = _strip(line, start + 1, end - 1)
    return start, end


def _strip(line: str, start: int, end: int) -> tuple[int, int]:
    while start < end and line[start].isspace():
        start += 1
    while end > start and line[end - 1].isspace():
        end -= 1
    return start, end


def row_cell(text: str, name: str, *, column: int, key: str | None = None, line: int | None = None,
             occurrence: int = 1) -> Cell:
    """The number in `column` of a row of `text` (the file `name`): the `occurrence`-th line whose first field
    is `key`, or line number `line`."""
    if (key is None) == (line is None):
        raise CellError(f"{name}: a row is found by its key or by its line number, one of the two")
    if column < 1:
        raise CellError(f"{name}: column {column}: columns count from 1")
    if key is not None:
        if occurrence < 1:
            raise CellError(f"{name}: occurrence {occurrence}: occurrences count from 1")
        rows = [(n, at, ln) for n, (at, ln) in enumerate(lines(text), 1)
                if (f := fields(ln)) and ln[slice(*_field_text(ln, *f[0]))] == key]
        if len(rows) < occurrence:
            raise CellError(f"{name}: no line whose first field is {key}" if not rows else
                            f"{name}: occurrence {occurrence} of {key}: the file has {len(rows)} such line"
                            + ("s" if len(rows) > 1 else ""))
        number, at, row = rows[occurrence - 1]
        where = f"{name} line {number} ({key}" + (f", occurrence {occurrence})" if occurrence > 1 else ")")
    else:
        assert line is not None
        all_lines = list(lines(text))
        if not 1 <= line <= len(all_lines):
            raise CellError(f"{name}: line {line}: the file has {len(all_lines)} lines")
        number, (at, row) = line, all_lines[line - 1]
        where = f"{name} line {number}"
    spans = fields(row)
    if column > len(spans):
        raise CellError(f"{where}, column {column} is past the end of the row, which has {len(spans)} fields")
    start, end = _field_text(row, *spans[column - 1])
    return _number(text, at + start, at + end, f"{where}, column {column}")


def ini_cell(text: str, name: str, *, key: str, section: str | None = None) -> Cell:
    """The number the value of `key` in `[section]` starts with (before any section when `section` is None)."""
    current: str | None = None
    sections: list[str] = []
    for number, (at, line) in enumerate(lines(text), 1):
        stripped = line.strip()
        if stripped.startswith("[") and stripped.endswith("]"):
            current = stripped[1:-1].strip()
            sections.append(current)
            continue
        if not stripped or stripped[0] in ";#" or current != section:
            continue
        split = min((i for i in (line.find("="), line.find(":")) if i >= 0), default=-1)
        if split < 0 or line[:split].strip() != key:
            continue
        start = split + 1
        while start < len(line) and line[start] in " \t":
            start += 1
        end = _INI_VALUE_END.search(line, start)
        where = f"{name} line {number} ({'[' + section + '] ' if section else ''}{key})"
        return _number(text, at + start, at + (end.start() if end else len(line)), where)
    if section is not None and section not in sections:
        have = ", ".join(f"[{s}]" for s in dict.fromkeys(sections)) or "none"
        raise CellError(f"{name}: no section [{section}] (its sections: {have})")
    place = f"in section [{section}]" if section is not None else "before the first section"
    raise CellError(f"{name}: no key {key} {place}")


def _number(text: str, start: int, end: int, where: str) -> Cell:
    cell = text[start:end]
    if not NUMBER.fullmatch(cell):
        raise CellError(f"{where} is {cell!r}, not a number")
    return Cell(start, end, cell, where)


def replace_cells(text: str, values: list[tuple[Cell, str]]) -> str:
    """`text` with each cell's characters replaced by its new text; every other character as it was."""
    out, at = [], 0
    for cell, new in sorted(values, key=lambda v: v[0].start):
        if cell.start < at:
            raise CellError(f"{cell.where}: two parameters on one cell")
        out += [text[at:cell.start], new]
        at = cell.end
    return "".join([*out, text[at:]])
