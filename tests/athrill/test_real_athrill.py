"""The real TOPPERS Athrill running the unmodified EV3RT sample image against our MuJoCo physics, over the
real Hakoniwa protocol (hakoniwa sync)."""

import json
import subprocess

import pytest

from athrill_sim.programs.third_party import EV3RT_SAMPLE_IMAGE
from hakoniwa.wire.timebase import ALLOWED_TIME_DIFF_US
from tests.helpers.athrill_fixtures import ASP_IMAGE
from tests.helpers.commands import hako
from tests.helpers.paths import needs_shared


def hako_trial(*args: str) -> tuple[subprocess.CompletedProcess, dict | None]:
    out = hako("try", *args, timeout=300)
    return out, json.loads(out.stdout) if out.returncode == 0 and "--json" in args else None


@pytest.mark.slow
def test_the_real_emulator_follows_the_line_on_our_physics(athrill2, tmp_path):
    out, result = hako_trial("--app", str(ASP_IMAGE), "--athrill2", str(athrill2), "--sync", "hakoniwa", "--json",
                             "--run-dir", str(tmp_path))
    assert out.returncode == 0, out.stderr
    assert result["sync"] == "hakoniwa"
    assert result["event"] not in ("HIT_WALL", "CRASH"), result
    assert result["distance_m"] >= 0.5, result
    assert result["max_time_diff_us"] <= ALLOWED_TIME_DIFF_US, result
    assert (tmp_path / "memory_mmap.txt").is_file() and (tmp_path / "device_config_mmap.txt").is_file()


def test_an_elf_without_athrill2_is_a_one_line_error(tmp_path, monkeypatch):
    if not ASP_IMAGE.is_file():
        pytest.skip(needs_shared("the real EV3RT image", ASP_IMAGE, EV3RT_SAMPLE_IMAGE))
    monkeypatch.setenv("PATH", str(tmp_path))  # no athrill2 anywhere on it
    out, _ = hako_trial("--app", str(ASP_IMAGE), "--sync", "hakoniwa", "--json")
    assert out.returncode != 0
    assert "athrill2" in out.stderr and "build_athrill2.sh" in out.stderr
    assert "Traceback" not in out.stderr and len(out.stderr.strip().splitlines()) == 1
