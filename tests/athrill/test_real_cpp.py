"""C++ programs in the real emulator: `hako build` builds an ET Robocon-style C++ workspace with EV3RT's own
`make img=` (SRCLANG := c++), the image runs in the repeatable athrill2, and prints what the native build
prints; an image with C++ debug information, which athrill2 cannot read, is one line that says so."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.athrill.test_native_cpp import FEATURE_LINES, FEATURES, SPIKE_TRACER, TRACER, press, program_lines
from tests.helpers.commands import hako, one_line_error
from tests.helpers.realemu_fixtures import need_v850_tools


def build(app: Path) -> Path:
    need_v850_tools()
    out = hako("build", str(app), timeout=900)
    assert out.returncode == 0, out.stderr
    return Path(out.stdout.strip())


@pytest.mark.slow
def test_a_cpp_image_is_stripped_of_the_debug_information_athrill2_cannot_read(repeatable_athrill2, tmp_path):
    image = build(TRACER)
    assert (image.parent / "asp.debug").is_file()
    assert b".debug_info" not in image.read_bytes() and b".debug_info" in (image.parent / "asp.debug").read_bytes()
    one_line_error(hako("try", "--app", str(image.parent / "asp.debug"), "--athrill2", str(repeatable_athrill2),
                        "--run-dir", str(tmp_path / "run"), timeout=300),
                   "cannot read a C++ image's debug information", "--strip-debug")


@pytest.mark.slow
def test_the_cpp_tracer_image_laps_in_the_real_emulator_after_the_touch_press(repeatable_athrill2, tmp_path):
    image = build(TRACER)
    out = hako("try", "--app", str(image), "--athrill2", str(repeatable_athrill2), "--noise", "0", "--json",
               "--scenario", str(press(tmp_path, 4)), "--run-dir", str(tmp_path / "run"), timeout=600)
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout)
    assert result["event"] == "GOAL" and 15 < result["lap_time_s"] < 20


@pytest.mark.slow
def test_the_cpp_features_image_prints_what_the_native_build_prints(repeatable_athrill2, tmp_path):
    image = build(FEATURES)
    out = hako("try", "--app", str(image), "--athrill2", str(repeatable_athrill2), "--noise", "0", "--json",
               "--time-limit", "0.5", "--run-dir", str(tmp_path / "run"), timeout=600)
    assert out.returncode == 0, out.stderr
    assert program_lines(tmp_path / "run") == FEATURE_LINES


@pytest.mark.slow
def test_hako_build_takes_the_spike_sdk_for_a_spike_program_and_its_image_laps(repeatable_athrill2, tmp_path):
    """No --sdk, no --toolchain: the program includes libcpp-spike and says USE_RASPIKE_ART, so ET Robocon's
    SPIKE SDK builds it, with EV3RT's toolchain (the SPIKE SDK has none beside it)."""
    need_v850_tools()
    from tests.helpers.raspike_sdk import NEEDS_RASPIKE, SDK

    if not SDK.is_dir():
        pytest.skip(NEEDS_RASPIKE)
    out = hako("build", str(SPIKE_TRACER), timeout=900)
    assert out.returncode == 0, out.stderr
    assert "SPIKE SDK at" in out.stderr or not out.stderr  # announced when it builds; a cached image is silent
    image = Path(out.stdout.strip())
    run = hako("try", "--app", str(image), "--athrill2", str(repeatable_athrill2), "--robot", "hackspi",
               "--scenario", str(press(tmp_path, "force")), "--noise", "0", "--json", "--run-dir",
               str(tmp_path / "run"), timeout=600)
    assert run.returncode == 0, run.stderr
    result = json.loads(run.stdout)
    assert result["event"] == "GOAL" and 25 < result["lap_time_s"] < 35
