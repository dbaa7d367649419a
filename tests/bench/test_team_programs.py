"""The corpus of programs written as ET Robocon teams write them for RasPike-ART (tests/programs/team_*: threads,
chrono pacing, condition variables, a logger thread, a spin on steady_clock, a busy system() script, a calibration
by hand, gains in command files): each drives, and repeats byte for byte, its logs too, with two CPU burners
beside it."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from hakoniwa.wire.rundir import WORKSPACE_DIR
from tests.helpers.commands import hako
from tests.helpers.native_fixtures import need_cc
from tests.helpers.paths import REPO

PROGRAMS = REPO / "tests" / "programs"
SCENARIOS = PROGRAMS / "scenarios"
TEAM_PROGRAMS = {  # name: (robot, scenario, a file the program writes into its workspace)
    "team_spike_threads": ("hackspi", "force-start.toml", "team_spike_threads/run_log.csv"),
    "team_c_posix": ("hackspi", "force-start.toml", None),
    "team_ev3_commands": ("hackev", "team_ev3_commands.toml", "team_ev3_commands/logs/init.txt"),
}


def trial(name: str, run_dir: Path) -> str:
    robot, scenario, _ = TEAM_PROGRAMS[name]
    out = hako("trial", "--app", str(PROGRAMS / name), "--robot", robot, "--scenario", str(SCENARIOS / scenario),
               "--seed", "3", "--json", "--run-dir", str(run_dir))
    assert out.returncode == 0, out.stderr
    return out.stdout


@pytest.mark.slow
@pytest.mark.parametrize("name", TEAM_PROGRAMS)
def test_a_team_program_drives_and_repeats_byte_for_byte_even_under_load(name, tmp_path):
    need_cc()
    quiet = trial(name, tmp_path / "quiet")
    burners = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(2)]
    try:
        loaded = trial(name, tmp_path / "loaded")
    finally:
        for b in burners:
            b.kill()
            b.wait()
    assert quiet == loaded
    result = json.loads(quiet)
    assert result["event"] == "GOAL" or result["distance_m"] >= 2.0, result
    written = TEAM_PROGRAMS[name][2]
    if written is not None:
        kept = [(tmp_path / run / WORKSPACE_DIR / written).read_bytes() for run in ("quiet", "loaded")]
        assert kept[0] == kept[1] and kept[0]
