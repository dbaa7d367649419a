"""A fourth objective from outside the package (issue 47): one module, named as module:attribute, with no file of
ours touched. "Distance driven" scores every run that ends without a crash by the path the robot drove, and the
campaign raises it."""

from __future__ import annotations

import json
import os
import sys

import pytest

from athrill_sim.programs.program import ProgramError
from hakoniwa.wire.objective import ObjectiveError, objective_named
from hakoniwa.wire.protocol import CrashKind, Event, Rx
from hakoniwa.wire.result import TestResult
from testctl.bench_options import BenchOptions
from testctl.campaign.journal import JOURNAL_FILE, read_journal
from testctl.campaign.loop import Campaign, CampaignConfig
from testctl.campaign.report import best_dict, format_summary
from testctl.search.space import Parameter, ParameterSpace
from tests.helpers.campaign_doubles import ScriptedBench
from tests.helpers.commands import hako

DISTANCE = '''
"""Distance driven: a run that ends without a crash scores the path the robot drove; more is better."""

from dataclasses import dataclass

from hakoniwa.objectives.lap import task
from hakoniwa.wire.measure import Measure
from hakoniwa.wire.objective import Objective
from hakoniwa.wire.protocol import Event


@dataclass(frozen=True)
class Distance(Objective):
    def success(self, r):
        return r.event != Event.CRASH

    def cost(self, r):
        return -r.distance_m if self.success(r) else None

    def set_value(self, mean_cost):
        return mean_cost

    def failure_value(self, penalty_s):
        return 0.0


OBJECTIVE = Distance("distance", Event.TIME_OVER, task, Measure("distance", "m", -1, "distance"))
'''
KEY = "distance_objective:OBJECTIVE"


@pytest.fixture
def plugin(tmp_path, monkeypatch) -> dict:
    """The module on the import path, of this process and of the benches it starts."""
    folder = tmp_path / "plugins"
    folder.mkdir()
    (folder / "distance_objective.py").write_text(DISTANCE)
    monkeypatch.syspath_prepend(str(folder))
    yield dict(os.environ, PYTHONPATH=os.pathsep.join([str(folder), os.environ.get("PYTHONPATH", "")]))
    sys.modules.pop("distance_objective", None)
    objective_named.cache_clear()


def drove(mm: int, event: Event = Event.HIT_WALL) -> TestResult:
    return TestResult(event, 0, 0.01, distance_mm=mm, objective=objective_named(KEY))


def test_a_plugin_judges_tests_and_a_campaign_keeps_the_longest_drive(plugin, tmp_path):
    assert drove(2500).success and drove(2500).cost == -2.5
    crash = TestResult(Event.CRASH, 0, 0.01, crash_kind=CrashKind.PROGRAM, objective=objective_named(KEY))
    assert not crash.success and crash.cost is None
    assert TestResult.decode(drove(1200).encode()) == drove(1200)  # the physics process sends it so
    config = CampaignConfig(space=ParameterSpace((Parameter("Kp", Rx.KP, 0, 5),)), init_points=3, trials=1,
                            repeats=1, optimizer="random", objective=KEY)
    summary = Campaign(config, tmp_path, ScriptedBench([drove(mm) for mm in (800, 3100, 1500, 2000)])).run()
    assert summary.best is not None and summary.best.number == 2 and summary.best.value == -3.1
    assert "distance 3.10 m (set 2)" in format_summary(summary)
    assert best_dict(summary)["distance"] == 3.1
    assert config.rule.judge([crash] * 4).value == 0.0  # a failed set drove nowhere


def test_an_objective_that_cannot_be_found_is_one_line(plugin):
    with pytest.raises(ProgramError, match=r"^--objective: 'distance_objective:NOPE' cannot be loaded"):
        BenchOptions(objective="distance_objective:NOPE")
    with pytest.raises(ObjectiveError, match="is a str, not a hakoniwa.wire.objective.Objective"):
        objective_named("distance_objective:__doc__")


@pytest.mark.slow
def test_hako_run_runs_a_campaign_on_it(plugin, tmp_path):
    out = tmp_path / "campaign"
    r = hako("run", "--objective", KEY, "--smoke", "--benches", "1", "--validate", "0", "--out", str(out),
             env=plugin, timeout=600)
    assert r.returncode == 0, r.stderr
    header, records = read_journal(out / JOURNAL_FILE)
    assert header["bench"]["objective"] == KEY
    assert records and all(rec.result.objective == objective_named(KEY) for rec in records)
    assert all(rec.result.cost == -rec.result.distance_m for rec in records if rec.result.event != Event.CRASH)
    best = json.loads((out / "best.json").read_text())
    drives = [rec.result.distance_m for rec in records if rec.set_index == best["set"] - 1 and rec.result.success]
    assert best["success"] and best["distances"] == drives
    assert best["distance"] == pytest.approx(sum(drives) / len(drives))
