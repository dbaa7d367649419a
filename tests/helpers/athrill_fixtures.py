"""The real TOPPERS athrill2 and the real EV3RT image from ../shared, built on demand (cached under build/);
tests/conftest.py makes the build a session fixture, `athrill2`.

Tests that need them skip with the reason in pytest's summary: no C compiler, or no ../shared beside the
clone (a fresh clone on its own).
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from athrill_sim.programs.third_party import ATHRILL, EV3RT_SAMPLE_IMAGE
from tests.helpers.paths import REPO, SHARED, needs_shared

SHARED_ATHRILL = SHARED / "third_party" / "athrill"
ASP_IMAGE = SHARED_ATHRILL / "ev3rt-ble_sample" / "asp"
ATHRILL_SOURCES = SHARED_ATHRILL / "src" / "athrill-target-v850e2m"
BUILD_DIR = REPO / "build" / "athrill"


def build_athrill2() -> Path:
    """athrill2, built from ../shared with scripts/build_athrill2.sh (cached), or a pytest skip saying why."""
    if shutil.which("cc") is None and shutil.which("gcc") is None:
        pytest.skip("needs a C compiler (cc) to build the real athrill2")
    if not ATHRILL_SOURCES.is_dir():
        pytest.skip(needs_shared("the real Athrill sources", ATHRILL_SOURCES, ATHRILL))
    if not ASP_IMAGE.is_file():
        pytest.skip(needs_shared("the real EV3RT image", ASP_IMAGE, EV3RT_SAMPLE_IMAGE))
    out = subprocess.run([str(REPO / "scripts" / "build_athrill2.sh"), str(BUILD_DIR)], capture_output=True,
                         text=True, timeout=900)
    assert out.returncode == 0, out.stderr[-2000:]
    return Path(out.stdout.strip())
