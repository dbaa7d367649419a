"""A campaign on ET Robocon's score: our garage program's tracer (its speed and steering `#define`s) tuned on the
etrobocon-l course raises its score above the program's own, and best.patch gives the program the gains that
score it."""

from __future__ import annotations

import json
import shutil
import subprocess

import pytest

from tests.helpers.commands import hako
from tests.helpers.native_fixtures import need_cc
from tests.helpers.paths import PROGRAMS

BENCH = ("--course", "etrobocon-l", "--robot", "hackev", "--objective", "etrobocon", "--noise", "0")


def score_of(app, run_dir) -> float:
    r = hako("try", "--app", str(app), *BENCH, "--json", "--run-dir", str(run_dir), timeout=600)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)["score"]["total"]


@pytest.mark.slow
def test_a_campaign_raises_the_score_and_best_patch_returns_the_gains(tmp_path):
    need_cc()
    own = score_of(PROGRAMS / "etrobo_garage", tmp_path / "own")
    out = tmp_path / "campaign"
    r = hako("run", "--app", str(PROGRAMS / "etrobo_garage"), "--space", str(PROGRAMS / "garage.toml"), *BENCH,
             "--repeats", "1", "--seed", "0", "--init-points", "5", "--trials", "10", "--validate", "0",
             "--out", str(out), timeout=1800)
    assert r.returncode == 0, r.stderr
    best = json.loads((out / "best.json").read_text())
    assert best["score"] > own + 3, (best["score"], own)
    assert f"score {best['score']:.2f} points" in r.stdout + r.stderr
    copy = tmp_path / "programs"
    shutil.copytree(PROGRAMS, copy)
    applied = subprocess.run(["git", "apply", str(out / "best.patch")], cwd=copy / "etrobo_garage",
                             capture_output=True, text=True)
    assert applied.returncode == 0, applied.stderr
    assert score_of(copy / "etrobo_garage", tmp_path / "patched") == best["score"]
