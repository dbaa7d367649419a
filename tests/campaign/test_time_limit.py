"""One owner for the time limit: the course's by default, `--time-limit` when given, and a failed test in a
campaign scores exactly that limit (a lower penalty would push the optimizer towards failing)."""

from __future__ import annotations

import csv
import json
import shutil

import pytest

from hakoniwa.physics.course import COURSES_DIR
from testctl.bench_options import BenchOptions
from testctl.campaign.journal import JOURNAL_FILE, read_journal
from tests.helpers.commands import hako


def short_course(tmp_path, seconds: int):
    folder = tmp_path / "short"
    shutil.copytree(COURSES_DIR / "oval", folder)
    toml = folder / "course.toml"
    assert "time_limit_s = 60" in toml.read_text()
    toml.write_text(toml.read_text().replace("time_limit_s = 60", f"time_limit_s = {seconds}"))
    return folder


def test_the_override_wins_and_the_course_is_the_default() -> None:
    assert BenchOptions().time_limit_us(3_000_000) == 3_000_000
    assert BenchOptions(time_limit_s=120.0).time_limit_us(3_000_000) == 120_000_000


@pytest.mark.slow
def test_hako_try_obeys_the_courses_time_limit(tmp_path) -> None:
    r = hako("try", "--course", str(short_course(tmp_path, 3)), "--noise", "0", "--json", timeout=300)
    assert r.returncode == 0, r.stderr
    result = json.loads(r.stdout)
    assert result["event"] == "TIME_OVER"
    assert result["lap_time_s"] is None


@pytest.mark.slow
def test_a_failure_scores_the_time_limit_of_the_campaign(tmp_path) -> None:
    """Every test of a 2 s campaign times out on the oval (a lap takes about 50 s), so every set fails and
    scores 2 s, the limit given, not the paper's 60."""
    out = tmp_path / "c"
    r = hako("run", "--smoke", "--noise", "0", "--time-limit", "2", "--out", str(out), timeout=600)
    assert r.returncode in (0, 1), r.stderr
    header, records = read_journal(out / JOURNAL_FILE)
    assert header["options"]["penalty_s"] == 2.0
    assert {rec.result.event.name for rec in records} == {"TIME_OVER"}
    rows = list(csv.DictReader(open(out / "results.csv")))
    assert rows and {float(row["objective_s"]) for row in rows} == {2.0}


@pytest.mark.slow
def test_the_course_limit_is_the_campaigns_penalty(tmp_path) -> None:
    out = tmp_path / "c"
    r = hako("run", "--smoke", "--noise", "0", "--course", str(short_course(tmp_path, 3)), "--out", str(out),
             timeout=600)
    assert r.returncode in (0, 1), r.stderr
    header, _ = read_journal(out / JOURNAL_FILE)
    assert header["options"]["penalty_s"] == 3.0
