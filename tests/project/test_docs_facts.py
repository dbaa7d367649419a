"""The facts docs/ restates from the code (slots, codes, levels, time constants, defaults, exit statuses),
checked against the code, so that a page cannot keep a number the code no longer has.

The code is the one source: each test reads a table or sentence of a page and compares it with the constant
it restates. A page that words a fact differently makes its pattern miss, which fails too ("no ... found"),
rather than passing over it. The byte offsets of `| Rx.NAME | offset |` rows are checked by
`tests/wire/test_protocol.py::test_the_docs_offset_tables_match_the_layout`.
"""

from __future__ import annotations

import dataclasses
import enum
import re
import tomllib
import typing
from pathlib import Path

import pytest
from click.testing import CliRunner

from hakoniwa.physics.course import course_file
from hakoniwa.physics.noise import DEFAULT_NOISE, NoiseLevels
from hakoniwa.wire import timebase
from hakoniwa.wire.exits import EXIT_BENCH_FAULT, EXIT_INTERRUPTED, EXIT_TERMINATED
from hakoniwa.wire.protocol import Event, Rx, Tx
from hakoniwa.wire.result import TestResult
from testctl.campaign.config import CampaignConfig
from tests.helpers.paths import REPO

DOCS = REPO / "docs"
DESIGN = DOCS / "DESIGN-NOTES.md"
_CELL_BAR = re.compile(r"(?<!\\)\|")  # a cell's `\|` is text, not a border
_UNITS_US = {"µs": 1, "us": 1, "ms": 1_000, "s": 1_000_000}


def tables(page: Path) -> list[tuple[list[str], list[list[str]]]]:
    """Every Markdown table of `page`: (header cells, body rows of cells)."""
    found: list[tuple[list[str], list[list[str]]]] = []
    block: list[list[str]] = []
    for line in [*page.read_text().splitlines(), ""]:
        if line.startswith("|"):
            block.append([c.strip() for c in _CELL_BAR.split(line.strip())[1:-1]])
        elif block:
            if len(block) > 2 and set("".join(block[1])) <= set("-: "):
                found.append((block[0], block[2:]))
            block = []
    return found


def table(page: Path, header: list[str]) -> list[list[str]]:
    rows = [body for head, body in tables(page) if head == header]
    assert len(rows) == 1, f"{page.name}: no single table headed {header}: the page or this test changed"
    return rows[0]


def names(cell: str) -> list[str]:
    """The slot names of a cell, `A_X` / `_Y` standing for A_X, A_Y."""
    out: list[str] = []
    for name in re.findall(r"`([A-Z_][A-Z0-9_]*)`", cell):
        out.append(out[-1].rsplit("_", 1)[0] + name if name.startswith("_") else name)
    return out


def extension_rows(side: str) -> list[tuple[list[int], list[str], str]]:
    """DESIGN-NOTES' tables headed `| RX |` or `| TX |`: (offsets, slot names, the row's text) per row."""
    rows = [(list(map(int, re.findall(r"\d+", row[0]))), names(" ".join(row[2:])), " ".join(row[2:]))
            for head, body in tables(DESIGN) if head[0] == side for row in body]
    assert rows, f"no `| {side} |` table in {DESIGN.name}"
    return rows


@pytest.mark.parametrize("side, layout", [("RX", Rx), ("TX", Tx)])
def test_the_slot_tables_name_each_slot_at_its_offset(side, layout):
    """Our extension and the SPIKE SDK's slots, as DESIGN-NOTES tabulates them, are where `Rx`/`Tx` put them."""
    wrong = [(offsets, slots) for offsets, slots, _ in extension_rows(side)
             if len(slots) != len(offsets) or [getattr(layout, n, None) for n in slots] != offsets]
    assert not wrong, f"{side} rows whose offsets are not their slots' (offsets, names): {wrong}"


@pytest.mark.parametrize("side, layout, low", [("RX", Rx, Rx.BUTTONS_UNTIL), ("TX", Tx, Tx.NEXT_WAKE)])
def test_every_slot_of_our_extension_is_in_the_tables(side, layout, low):
    """A slot added to our extension (below ET Robocon's, from the lowest one) must be documented too."""
    documented = {n for _, slots, _ in extension_rows(side) for n in slots}
    ours = {n for n, v in vars(layout).items() if n.isupper() and low <= v < 480}
    assert ours <= documented, f"{side} slots of our extension missing from {DESIGN.name}: {ours - documented}"


