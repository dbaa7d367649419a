"""The real emulator's repeatable mode and v850 images for tests: athrill2 built with the sync patch, and the
EV3RT SDK with its toolchain, from ../shared (cached under build/ and the user cache); tests/conftest.py makes
the builds session fixtures (`repeatable_athrill2`, `base_practice_image`).

Tests that need them skip with the reason in pytest's summary: no C compiler, no ../shared beside the clone,
no Ruby (EV3RT's generators), no toolchain.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from athrill_sim.programs.athrill2 import REPEATABLE_DIR
from athrill_sim.v850 import ImageError
from athrill_sim.v850.toolchain import SHARED, check_build_tools, find_tools
from tests.helpers.athrill_fixtures import build_athrill2
from tests.helpers.paths import REPO

WORKSPACE = SHARED / "ev3rt" / "ev3rt-athrill-v850e2m" / "sdk" / "workspace"
BASE_PRACTICE = WORKSPACE / "base_practice_1"
# ET Robocon's athrill2 device configs for its UDP link (127.0.0.1, ports 54001 / 54002), as its SDKs ship them.
ETROBOC_DEVICE_CONFIGS = [SHARED / "raspike" / "raspike-athrill-v850e2m" / "sdk" / "common" / "device_config.txt",
                          SHARED / "ev3rt" / "ev3rt-athrill-v850e2m" / "sdk" / "common" / "device_config.txt"]


def need_v850_tools() -> None:
    """A pytest skip, saying what is missing, unless an image can be built here."""
    try:
        find_tools()
        check_build_tools()
    except ImageError as e:
        pytest.skip(f"cannot build v850 images: {e}")


def build_repeatable_athrill2() -> Path:
    """athrill2 with the repeatable-sync patch (scripts/build_athrill2.sh --repeatable, cached), or a skip."""
    build_athrill2()  # skips without a compiler or ../shared
    out = subprocess.run([str(REPO / "scripts" / "build_athrill2.sh"), "--repeatable", str(REPO / REPEATABLE_DIR)],
                         capture_output=True, text=True, timeout=900)
    assert out.returncode == 0, out.stderr[-2000:]
    return Path(out.stdout.strip())
