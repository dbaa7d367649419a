"""docs/BENCHMARKS.md is its tables, each rendered from the data its benchmark recorded (scripts/benchmark_tables.py):
a table edited by hand, or data recorded and not rendered, fails here, and so does a line too long to read."""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import click
import pytest

from tests.helpers.paths import SCRIPTS


def load():
    spec = importlib.util.spec_from_file_location("benchmark_tables", SCRIPTS / "benchmark_tables.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["benchmark_tables"] = module
    spec.loader.exec_module(module)
    return module


benchmark_tables = load()


def test_every_table_is_what_its_data_renders():
    page = benchmark_tables.PAGE.read_text()
    assert benchmark_tables.refresh(page)[1] == []


def test_every_data_file_has_one_table_and_every_table_its_data():
    names = benchmark_tables.tables(benchmark_tables.PAGE.read_text())
    assert len(names) == len(set(names))
    assert sorted(names) == sorted(p.stem for p in benchmark_tables.DATA.glob("*.json"))


def test_every_table_says_how_where_and_when_it_was_measured():
    for path in sorted(benchmark_tables.DATA.glob("*.json")):
        data = json.loads(path.read_text())
        assert data["command"] and data["machine"], path.name
        assert len(data["date"]) == 10 and data["date"][4] == data["date"][7] == "-", path.name


def test_no_line_of_the_page_is_over_the_limit():
    long = [(n, len(line)) for n, line in enumerate(benchmark_tables.PAGE.read_text().splitlines(), 1)
            if len(line) > benchmark_tables.MAX_LINE]
    assert long == []


def table(data: dict, tmp_path: Path, name: str = "t") -> str:
    (tmp_path / f"{name}.json").write_text(json.dumps(data))
    return f"intro\n<!-- bench-table: {name} -->\nstale\n<!-- /bench-table -->\nmore\n"


DATA = {"command": "python scripts/bench_x.py", "machine": "2-core VM", "date": "2026-12-06", "columns": ["a", "b"],
        "rows": [["1", "x|y"]]}


def test_a_stale_table_is_caught_and_rewritten(tmp_path: Path):
    page = table(DATA, tmp_path)
    new, changed = benchmark_tables.refresh(page, tmp_path)
    assert changed == ["t"]
    assert new == ("intro\n<!-- bench-table: t -->\n`python scripts/bench_x.py` · 2-core VM · 2026-12-06\n\n"
                   "| a | b |\n| --- | --- |\n| 1 | x\\|y |\n<!-- /bench-table -->\nmore\n")
    assert benchmark_tables.refresh(new, tmp_path) == (new, [])


def test_a_recorded_output_is_shown_as_printed(tmp_path: Path):
    data = benchmark_tables.record("t", [sys.executable, "-c", "print('| n | s |'); print('| 3 | 0.5 |')"], tmp_path)
    assert data["output"] == ["| n | s |", "| 3 | 0.5 |"] and data["command"].startswith(sys.executable)
    new, _ = benchmark_tables.refresh(table(data, tmp_path), tmp_path)
    assert "```text\n| n | s |\n| 3 | 0.5 |\n```\n<!-- /bench-table -->" in new


@pytest.mark.parametrize("bad, words", [
    ({**DATA, "rows": [["1"]]}, "a row of 1 cells under 2 columns"),
    ({**DATA, "rows": [["1", "x" * 400]]}, "a line of"),
    ({k: v for k, v in DATA.items() if k != "date"}, "lacks 'date'"),
])
def test_data_that_cannot_be_a_table_is_one_line(tmp_path: Path, bad: dict, words: str):
    with pytest.raises(click.ClickException, match=words):
        benchmark_tables.refresh(table(bad, tmp_path), tmp_path)


def test_a_failed_benchmark_records_nothing(tmp_path: Path):
    with pytest.raises(click.ClickException, match="exited with 3"):
        benchmark_tables.record("t", [sys.executable, "-c", "raise SystemExit(3)"], tmp_path)
    assert not (tmp_path / "t.json").exists()
