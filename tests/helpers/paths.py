"""Where the tests find the repository and their data, computed once here so that a test file that moves
between area folders keeps finding them."""

from __future__ import annotations

from pathlib import Path

from athrill_sim.programs.third_party import Piece

TESTS = Path(__file__).resolve().parents[1]
REPO = TESTS.parent
SHARED = REPO.parent / "shared"  # ../shared beside the clone: the real SDKs, emulator and large maze set
DOCS = REPO / "docs"
SCRIPTS = REPO / "scripts"
PROGRAMS = TESTS / "programs"  # the test programs (tracers to tune, C++ workspaces)
MICE = TESTS / "mice"  # mms-protocol mice


def needs_shared(what: str, path: Path, piece: Piece) -> str:
    """The skip reason of a test that needs a piece of ../shared: what it is, where it was looked for, and
    where a user without ../shared gets it (`athrill_sim.programs.third_party`), so that a skip says what to do.
    tests/project/test_skip_reasons.py holds every skip that names ../shared to this."""
    return f"needs {what} at {path} (../shared; {piece.source()})"
