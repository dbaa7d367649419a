"""A tiny end-to-end campaign against the synthetic bench: the loop, progress, and the report files."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from hakoniwa.wire.protocol import Event
from testctl.campaign.journal import JOURNAL_FILE, read_journal
from testctl.campaign.loop import Campaign, CampaignConfig, Progress, SetResult
from testctl.campaign.repetition import RepetitionRule
from testctl.campaign.report import best_so_far, format_summary, l1_changes, write_report
from tests.helpers.campaign_doubles import ScriptedBench, SyntheticBench, result


@pytest.mark.parametrize("optimizer", ["gpyopt", "random"])
def test_campaign_finds_the_goal_region_and_writes_the_report(tmp_path: Path, optimizer: str) -> None:
    config = CampaignConfig(init_points=3, trials=3, repeats=3, seed=3, optimizer=optimizer)
    progress: list[Progress] = []
    bench = SyntheticBench()
    summary = Campaign(config, tmp_path, bench, on_progress=progress.append).run()

    assert [s.index for s in summary.sets] == list(range(6))
    assert [s.phase for s in summary.sets] == ["init"] * 3 + ["bo"] * 3
    assert summary.n_tests == summary.tests_run == len(bench.calls) == 12
    assert summary.best is not None and summary.best.verdict.success
    assert summary.best.value == min(s.value for s in summary.sets)
    assert progress[0].sets_done == 0 and progress[-1].sets_done == 6
    assert sum(p.last_test is not None for p in progress) == 12
    laps = [p.best.value for p in progress if p.best is not None]
    assert laps == sorted(laps, reverse=True)

    paths = write_report(tmp_path, summary)
    assert {p.name for p in paths} == {"results.csv", "best.json", "fig8.png", "fig9.png"}
    rows = list(csv.DictReader(open(tmp_path / "results.csv")))
    assert len(rows) == 6
    assert [float(r["Kp"]) for r in rows] == [s.x[0] for s in summary.sets]
    best = json.loads((tmp_path / "best.json").read_text())
    assert best["lap_time_s"] == summary.best.value
    assert best["offsets"]["552"] == 15.0 and best["params"]["Kp"] == summary.best.x[0]
    for png in ("fig8.png", "fig9.png"):
        assert (tmp_path / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "best: [Kp=" in format_summary(summary)


def test_random_baseline_shares_the_initial_design(tmp_path: Path) -> None:
    """With the same seed, BO and random search start from the same points: a fair comparison."""
    runs = {
        name: Campaign(
            CampaignConfig(init_points=3, trials=0, repeats=1, seed=5, optimizer=name),
            tmp_path / name,
            SyntheticBench(),
        ).run()
        for name in ("gpyopt", "random")
    }
    assert [s.x for s in runs["gpyopt"].sets] == [s.x for s in runs["random"].sets]


def test_crashed_test_is_journaled_and_retried(tmp_path: Path) -> None:
    G, C = result(Event.GOAL, 40.0), result(Event.CRASH)
    config = CampaignConfig(init_points=1, trials=0, repeats=3, optimizer="random")
    summary = Campaign(config, tmp_path, ScriptedBench([C, G, C, G])).run()
    (only,) = summary.sets
    assert (only.verdict.success, only.verdict.crashes, only.value) == (True, 2, 40.0)
    assert [(r.rep, r.result.event) for r in read_journal(tmp_path / JOURNAL_FILE)[1]] == [
        (1, Event.CRASH), (2, Event.GOAL), (3, Event.CRASH), (4, Event.GOAL)
    ]


def test_no_success_means_no_best(tmp_path: Path) -> None:
    config = CampaignConfig(init_points=2, trials=0, repeats=1, optimizer="random")
    summary = Campaign(config, tmp_path, ScriptedBench([result(Event.TIME_OVER)] * 2)).run()
    assert summary.best is None
    write_report(tmp_path, summary)
    assert json.loads((tmp_path / "best.json").read_text())["success"] is False
    assert "no parameter set succeeded" in format_summary(summary)


def test_fig9_series() -> None:
    rule = RepetitionRule(1)
    sets = tuple(
        SetResult(i, "init", x, rule.judge([result(Event.GOAL, lap)]), ())
        for i, (x, lap) in enumerate([((0.0, 0.0), 40.0), ((1.0, 2.0), 45.0), ((1.5, 1.0), 35.0)])
    )
    assert l1_changes(sets) == [3.0, 1.5]
    assert best_so_far(sets) == [40.0, 40.0, 35.0]
