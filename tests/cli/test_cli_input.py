"""Bad input a user can give `hako`, `hakoniwa-physics` and `testctl`: each a one-line error and a non-zero exit,
before any test runs; and `-h` everywhere."""

from __future__ import annotations

import pytest

from testctl.campaign.journal import JOURNAL_FILE
from tests.helpers.commands import one_line_error
from tests.helpers.commands import run_module as run


@pytest.mark.parametrize("args, words", [
    (["--kp", "nan"], ["--kp", "not a finite number"]),
    (["--ki", "inf"], ["--ki", "not a finite number"]),
    (["--kd", "-inf"], ["--kd", "not a finite number"]),
    (["--kp", "1e40"], ["--kp", "outside", "3.40282e+38"]),
    (["--power", "1000"], ["--power", "outside -100..100"]),
    (["--power", "abc"], ["--power", "not a number"]),
    (["--trajectory", "/missing/dir/x.png"], ["--trajectory", "/missing/dir", "does not exist"]),
    (["--athrill-timeout", "-1"], ["--athrill-timeout", "outside"]),
    (["--time-limit", "nan"], ["--time-limit", "not a finite number"]),
    (["--noise", "-1"], ["--noise", "outside"]),
    (["--app", "nosuch"], ["--app nosuch", "not a built-in app"]),
    (["--app", "nosuch_module:main_task"], ["cannot load app", "nosuch_module"]),
])
def test_hako_try_refuses_bad_values_before_running(args, words):
    one_line_error(run("testctl.hako", "try", *args), *words)


@pytest.mark.parametrize("args, words", [
    (["--athrill-timeout", "-1"], ["--athrill-timeout"]),
    (["--app", "nosuch"], ["--app nosuch"]),
    (["--time-limit", "0"], ["--time-limit"]),
])
def test_hakoniwa_physics_validates_at_start(tmp_path, args, words):
    one_line_error(run("testctl.physics_process", "--run-dir", str(tmp_path), *args), *words)
    assert not (tmp_path / "unity_mmap.bin").exists()


def test_out_under_a_file_or_in_proc_is_one_line(tmp_path):
    (tmp_path / "afile").write_text("x")
    for out in (tmp_path / "afile" / "sub", "/proc/hako-campaign"):
        one_line_error(run("testctl.hako", "run", "--smoke", "--out", str(out)), "--out", "cannot write there")


def test_testctl_trial_refuses_non_finite_gains(tmp_path):
    one_line_error(run("testctl.cli", "try", "--run-dir", str(tmp_path), "--kp", "nan", "--ki", "0", "--kd", "0",
                       "--out", str(tmp_path / "r.json")), "--kp")


@pytest.mark.parametrize("module, args", [
    ("testctl.hako", []), ("testctl.hako", ["try"]), ("testctl.hako", ["run"]), ("testctl.physics_process", []),
    ("testctl.cli", []), ("testctl.cli", ["try"]), ("testctl.cli", ["campaign"]), ("athrill_sim.mock.main", []),
])
def test_dash_h_is_help_everywhere(module, args):
    r = run(module, *args, "-h")
    assert r.returncode == 0, r.stderr
    assert "Usage:" in r.stdout and "-h, --help" in r.stdout


@pytest.mark.slow
def test_resume_with_fewer_trials_says_the_campaign_has_more(tmp_path):
    out = tmp_path / "c"
    first = run("testctl.hako", "run", "--smoke", "--noise", "0", "--out", str(out), timeout=600)
    assert first.returncode == 0, first.stderr
    n = (out / JOURNAL_FILE).read_text().count("\n")
    again = run("testctl.hako", "run", "--resume", str(out), "--trials", "0", timeout=600)
    assert again.returncode == 0, again.stderr
    assert "already has 4 sets, more than the 2" in again.stderr
    assert (out / JOURNAL_FILE).read_text().count("\n") == n  # nothing ran
