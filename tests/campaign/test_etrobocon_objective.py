"""A campaign under ET Robocon's score: every run that ends without a crash is scored, the campaign maximises
the mean score (its optimizers minimise its negative), and what people read shows the score as a score."""

from __future__ import annotations

import csv
import json

import pytest

from hakoniwa.wire.etrobocon_rules import Score
from hakoniwa.wire.measure import LAP_TIME, SCORE
from hakoniwa.wire.objective import objective_named
from hakoniwa.wire.protocol import CrashKind, Event, Rx
from hakoniwa.wire.result import TestResult
from testctl.campaign.loop import Campaign, CampaignConfig
from testctl.campaign.repetition import RepetitionRule
from testctl.campaign.report import best_dict, fig8, format_summary, write_report
from testctl.search.space import Parameter, ParameterSpace
from tests.helpers.campaign_doubles import ScriptedBench

ETROBOCON = objective_named("etrobocon")


def scored(event: Event, total: float) -> TestResult:
    """A run that made `total` points: the run points of a LAP in (35 - total) s, and no task."""
    lap_us = round((35 - total) * 1e6)
    return TestResult(event, 0, 0.01, objective=ETROBOCON,
                      score=Score.of("applied", lap_us, 0, False, None) if event != Event.CRASH else None)


def test_every_scored_end_succeeds_and_costs_minus_its_score():
    for event in (Event.FINISH, Event.TIME_OVER, Event.HIT_WALL, Event.COMPLETED):
        r = scored(event, 20.0)
        assert r.success and r.cost == -(20.0 + 3) and r.lap_time_s == 15.0  # + the LAP gate's 3 points
    crash = TestResult(Event.CRASH, 0, 0.01, crash_kind=CrashKind.PROGRAM, objective=ETROBOCON)
    assert not crash.success and crash.cost is None
    assert TestResult(Event.FINISH, 0, 0.01, objective=ETROBOCON).success is False  # no score read


def test_the_journal_carries_each_component():
    r = TestResult(Event.FINISH, 0, 0.01, objective=ETROBOCON,
                   score=Score.of("basic", 21_450_000, 3, True, True))
    d = r.to_dict()
    assert d["score"] == {"total": 13.6 + 12 + 3 + 3 + 5, "run_points": 13.6, "task_points": 23.0,
                          "lap_time_s": 21.45, "checkpoints": 3, "lap_gate": True, "finish": True, "sumo": True,
                          "class": "basic"}
    assert TestResult.from_dict(json.loads(json.dumps(d)), 0.01) == r


def test_a_set_scores_its_mean_and_a_failed_one_no_points():
    rule = RepetitionRule(objective=ETROBOCON)
    v = rule.judge([scored(Event.FINISH, 20.0), scored(Event.TIME_OVER, 10.0), scored(Event.FINISH, 30.0)])
    assert (v.success, v.value) == (True, -23.0)
    crashes = [TestResult(Event.CRASH, 0, 0.01, crash_kind=CrashKind.PROGRAM, objective=ETROBOCON)] * 6
    assert RepetitionRule(max_crashes=0, objective=ETROBOCON).judge(crashes[:3]).value == 0.0


def test_the_measure_follows_the_objective():
    assert ETROBOCON.measure is SCORE
    assert objective_named("lap").measure is objective_named("completed").measure is LAP_TIME
    assert SCORE.format(-31.5) == "score 31.50 points" and LAP_TIME.format(33.125) == "lap 33.12 s"
    assert CampaignConfig(objective="etrobocon").rule.failure_value == 0.0
    assert CampaignConfig(penalty_s=120.0).rule.failure_value == 120.0


SPACE = ParameterSpace((Parameter("Kp", Rx.KP, 0, 5),))


def test_the_campaign_keeps_the_highest_score_and_its_figures_and_files_show_scores(tmp_path):
    config = CampaignConfig(space=SPACE, init_points=3, trials=2, repeats=1, optimizer="random", objective="etrobocon")
    totals = [10.0, 25.0, 18.0, 31.0, 2.0]
    summary = Campaign(config, tmp_path, ScriptedBench([scored(Event.FINISH, t) for t in totals])).run()
    best = summary.best
    assert best is not None and best.number == 4 and best.value == -(31.0 + 3)
    assert "score 34.00 points (set 4)" in format_summary(summary)
    d = best_dict(summary)
    assert (d["score"], d["scores"]) == (34.0, [34.0]) and "lap_time_s" not in d
    write_report(tmp_path, summary)
    rows = list(csv.DictReader(open(tmp_path / "results.csv")))
    assert [float(r["objective"]) for r in rows] == [t + 3 for t in totals]
    assert [float(r["best_so_far"]) for r in rows] == [13.0, 28.0, 28.0, 34.0, 34.0]
    *_, ax = fig8(summary).axes
    assert ax.get_ylabel() == "score [points]"
    assert list(ax.get_lines()[1].get_ydata()) == [t + 3 for t in totals]  # the successes, as scores


@pytest.mark.parametrize("objective", ["lap", "completed"])
def test_time_objectives_keep_their_files_as_they_were(tmp_path, objective):
    config = CampaignConfig(space=SPACE, init_points=2, trials=0, repeats=1, optimizer="random", objective=objective)
    summary = Campaign(config, tmp_path, ScriptedBench([TestResult(Event.GOAL, 30_000_000, 0.01)] * 2)).run()
    write_report(tmp_path, summary)
    assert "objective_s" in (tmp_path / "results.csv").read_text().splitlines()[0]
    assert best_dict(summary)["lap_time_s"] == 30.0


def test_a_validation_of_the_best_set_reports_its_scores():
    from testctl.campaign.validate import Validation

    results = (scored(Event.FINISH, 20.0), scored(Event.TIME_OVER, 24.0))
    v = Validation((1, 2), results, -25.0, SCORE)
    assert v.scores == [23.0, 27.0]
    assert "score mean 25.00 (min 23, max 27)" in v.describe() and "estimate: score 25.00 points" in v.describe()
    assert v.to_dict()["campaign_estimate"] == 25.0 and "campaign_estimate_s" not in v.to_dict()
    assert "campaign_estimate_s" in Validation((1,), results[:1], 33.0).to_dict()
