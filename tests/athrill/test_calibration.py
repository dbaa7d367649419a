"""A program that calibrates by hand before its start, as ET Robocon teams' programs do, run with the scenario
that does the person's part (docs/examples/calibrate-then-start*.toml): robot over black, button, over white,
button, course button, back at the start, a hand in front of the ultrasonic sensor (or, on HackSPi, a force
press). Natively, and as a v850 image in the repeatable athrill2, where a place happens at the same instant."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.helpers.commands import hako
from tests.helpers.native_fixtures import need_cc
from tests.helpers.paths import DOCS, PROGRAMS
from tests.helpers.realemu_fixtures import need_v850_tools

EV3_APP = PROGRAMS / "calibrate_then_trace" / "app.c"
SPIKE_APP = PROGRAMS / "calibrate_then_trace_spike" / "app.c"
EV3_SCENARIO = DOCS / "examples" / "calibrate-then-start.toml"
SPIKE_SCENARIO = DOCS / "examples" / "calibrate-then-start-spike.toml"


def trial(run_dir: Path, app: Path | str, *args: str) -> tuple[str, str]:
    """`hako try --json`: its output, and the program's log."""
    out = hako("try", "--app", str(app), "--json", "--run-dir", str(run_dir), *args, timeout=600)
    assert out.returncode == 0, out.stderr
    return out.stdout, (run_dir / "athrill.log").read_text(errors="replace")


def without_places(scenario: Path, out: Path) -> Path:
    """The scenario with its [[place]] tables left out: the same presses, with the robot never moved."""
    tables = scenario.read_text().split("\n\n")
    out.write_text("\n\n".join(t for t in tables if not t.startswith("[[place]]")))
    assert "[[press]]" in out.read_text() and "[[place]]" not in out.read_text()
    return out


@pytest.mark.slow
def test_the_calibrating_tracer_laps_with_the_example_scenario_and_repeats_it(tmp_path):
    need_cc()
    args = ("--robot", "hackev", "--scenario", str(EV3_SCENARIO))
    first, log = trial(tmp_path / "a", EV3_APP, *args)
    again, _ = trial(tmp_path / "b", EV3_APP, *args)
    result = json.loads(first)
    assert result["event"] == "GOAL" and result["checkpoints"] == 4, log
    assert first == again
    # Black from the line's middle, white from the floor beside it; the lap only after the hand.
    assert "black 6" in log and "white 10" in log and "R course" in log and "[     3.500 s] start" in log


@pytest.mark.slow
def test_without_the_places_the_calibration_fails_and_the_robot_stays(tmp_path):
    need_cc()
    scenario = without_places(EV3_SCENARIO, tmp_path / "presses-only.toml")
    out, log = trial(tmp_path / "run", EV3_APP, "--robot", "hackev", "--scenario", str(scenario),
                     "--time-limit", "6")
    result = json.loads(out)
    assert (result["event"], result["distance_m"]) == ("TIME_OVER", 0.0)
    assert "calibration failed" in log and "start" not in log.split("calibration failed")[1]


@pytest.mark.slow
def test_the_spike_variant_laps_with_hub_buttons_and_a_force_press(tmp_path):
    need_cc()
    out, log = trial(tmp_path / "run", SPIKE_APP, "--robot", "hackspi", "--scenario", str(SPIKE_SCENARIO))
    result = json.loads(out)
    assert result["event"] == "GOAL" and result["checkpoints"] == 4, log
    assert "black 1" in log and "white 40" in log and "R course" in log


@pytest.mark.slow
def test_in_the_repeatable_emulator_the_places_happen_as_natively(repeatable_athrill2, tmp_path):
    """The same program built by EV3RT's own make into a v850 image: calibrated and lapping as the native build
    does (the emulator's clock takes time the native one does not, so within 2%), and repeatable to the byte."""
    need_v850_tools()
    built = hako("build", str(EV3_APP.parent), timeout=900)
    assert built.returncode == 0, built.stderr
    image = built.stdout.strip()
    args = ("--robot", "hackev", "--scenario", str(EV3_SCENARIO), "--athrill2", str(repeatable_athrill2))
    first, log = trial(tmp_path / "a", image, *args)
    again, _ = trial(tmp_path / "b", image, *args)
    native = json.loads(trial(tmp_path / "native", EV3_APP, *args[:4])[0])
    real = json.loads(first)
    assert first == again and real["sync"] == "repeatable" and "R course" in log
    assert real["event"] == native["event"] == "GOAL"
    assert real["distance_m"] == pytest.approx(native["distance_m"], rel=0.02)
