"""ET Robocon's end of a run: `ETRoboc_notifyCompletedToSimulator()` is recorded with the time it came, and
`--objective completed` (bench option of `hako try`, `hako run`, `hako test`) scores a test by that time:
the goal line no longer ends the test, a test the notice never comes to fails, and the journal records the
objective."""

from __future__ import annotations

import json
import os

import pytest

from hakoniwa.wire.objective import objective_named
from hakoniwa.wire.protocol import Event
from hakoniwa.wire.result import TestResult
from testctl.campaign.journal import JOURNAL_FILE, read_journal
from testctl.campaign.repetition import RepetitionRule
from testctl.lapstats import LapStats
from testctl.suite.expect import parse_expectation
from tests.helpers.commands import hako

DONE_S = 50  # past the first lap with the paper's gains (GOAL at 35.68 s) and its next checkpoint
# The paper's Fig. 7 tracer that says its run is complete once DONE_S have passed, as an ET Robocon program
# ends its competition run: from the first wake-up at or after DONE_S on.
DONE_APP = f'''
from athrill_sim.apps import line_trace
from athrill_sim.mock.ev3api import tx
from hakoniwa.wire.protocol import Tx


def main_task(api):
    sleep = api.tslp_tsk

    def tslp_tsk(us):
        if api.kernel.now_us >= {DONE_S}_000_000:
            api.bus.write("i", tx(Tx.COMPLETED), 1)
        return sleep(us)

    api.tslp_tsk = tslp_tsk
    line_trace.main_task(api)
'''


def completed(at_s: float | None, event: Event = Event.COMPLETED, objective: str = "completed") -> TestResult:
    return TestResult(event, 0, 0.01, completed_time_us=0 if at_s is None else round(at_s * 1e6),
                      objective=objective_named(objective))


def test_under_the_completed_objective_the_notice_is_the_success_and_its_time_the_score():
    rule = RepetitionRule(repeats=3, penalty_s=120.0)
    v = rule.judge([completed(40.0), completed(None, Event.TIME_OVER), completed(42.0)])
    assert (v.decided, v.success, v.value) == (True, True, pytest.approx(41.0))
    # A test the notice never came to fails, whatever else happened; a lap no longer succeeds.
    v = rule.judge([completed(None, Event.GOAL), completed(None, Event.HIT_WALL)])
    assert (v.decided, v.success, v.value) == (True, False, 120.0)
    # Under the lap objective, COMPLETED stays a failure, as before.
    v = rule.judge([completed(30.0, objective="lap")] * 2)
    assert (v.decided, v.success) == (True, False)


def test_a_results_record_keeps_the_time_and_the_objective():
    r = completed(40.0)
    assert r.success and r.lap_time_s == 40.0 and r.success_event == Event.COMPLETED
    assert TestResult.from_dict(r.to_dict(), 0.0) == TestResult.from_dict({**r.to_dict()}, 0.0)
    again = TestResult.from_dict(r.to_dict(), r.wall_s)
    assert again == r and r.to_dict()["objective"] == "completed" and r.to_dict()["completed_time_us"] == 40_000_000
    lap = TestResult(Event.GOAL, 30_000_000, 0.0)
    assert "objective" not in lap.to_dict() and "completed_time_us" not in lap.to_dict()  # as before
    assert TestResult.from_dict({"event": "GOAL", "goal_time_us": 30_000_000}, 0.0) == lap  # an old journal's


def test_expectations_and_statistics_read_the_completion_time():
    runs = [completed(40.0), completed(44.0), completed(None, Event.HIT_WALL)]
    labels = ["a", "b", "c"]
    assert parse_expectation("success >= 0.6").check(runs, labels).passed
    assert parse_expectation("p50 <= 44").check(runs, labels).passed
    assert not parse_expectation("lap_s < 45").check(runs, labels).passed  # c never completed
    stats = LapStats.of(runs)
    assert stats.laps_s == (40.0, 44.0) and "2/3 reached COMPLETED" in stats.describe()


@pytest.fixture
def done_app(tmp_path) -> dict:
    apps = tmp_path / "apps"
    apps.mkdir()
    (apps / "done_app.py").write_text(DONE_APP)
    return dict(os.environ, PYTHONPATH=os.pathsep.join([str(apps), os.environ.get("PYTHONPATH", "")]))


def trial(env: dict, *args: str) -> dict:
    out = hako("try", "--app", "done_app:main_task", "--noise", "0", "--json", *args, env=env, timeout=300)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def test_the_notice_is_recorded_with_its_time_and_ends_the_run_under_the_completed_objective(done_app):
    lap = trial(done_app)
    assert lap["event"] == "GOAL" and lap["lap_time_s"] < DONE_S and "completed_time_us" not in lap
    done = trial(done_app, "--objective", "completed")
    # The goal line no longer ends the test: the program drives on into its second lap, then says it is done.
    assert done["event"] == "COMPLETED" and done["completed_time_us"] == DONE_S * 1_000_000
    assert done["lap_time_s"] == DONE_S and done["objective"] == "completed" and done["checkpoints"] > 4
    assert trial(done_app, "--objective", "completed", "--time-limit", "20")["event"] == "TIME_OVER"


def test_an_unknown_objective_is_one_line():
    r = hako("try", "--objective", "fastest", timeout=60)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert "'fastest' is not one of 'lap', 'completed'" in r.stderr


@pytest.mark.slow
def test_hako_test_and_a_campaign_score_by_the_completion(done_app, tmp_path):
    tests = tmp_path / "hako-tests.toml"
    tests.write_text('[case.done]\napp = "done_app:main_task"\nobjective = "completed"\nseeds = 2\nnoise = 0\n'
                     'params = { Kp = 1.539, Ki = 4.267, Kd = 4.511 }\n'
                     f'expect = ["COMPLETED", "lap_s <= {DONE_S}.1", '
                     '"checkpoints > 4"]\n')
    r = hako("test", str(tests), "--benches", "1", "--out", str(tmp_path / "test-out"), env=done_app, timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    out = tmp_path / "campaign"
    r = hako("run", "--app", "done_app:main_task", "--objective", "completed", "--smoke", "--benches", "1",
             "--validate", "0", "--out", str(out), env=done_app, timeout=600)
    assert r.returncode == 0, r.stderr
    header, records = read_journal(out / JOURNAL_FILE)
    assert header["bench"]["objective"] == "completed"
    assert {rec.result.objective for rec in records} == {objective_named("completed")}
    for rec in records:
        assert rec.result.success == (rec.result.event == Event.COMPLETED)
    best = json.loads((out / "best.json").read_text())
    assert not best["success"] or best["lap_time_s"] == pytest.approx(DONE_S)
    resumed = hako("run", "--resume", str(out), "--objective", "lap", env=done_app, timeout=120)
    assert resumed.returncode != 0 and "--objective 'lap' (given) vs 'completed' (journal)" in resumed.stderr
