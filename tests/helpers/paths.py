"""Where the tests find the repository and their data, computed once here so that a test file that moves
between area folders keeps finding them."""

from __future__ import annotations

from pathlib import Path

TESTS = Path(__file__).resolve().parents[1]
REPO = TESTS.parent
SHARED = REPO.parent / "shared"  # ../shared beside the clone: the real SDKs, emulator and large maze set
DOCS = REPO / "docs"
SCRIPTS = REPO / "scripts"
PROGRAMS = TESTS / "programs"  # the test programs (tracers to tune, C++ workspaces)
MICE = TESTS / "mice"  # mms-protocol mice
