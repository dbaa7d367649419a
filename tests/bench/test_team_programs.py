"""The corpus of programs written as ET Robocon teams write them for RasPike-ART (tests/programs/team_*: threads,
chrono pacing, condition variables, a logger thread, a spin on steady_clock, a busy system() script, a calibration
by hand, gains in command files): each drives, and repeats byte for byte, its logs too, with two CPU burners
beside it; a campaign tunes it in its command file through `row` and `ini` parameters, and best.patch gives the
lap back."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from athrill_sim.tuning.command_files import NUMBER
from hakoniwa.wire.rundir import WORKSPACE_DIR
from tests.helpers.commands import hako, one_line_error
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
    out = hako("try", "--app", str(PROGRAMS / name), "--robot", robot, "--scenario", str(SCENARIOS / scenario),
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


@pytest.mark.slow
@pytest.mark.parametrize("name", TEAM_PROGRAMS)
def test_a_team_program_is_tuned_in_its_command_file_and_best_patch_gives_its_lap(name, tmp_path):
    """A campaign through the program's row or ini parameters; best.patch applied with git apply to a copy
    changes those cells alone, and the copy, run with no parameters, laps as the best set did."""
    need_cc()
    robot, scenario, _ = TEAM_PROGRAMS[name]
    world = ("--robot", robot, "--scenario", str(SCENARIOS / scenario), "--noise", "0")
    out = tmp_path / "campaign"
    r = hako("run", "--app", str(PROGRAMS / name), "--space", str(PROGRAMS / f"{name}.toml"), *world, "--repeats",
             "1", "--seed", "0", "--init-points", "4", "--trials", "4", "--validate", "0", "--out", str(out),
             timeout=1800)
    assert r.returncode == 0, r.stderr
    best = json.loads((out / "best.json").read_text())
    assert best["lap_time_s"] is not None
    copy = tmp_path / "workspace" / name  # the program opens its files by its folder's name
    shutil.copytree(PROGRAMS / name, copy)
    applied = subprocess.run(["git", "apply", str(out / "best.patch")], cwd=copy, capture_output=True, text=True)
    assert applied.returncode == 0, applied.stderr
    lines = (out / "best.patch").read_text().splitlines()
    removed = [line[1:] for line in lines if line.startswith("-") and not line.startswith("---")]
    added = [line[1:] for line in lines if line.startswith("+") and not line.startswith("+++")]
    assert len(removed) == len(added) and 0 < len(added) <= len(best["params"])
    assert [NUMBER.sub("#", line) for line in removed] == [NUMBER.sub("#", line) for line in added]  # cells alone
    trial = hako("try", "--app", str(copy), *world, "--json", "--run-dir", str(tmp_path / "patched"))
    assert trial.returncode == 0, trial.stderr
    assert json.loads(trial.stdout)["lap_time_s"] == best["lap_time_s"]


BAD_SPACES = {
    "no such key": ('row = { file = "datafiles/LineTraceLeft.csv", key = "Arc", column = 5 }',
                    "'Kp': datafiles/LineTraceLeft.csv: no line whose first field is Arc"),
    "a column past the end": ('row = { file = "datafiles/LineTraceLeft.csv", key = "LineTrace", column = 9 }',
                              "column 9 is past the end of the row, which has 7 fields"),
    "a cell that is not a number": ('row = { file = "datafiles/LineTraceLeft.csv", key = "LineTrace", column = 2 }',
                                    "column 2 is 'S001', not a number"),
    "no such file": ('row = { file = "datafiles/Missing.csv", key = "LineTrace", column = 5 }',
                     "datafiles/Missing.csv does not exist"),
    "no such ini section": ('ini = { file = "app.h", section = "pid", key = "kp" }',
                            "app.h: no section [pid] (its sections: none)"),
    "neither key nor line": ('row = { file = "datafiles/LineTraceLeft.csv", column = 5 }',
                             "give one of key and line"),
}


@pytest.mark.parametrize("case", BAD_SPACES)
def test_each_bad_row_or_ini_parameter_is_one_line_naming_the_file_and_the_row(case, tmp_path):
    need_cc()
    where, message = BAD_SPACES[case]
    space = tmp_path / "space.toml"
    space.write_text(f'[[param]]\nname = "Kp"\n{where}\nlow = 0.5\nhigh = 3.0\n')
    r = hako("run", "--app", str(PROGRAMS / "team_spike_threads"), "--space", str(space), "--robot", "hackspi",
             "--smoke", "--out", str(tmp_path / "out"), timeout=300)
    one_line_error(r, message)


def test_two_parameters_on_one_cell_are_refused_however_each_names_it(tmp_path):
    need_cc()
    space = tmp_path / "space.toml"
    space.write_text('[[param]]\nname = "Kp"\nrow = { file = "datafiles/LineTraceLeft.csv", key = "LineTrace", '
                     'column = 5 }\nlow = 0.5\nhigh = 3.0\n\n[[param]]\nname = "Gain"\nrow = { file = '
                     '"datafiles/LineTraceLeft.csv", line = 2, column = 5 }\nlow = 0.5\nhigh = 3.0\n')
    r = hako("run", "--app", str(PROGRAMS / "team_spike_threads"), "--space", str(space), "--robot", "hackspi",
             "--smoke", "--out", str(tmp_path / "out"), timeout=300)
    one_line_error(r, "'Kp' and 'Gain' are two parameters on one cell",
                   "(datafiles/LineTraceLeft.csv line 2, column 5)")
