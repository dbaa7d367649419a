"""The fixtures many test modules share: the real emulators and an image, built once a session (each a
pytest skip, with the reason, where they cannot be built). Plain helpers are in tests/helpers/."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tests.helpers.athrill_fixtures import build_athrill2
from tests.helpers.commands import hako
from tests.helpers.realemu_fixtures import BASE_PRACTICE, build_repeatable_athrill2, need_v850_tools

# Films render headless: MuJoCo picks its OpenGL backend when first imported, by whichever test module that is.
os.environ.setdefault("MUJOCO_GL", "egl")


@pytest.fixture(scope="session")
def athrill2() -> Path:
    return build_athrill2()


@pytest.fixture(scope="session")
def repeatable_athrill2() -> Path:
    return build_repeatable_athrill2()


@pytest.fixture(scope="session")
def base_practice_image() -> Path:
    """base_practice_1 built with `hako build` (cached)."""
    need_v850_tools()
    out = hako("build", str(BASE_PRACTICE), timeout=900)
    assert out.returncode == 0, out.stderr
    return Path(out.stdout.strip())
