"""Validating a campaign's best set on fresh noise draws, and the picture of how its laps spread."""

from __future__ import annotations

import json

import pytest

from hakoniwa.wire.protocol import Event
from testctl.campaign.journal import JOURNAL_FILE, PHASE_VALIDATION, read_journal
from testctl.campaign.loop import Campaign, CampaignConfig
from testctl.campaign.validate import validate_best, validation_specs
from testctl.executor import BenchFault, SerialExecutor
from testctl.lap_figure import lap_figure
from testctl.options import MAX_DRAWS, VALIDATE_KEY, plan
from tests.helpers.campaign_doubles import BENCH_FAULT, Killed, SyntheticBench, result
from tests.helpers.commands import hako, one_line_error


def campaign(tmp_path, **options):
    config = CampaignConfig(optimizer="random", trials=4, init_points=2, repeats=3, seed=5, noise=1.0, **options)
    return Campaign(config, tmp_path / "c", SyntheticBench()).run()


def test_the_draws_are_fresh_and_the_same_for_the_same_campaign(tmp_path):
    summary = campaign(tmp_path)
    specs = validation_specs(summary, 12)
    used = {t.noise_seed for s in summary.sets for t in s.tests}
    assert len({s.noise_seed for s in specs}) == 12 and not used & {s.noise_seed for s in specs}
    assert {s.set_index for s in specs} == {summary.best.index}
    assert all(s.rep > summary.config.repeats and s.noise_scale == 1.0 for s in specs)
    assert specs == validation_specs(campaign(tmp_path / "again"), 12)


def test_the_best_set_is_judged_on_every_draw(tmp_path):
    summary = campaign(tmp_path)
    bench = SyntheticBench()
    validation = validate_best(summary, SerialExecutor(bench), 6, tmp_path / "c")
    assert len(bench.calls) == 6 and validation.seeds == tuple(s.noise_seed for s in bench.calls)
    d = validation.to_dict()
    assert d["draws"] == d["runs"] == 6 and d["success"] == 1.0 and d["campaign_estimate_s"] == summary.best.value
    assert d["events"] == {"GOAL": 6}
    assert "validation on 6 fresh noise draws: 6/6 reached GOAL" in validation.describe()


def test_a_bench_fault_voids_the_validation(tmp_path):
    summary = campaign(tmp_path)
    with pytest.raises(BenchFault, match="spoiled a test"):
        validate_best(summary, SerialExecutor(lambda spec: BENCH_FAULT), 3, tmp_path / "c")


def test_the_lap_figure_has_a_legend_naming_the_estimate_and_the_misses():
    runs = [result(Event.GOAL, 32.0 + i / 10) for i in range(8)] + [result(Event.HIT_WALL)]
    fig = lap_figure(runs, "t", estimate_s=31.5)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert labels == ["lap of a run that reached GOAL (8 of 9)", "p50 of all runs: 32.40 s",
                      "campaign's estimate (mean lap): 31.50 s", "no lap: 1 HIT_WALL"]


@pytest.mark.slow
def test_hako_run_reports_the_best_sets_robustness(tmp_path):
    out = tmp_path / "smoke"
    r = hako("run", "--smoke", "--validate", "4", "--out", str(out))
    assert r.returncode == 0, r.stderr
    best = json.loads((out / "best.json").read_text())
    v = best["validation"]
    assert v["draws"] == v["runs"] == 4 and len(v["noise_seeds"]) == 4 and 0 <= v["success"] <= 1
    assert v["campaign_estimate_s"] == best["lap_time_s"]
    assert f"validation on 4 fresh noise draws: {v['successes']}/4 reached GOAL" in r.stdout
    assert (out / "validation.png").stat().st_size > 0


@pytest.mark.slow
def test_validate_0_skips_it(tmp_path):
    r = hako("run", "--smoke", "--validate", "0", "--out", str(tmp_path))
    assert r.returncode == 0, r.stderr
    assert "validation" not in json.loads((tmp_path / "best.json").read_text())
    assert "validation" not in r.stdout and not (tmp_path / "validation.png").exists()
    resumed = hako("run", "--resume", str(tmp_path))  # keeps --validate 0 (it once fell back to 20)
    assert resumed.returncode == 0, resumed.stderr
    assert "validation" not in resumed.stdout and not (tmp_path / "validation.png").exists()


def test_an_interrupted_validation_resumes_with_the_draws_it_lacks(tmp_path):
    summary = campaign(tmp_path)
    clean = validate_best(summary, SerialExecutor(SyntheticBench()), 8, tmp_path / "c")
    interrupted = campaign(tmp_path / "again")
    seen = []

    def stop_after_three(spec, result):
        seen.append(spec.rep)
        if len(seen) == 3:
            raise Killed

    with pytest.raises(Killed):
        validate_best(interrupted, SerialExecutor(SyntheticBench()), 8, tmp_path / "again" / "c", stop_after_three)
    _, records = read_journal(tmp_path / "again" / "c" / JOURNAL_FILE)
    assert [r.rep for r in records if r.phase == PHASE_VALIDATION] == seen
    bench = SyntheticBench()
    resumed = validate_best(interrupted, SerialExecutor(bench), 8, tmp_path / "again" / "c")
    assert sorted(s.rep for s in bench.calls) == [s.rep for s in validation_specs(interrupted, 8)][3:]
    assert resumed == clean
    # the campaign's search reads none of them: resuming it runs nothing and decides the same sets
    again = Campaign(interrupted.config, tmp_path / "again" / "c", SyntheticBench(), resume=True).run()
    assert again.sets == interrupted.sets and again.tests_run == 0


def test_a_resumed_campaign_keeps_its_validate_setting(tmp_path):
    config = CampaignConfig(optimizer="random", trials=0, init_points=1, repeats=1)
    Campaign(config, tmp_path, SyntheticBench(), header={VALIDATE_KEY: 0}).run()
    p = plan(None, None, None, None, None, None, None, None, None, tmp_path, False, penalty_s=60.0)
    p.lock.release()
    assert p.validate == 0


def test_validate_beyond_its_bound_is_one_line():
    r = hako("run", "--validate", str(MAX_DRAWS + 1))
    one_line_error(r, f"{MAX_DRAWS + 1} draws is more than {MAX_DRAWS}")
    assert r.returncode == 2
