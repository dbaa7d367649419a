"""docs/GLOSSARY.md against the code: each word names one thing (issue 47). The names the glossary gives exist;
"trial" names code only where it is Optuna's trial, a set the search proposes; and a module named for a word
holds what the word means."""

from __future__ import annotations

import ast
import importlib
import re
from pathlib import Path

import pytest

from tests.helpers.paths import REPO

GLOSSARY = REPO / "docs" / "GLOSSARY.md"
PACKAGES = ("hakoniwa", "athrill_sim", "testctl", "maze")


def rows() -> dict[str, list[str]]:
    """{word: its row's cells}, from the glossary's table."""
    out = {}
    for line in GLOSSARY.read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("| ") and len(cells) == 4 and cells[0] not in ("word", "---"):
            out[cells[0]] = cells
    assert out, f"no table in {GLOSSARY.name}"
    return out


def python_files() -> list[Path]:
    return sorted(p for package in PACKAGES for p in (REPO / package).rglob("*.py"))


def names_in(path: Path) -> set[str]:
    """The names a module gives things: classes, functions, arguments, variables and attributes it assigns."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            found.add(node.name)
        elif isinstance(node, ast.arg):
            found.add(node.arg)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            found.add(node.id)
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
            found.add(node.attr)
    return found


@pytest.mark.parametrize("word", list(rows()))
def test_the_names_the_glossary_gives_exist(word):
    for name in re.findall(r"`([a-z_]+(?:\.[A-Za-z_]+)+)`", rows()[word][2]):
        parts = name.split(".")
        for cut in range(len(parts), 0, -1):
            try:
                target = importlib.import_module(".".join(parts[:cut]))
                break
            except ModuleNotFoundError:
                continue
        for attribute in parts[cut:]:
            assert hasattr(target, attribute), f"{word}: {name} does not exist"
            target = getattr(target, attribute)


@pytest.mark.parametrize("word", [w for w, cells in rows().items() if cells[3]])
def test_a_word_names_code_only_where_the_glossary_says(word):
    homes = re.findall(r"`([\w/.]+)`", rows()[word][3])
    token = re.compile(rf"(^|_){word}s?($|_)|{word.capitalize()}")
    strays = []
    for path in python_files():
        where = path.relative_to(REPO).as_posix()
        if any(where == home or (home.endswith("/") and where.startswith(home)) for home in homes):
            continue
        strays += [f"{where}: {name}" for name in sorted(names_in(path)) if token.search(name)]
    assert strays == [], f"'{word}' names code outside {homes}"


def test_a_module_named_for_objective_holds_an_objective():
    """testctl/campaign/objective.py once held the repetition rule."""
    named = [p.relative_to(REPO).as_posix() for p in python_files() if "objective" in p.name]
    assert all(p.startswith("hakoniwa/objectives/") or p == "hakoniwa/wire/objective.py" for p in named), named


def test_hako_trial_still_runs_hidden_and_deprecated():
    """What `hako try` was called before the glossary: a team's scripts keep working, and are told."""
    import click

    from testctl.hako.main import main

    ctx = click.Context(main)
    shown = [n for n in main.list_commands(ctx) if not main.get_command(ctx, n).hidden]
    old = main.get_command(ctx, "trial")
    assert "try" in shown and "trial" not in shown
    assert old.callback is main.get_command(ctx, "try").callback and "hako try" in str(old.deprecated)


def test_a_script_that_measures_is_named_a_benchmark():
    """A bench is a physics process and its program; a script that prints numbers is a benchmark."""
    assert sorted(p.name for p in (REPO / "scripts").glob("bench_*.py")) == []
