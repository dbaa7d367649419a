"""Programs on the built-in ET Robocon-style courses, natively: ET Robocon's official SPIKE sample and our
look-alike of its HackEV sample follow the line to the LAP gate on both lanes as written; our own programs
trace until blue and stop in the garage, and push the sumo bottle out of its ring, and --objective etrobocon
scores each; a film of the sumo run shows the lane's colours, the bottle moving and the score."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from tests.helpers.commands import hako
from tests.helpers.native_fixtures import need_cc
from tests.helpers.paths import DOCS, PROGRAMS
from tests.helpers.raspike_sdk import ART_SAMPLES, NEEDS_RASPIKE

LANES = ("etrobocon-l", "etrobocon-r")
PRESS_TOUCH_1 = '[[press]]\nsensor = "touch"\nport = 1\nat_s = 0.5\nfor_s = 0.2\n'  # HackEV's touch sensor


def trial(tmp_path, *args: str) -> dict:
    need_cc()
    r = hako("try", "--noise", "0", "--json", "--run-dir", str(tmp_path / "run"), *args, timeout=600)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


@pytest.mark.slow
@pytest.mark.parametrize("lane", LANES)
def test_et_robocons_spike_sample_follows_the_line_to_the_lap_gate(tmp_path, lane):
    if not (ART_SAMPLES / "sample_c5_spike").is_dir():
        pytest.skip(NEEDS_RASPIKE)
    app = shutil.copytree(ART_SAMPLES / "sample_c5_spike", tmp_path / "sample_c5_spike")
    result = trial(tmp_path, "--course", lane, "--app", str(app), "--robot", "hackspi", "--scenario",
                   str(DOCS / "examples" / "press-force.toml"))
    assert (result["event"], result["checkpoints"]) == ("GOAL", 4)  # the LAP gate is the last checkpoint
    assert 60 < result["lap_time_s"] < 90  # its power 30: about 0.15 m/s over some 10 m


@pytest.mark.slow
@pytest.mark.parametrize("lane", LANES)
def test_the_hackev_sample_look_alike_follows_the_line_to_the_lap_gate(tmp_path, lane):
    (tmp_path / "press.toml").write_text(PRESS_TOUCH_1)
    result = trial(tmp_path, "--course", lane, "--app", str(PROGRAMS / "etrobo_sample_c4"), "--robot", "hackev",
                   "--scenario", str(tmp_path / "press.toml"))
    assert (result["event"], result["checkpoints"]) == ("GOAL", 4)
    log = (tmp_path / "run" / "athrill.log").read_text()
    assert "tap the touch sensor" in log


@pytest.mark.slow
def test_a_program_that_traces_until_blue_and_stops_in_the_garage_scores_the_finish(tmp_path):
    result = trial(tmp_path, "--course", "etrobocon-l", "--app", str(PROGRAMS / "etrobo_garage"), "--robot",
                   "hackev", "--objective", "etrobocon")
    score = result["score"]
    assert result["event"] == "FINISH" and result["objective"] == "etrobocon"
    assert (score["checkpoints"], score["lap_gate"], score["finish"], score["sumo"]) == (3, True, True, False)
    assert score["total"] == score["run_points"] + 2 * 3 + 3 + 3  # the applied class's points
    assert score["lap_time_s"] == result["lap_time_s"]
    log = (tmp_path / "run" / "athrill.log").read_text()
    assert "blue section 2" in log and "stopped in the garage" in log


@pytest.fixture(scope="module")
def sumo_run(tmp_path_factory):
    """The sumo program's run under --objective etrobocon: its result and its run folder."""
    tmp = tmp_path_factory.mktemp("sumo")
    return trial(tmp, "--course", "etrobocon-l", "--app", str(PROGRAMS / "etrobo_sumo"), "--robot", "hackev",
                 "--objective", "etrobocon"), tmp / "run"


@pytest.mark.slow
def test_a_program_that_pushes_the_bottle_out_of_the_ring_scores_the_sumo(sumo_run):
    result, run = sumo_run
    assert result["event"] == "COMPLETED" and result["score"]["sumo"] is True
    replay = json.loads((run / "replay.json").read_text())
    start, end = replay["object_states"][0], replay["object_states"][-1]
    assert np.hypot(end[0] - start[0], end[1] - start[1]) > 0.35  # from the ring's centre to beyond its edge
    assert "the bottle" in (run / "athrill.log").read_text()  # the ultrasonic sensor found it


@pytest.mark.slow
def test_a_film_of_the_sumo_run_shows_the_lanes_colours_the_bottle_moving_and_the_score(sumo_run, tmp_path):
    from hakoniwa.pictures import video
    from tests.physics.test_video import read_frames

    if (problem := video.gl_problem()) is not None:
        pytest.skip(problem)
    film = tmp_path / "sumo.mp4"
    r = hako("replay", str(sumo_run[1]), "--video", str(film), "--camera", "top", "--fps", "5", "--speed", "10x",
             timeout=600)
    assert r.returncode == 0, r.stderr
    frames = read_frames(film)
    first, last = frames[0].astype(int), frames[-1].astype(int)
    blue = (first[:, :, 2] - first[:, :, 0] > 50) & (first[:, :, 2] > 70)  # the image's blue is (5, 40, 94)
    yellow = (first[:, :, 0] > 150) & (first[:, :, 1] > 130) & (first[:, :, 2] < 90)
    assert blue.sum() > 20 and yellow.sum() > 20  # the lanes' blue sections and the sumo rings
    moved = np.abs(last - first).sum(axis=2) > 120
    assert moved[first.shape[0] // 6:].sum() > 30  # below the overlay: the robot and the bottle moved
    def score_coloured(frame: np.ndarray) -> int:  # the score line's colour in the banner at the top
        top = frame[: frame.shape[0] // 4]
        return int(((top[:, :, 0] > 230) & (top[:, :, 1] > 200) & (top[:, :, 2] < 150)).sum())

    assert score_coloured(first) == 0 and score_coloured(last) > 100  # the score, at the end only