def test_the_result_table_names_every_field_and_code():
    """Each field of `TestResult` (what result.json carries) has its row, and a field that is an enum lists
    every name the enum has."""
    rows = {tuple(names_of(row[0])): row[2] for head, body in tables(DESIGN) if head[0] == "result.json"
            for row in body}
    documented = {name for key in rows for name in key}
    hints = typing.get_type_hints(TestResult)
    assert documented == {f.name for f in dataclasses.fields(TestResult)}
    for key, text in rows.items():
        for name in key:
            if isinstance(hints[name], type) and issubclass(hints[name], enum.Enum) and hints[name] is not Event:
                assert set(re.findall(r"\b[A-Z][A-Z_]+\b", text)) >= {c.name for c in hints[name]}, name


def names_of(cell: str) -> list[str]:
    return re.findall(r"`([a-z_]+)`", cell)


def test_the_noise_table_gives_the_default_levels():
    """NOISE.md's default column is `NoiseLevels`' defaults, key for key."""
    rows = table(DOCS / "NOISE.md", ["source", "what happens", "key", "default (oval)"])
    documented = {row[2].strip("`"): float(re.match(r"[\d.]+", row[3]).group()) for row in rows}
    assert documented == dataclasses.asdict(NoiseLevels())


def test_the_oval_course_writes_out_the_default_levels():
    """The oval's `[noise]` restates the defaults for a course author to copy; it must restate them all, exactly
    (it cannot simply drop them: the course folder's hash is in every oval campaign's journal)."""
    noise = tomllib.loads(course_file("oval").read_text())["noise"]
    assert noise == dataclasses.asdict(DEFAULT_NOISE)


def test_the_time_table_gives_the_timebase_constants():
    """DESIGN-NOTES' table of `timebase.` constants lists every one of them (`*_US`), at its value."""
    rows = table(DESIGN, ["`timebase.`", "value", "what"])
    documented = {}
    for row in rows:
        value, unit = re.fullmatch(r"([\d.]+) (µs|us|ms|s)", row[1]).groups()
        documented[row[0].strip("`")] = round(float(value) * _UNITS_US[unit])
    actual = {n: v for n, v in vars(timebase).items() if n.endswith("_US") and isinstance(v, int)}
    assert documented == actual


def test_the_docs_exit_statuses_are_the_code_s():
    """Where a page gives the status of an interrupted or a bench-faulted process, it is the code's."""
    ci = {int(row[0]): row[1] for row in table(DOCS / "CI.md", ["exit", "meaning"])}
    assert "Ctrl-C" in ci[EXIT_INTERRUPTED] and "SIGTERM" in ci[EXIT_TERMINATED]
    said = re.search(r"Ctrl-C exits (\d+) after that line, SIGTERM (\d+)", DESIGN.read_text())
    assert said is not None and tuple(map(int, said.groups())) == (EXIT_INTERRUPTED, EXIT_TERMINATED)
    native = re.findall(r"exit (\d+) \(EXIT_BENCH_FAULT\)", (DOCS / "NATIVE.md").read_text())
    assert native and set(map(int, native)) == {EXIT_BENCH_FAULT}


def test_the_docs_repetition_rule_is_the_default_one():
    """`first-to-3-of-5` (or `first to 3 of 5`) in a page is the default repetition rule."""
    rule = CampaignConfig().rule
    said = [(page.name, int(k), int(n)) for page in [*sorted(DOCS.glob("*.md")), REPO / "README.md"]
            for k, n in re.findall(r"first[- ]to[- ](\d+)[- ]of[- ](\d+)", page.read_text())]
    assert said, "no page states the repetition rule"
    assert {(k, n) for _, k, n in said} == {(rule.needed, rule.repeats)}, said


def test_the_campaign_help_gives_the_config_defaults():
    """`hako run --help` and `testctl campaign --help` show `CampaignConfig`'s defaults (they are formatted
    from it: this catches the help no longer being so)."""
    from testctl.cli import main as testctl
    from testctl.hako.main import main as hako

    d = CampaignConfig()
    shown = {"--trials": f"[{d.trials}]", "--init-points": f"[{d.init_points}]", "--repeats": f"[{d.repeats}]",
             "--seed": f"[{d.seed}]", "--optimizer": f"[{d.optimizer}]", "--batch": f"[{d.batch},",
             "--noise": f"[{d.noise:g}]"}
    for cli, args in ((hako, ["run", "--help"]), (testctl, ["campaign", "--help"])):
        text = " ".join(CliRunner().invoke(cli, args, terminal_width=10_000).output.split("Options:")[1].split())
        for option, default in shown.items():
            entry = text.split(f" {option} ", 1)[1].split(" --", 1)[0]  # up to the next option
            assert default in entry, (args, option, default, entry)
