"""`hako run` end to end: the campaign over the real three-process bench."""

import json
import os
import signal
import subprocess
import sys

import pytest

from testctl.campaign.journal import JOURNAL_FILE, PHASE_VALIDATION, read_journal
from testctl.options import SMOKE_DRAWS
from tests.helpers.commands import hako
from tests.helpers.processes import interruptible
from tests.helpers.waiting import wait_until


def test_smoke_campaign_writes_every_result_file(tmp_path):
    out = tmp_path / "smoke"
    r = hako("run", "--smoke", "--out", str(out))
    assert r.returncode == 0, r.stderr
    assert "best:" in r.stdout
    assert f"campaign {out}: sets 0/4, tests 0, benches" in r.stderr  # stderr is no terminal: plain progress
    names = ["journal.jsonl", "results.csv", "best.json", "fig8.png", "fig9.png", "best_trajectory.png"]
    from hakoniwa.pictures.video import gl_problem

    filmed = gl_problem() is None  # where MuJoCo can render: the best set's lap, filmed (tests/physics/test_video.py)
    if filmed:
        names.append("best_lap.mp4")
    for name in names:
        assert (out / name).stat().st_size > 0, name
    if filmed:  # and in the study, beside the trajectory
        import optuna
        from optuna.artifacts import get_all_artifact_meta

        from testctl.campaign.study import open_storage, study_name

        study = optuna.load_study(study_name=study_name(out), storage=open_storage(out))
        assert {"best_trajectory.png", "best_lap.mp4"} <= {m.filename for m in get_all_artifact_meta(study)}
    best = json.loads((out / "best.json").read_text())
    _, records = read_journal(out / JOURNAL_FILE)
    searched = [r for r in records if r.phase != PHASE_VALIDATION]
    assert len(searched) == best["n_tests"] == 4  # 2 initial + 2 iterations, 1 test each
    assert len(records) - len(searched) == SMOKE_DRAWS  # the validation's draws, journaled too
    assert best["success"] and 20 < best["lap_time_s"] < 60


@pytest.mark.parametrize("content, message", [
    ("this is = = not toml", "TOML"),
    ('[[param]]\nname = "Kp"\noffset = 540\nlow = 5.0\nhigh = 1.0\n', "low"),
    ('[[param]]\nname = "Kp"\noffset = 12\nlow = 0.0\nhigh = 1.0\n', "offset"),
    ('[[param]]\nname = "Kp"\noffset = 540\nlow = 0.0\nhigh = 1e39\n', "float32"),
    ('[[param]]\nname = "Kp"\noffset = 540\nlow = 0.0\nhigh = 1.0\n[[fixed]]\nname = "p"\noffset = 552\n'
     'value = 1e39\n', "float32"),
])
def test_bad_space_file_is_a_one_line_error(tmp_path, content, message):
    space = tmp_path / "space.toml"
    space.write_text(content)
    r = hako("run", "--space", str(space), "--out", str(tmp_path / "o"), timeout=120)
    assert r.returncode != 0
    assert message in r.stderr and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "o" / JOURNAL_FILE).exists()


def test_resume_refuses_other_settings(tmp_path):
    r = hako("run", "--resume", str(tmp_path / "nothing-here"), timeout=120)
    assert r.returncode != 0 and "Traceback" not in r.stderr


def set_tests(records):
    return sorted((r.set_index, r.rep, tuple(sorted(r.params.items())), r.result.event, r.result.goal_time_us)
                  for r in records)


RESUMED = ["--optimizer", "random", "--init-points", "2", "--trials", "4", "--repeats", "3", "--seed", "7",
           "--noise", "0"]


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory) -> list:
    """The campaign of RESUMED run from start to end: what a stopped and resumed one must equal."""
    whole = tmp_path_factory.mktemp("whole") / "c"
    assert hako("run", *RESUMED, "--out", str(whole)).returncode == 0
    return read_journal(whole / JOURNAL_FILE)[1]


@pytest.mark.slow
@pytest.mark.parametrize("signum", [signal.SIGKILL, signal.SIGINT], ids=["sigkill", "ctrl-c"])
def test_a_campaign_killed_or_interrupted_then_resumed_equals_an_uninterrupted_one(tmp_path, uninterrupted, signum):
    """SIGKILL (no chance to clean up) or Ctrl-C (to the whole process group, as a terminal sends it) mid-set;
    `--resume` loses no finished test, repeats none, and ends with the very journal of an uninterrupted run."""
    killed = tmp_path / "killed"
    proc = subprocess.Popen([sys.executable, "-m", "testctl.hako", "run", *RESUMED, "--out", str(killed)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, start_new_session=True,
                            preexec_fn=interruptible)
    journal = killed / JOURNAL_FILE
    wait_until(lambda: journal.exists() and journal.read_text().count("\n") >= 1 + 3, 300,  # header + 3 tests: mid-set
               alive=lambda: proc.poll() is None, what="3 tests")
    if signum == signal.SIGKILL:
        os.kill(proc.pid, signal.SIGKILL)
    else:
        os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    if signum == signal.SIGINT:
        assert proc.returncode == 130 and f"continue with: hako run --resume {killed}" in err, err
    _, before = read_journal(journal)
    assert 3 <= len(before) < 12

    r = hako("run", "--resume", str(killed))
    assert r.returncode == 0, r.stderr

    _, resumed = read_journal(journal)
    assert set(set_tests(before)) <= set(set_tests(resumed))  # nothing finished was lost
    assert set_tests(resumed) == set_tests(uninterrupted)  # nothing repeated, nothing skipped
    searched = [r for r in resumed if r.phase != PHASE_VALIDATION]
    assert len(searched) == 12  # deterministic bench: each of 6 sets is decided by 2 equal tests of 3


@pytest.mark.slow
def test_the_papers_arrangement_gives_the_same_campaign(tmp_path):
    """The physics process starting the controller on its one bench (paper Fig. 3) and `hako run` on a Dask
    bench give the same results for the same seed."""
    via_hako = tmp_path / "hako"
    assert hako("run", "--smoke", "--out", str(via_hako)).returncode == 0
    paper = tmp_path / "paper"
    r = subprocess.run([sys.executable, "-m", "testctl.physics_process", "--run-dir", str(tmp_path / "run"), "--",
                        sys.executable, "-m", "testctl.cli", "campaign", "--smoke", "--out", str(paper)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert (paper / "results.csv").read_text() == (via_hako / "results.csv").read_text()
