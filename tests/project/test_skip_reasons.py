"""Every test that skips for want of a piece of ../shared says where a user without ../shared gets it, and the
README and docs/REAL-ATHRILL.md name the same repositories and commits as `athrill_sim.programs.third_party`, the one
table of them."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from athrill_sim.programs.third_party import PIECES, Piece
from tests.helpers.paths import DOCS, REPO, TESTS, needs_shared

SHARED_WORD = "../" + "shared"  # spelt so that this file's own strings are not what it looks for
SKIP_HELPER = TESTS / "helpers" / "paths.py"  # needs_shared, which adds the source to every such reason


def strings_naming_shared(path: Path) -> list[int]:
    """The lines of the strings in `path` (docstrings aside) that name ../shared: in a test file, such a string
    is a skip reason written by hand, without the source a user needs."""
    tree = ast.parse(path.read_text())
    docstrings = {id(node.body[0].value) for node in ast.walk(tree)
                  if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef))
                  and node.body and isinstance(node.body[0], ast.Expr)}
    return [node.lineno for node in ast.walk(tree) if isinstance(node, ast.Constant) and isinstance(node.value, str)
            and SHARED_WORD in node.value and id(node) not in docstrings]


def test_every_skip_that_names_shared_goes_through_needs_shared():
    written = {f"{f.relative_to(REPO)}:{line}" for f in sorted(TESTS.rglob("*.py")) if f != SKIP_HELPER
               for line in strings_naming_shared(f)}
    assert not written, f"skip reasons naming {SHARED_WORD} without needs_shared (so without a source): {written}"


def test_the_scan_finds_a_skip_reason_written_by_hand(tmp_path):
    test = tmp_path / "test_x.py"
    test.write_text(f'"""{SHARED_WORD} in a docstring is no skip."""\nimport pytest\n\n\ndef test_x():\n'
                    f'    pytest.skip(f"needs the SDK at {{1}} ({SHARED_WORD})")\n')
    assert strings_naming_shared(test) == [6]


@pytest.mark.parametrize("piece", PIECES, ids=lambda p: p.shared)
def test_each_reason_says_where_to_get_the_piece(piece: Piece):
    reason = needs_shared("it", Path("/nowhere"), piece)
    assert SHARED_WORD in reason and "\n" not in reason
    if piece.repository is not None:
        assert f"https://github.com/{piece.repository} at {piece.commit}" in reason
    for script in re.findall(r"scripts/[\w./-]+\w", reason):
        assert (REPO / script).exists(), script


@pytest.mark.parametrize("doc", [REPO / "README.md", DOCS / "REAL-ATHRILL.md"], ids=lambda d: d.name)
def test_the_docs_name_each_repository_and_commit_of_the_table(doc: Path):
    text = doc.read_text()
    pieces = [p for p in PIECES if p.repository is not None and (doc.name == "README.md" or "mazes" not in p.shared)]
    missing = [f"{p.repository} {p.commit}" for p in pieces
               if f"https://github.com/{p.repository}" not in text or p.commit not in text]
    assert not missing, f"{doc.name} does not name {missing}"
