"""Every campaign is an Optuna study mirroring its journal: a trial per decided set, in set order, with its
params, value and tests; rebuilt or completed from the journal after a kill, a deletion or a truncation, so
that it always equals the study of an uninterrupted run."""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import optuna
import pytest
from optuna.artifacts import get_all_artifact_meta
from optuna.distributions import FloatDistribution, IntDistribution

from hakoniwa.wire.protocol import Rx
from testctl.campaign import study as study_module
from testctl.campaign.loop import Campaign, CampaignConfig, CampaignSummary
from testctl.campaign.study import STUDY_FILE, StudyMirror, attach, open_storage, trajectory_png
from testctl.search.space import Parameter, ParameterSpace
from tests.campaign.test_campaign_parallel import NoisyBench, ShuffledExecutor
from tests.helpers.campaign_doubles import Killed, KilledAfter, SyntheticBench

# 6 sets of 2 tests each on the deterministic synthetic bench; several improve on the best before them.
CONFIG = CampaignConfig(init_points=3, trials=3, repeats=3, seed=11, optimizer="random")


class Drawer:
    """Stands for a bench drawing a set's trajectory: a PNG-named file whose bytes say which set it is."""

    def __init__(self) -> None:
        self.sets: list[int] = []

    def __call__(self, s, png: Path) -> None:
        self.sets.append(s.number)
        png.write_bytes(f"trajectory of set {s.number}".encode())


def run(out: Path, config: CampaignConfig = CONFIG, bench=None, *, resume: bool = False,
        draw: Drawer | None = None) -> CampaignSummary:
    mirror = StudyMirror(out, draw or Drawer())
    return Campaign(config, out, bench or SyntheticBench(), on_sets=mirror.update, resume=resume).run()


def load(out: Path) -> optuna.Study:
    return optuna.load_study(study_name=out.resolve().name, storage=open_storage(out))


def essence(out: Path) -> list[tuple]:
    """What must match between two studies of one campaign: every trial but its clock and artifact ids."""
    study = load(out)
    return [(t.number, t.state, t.params, t.distributions, t.value, t.user_attrs,
             sorted(m.filename for m in get_all_artifact_meta(t, storage=study._storage)))
            for t in study.get_trials(deepcopy=False)] + [study.user_attrs]


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> tuple[list[tuple], CampaignSummary]:
    out = tmp_path_factory.mktemp("uninterrupted") / "c"
    summary = run(out)
    return essence(out), summary


def test_every_decided_set_is_a_trial(reference, tmp_path: Path) -> None:
    _, summary = reference
    out = tmp_path / "c"
    drawer = Drawer()
    run(out, draw=drawer)
    study = load(out)
    assert study.study_name == "c" and study.direction == optuna.study.StudyDirection.MINIMIZE
    assert study.metric_names == ["lap time [s]"]
    assert study.user_attrs["optimizer"] == "random" and study.user_attrs["seed"] == 11
    trials = study.get_trials()
    assert [t.number for t in trials] == [s.index for s in summary.sets] == list(range(6))
    improving, best = [], None
    for t, s in zip(trials, summary.sets):
        assert t.state == optuna.trial.TrialState.COMPLETE
        assert t.value == s.value  # penalties included: a failed set is scored the time limit
        assert t.params == CONFIG.space.to_named(s.x)
        assert t.distributions == {p.name: FloatDistribution(p.low, p.high) for p in CONFIG.space.params}
        attrs = t.user_attrs
        assert attrs["set"] == s.number and attrs["success"] == s.verdict.success and attrs["campaign_seed"] == 11
        assert [(d["rep"], d["noise_seed"], d["event"], d["lap_s"]) for d in attrs["tests"]] == [
            (r.rep, r.noise_seed, r.result.event.name, r.result.lap_time_s) for r in s.tests]
        files = get_all_artifact_meta(t, storage=study._storage)
        if s.verdict.success and (best is None or s.value < best):
            best = s.value
            improving.append(s.number)
            (meta,) = files
            assert meta.filename == trajectory_png(out, s).name and meta.mimetype == "image/png"
            with study_module.artifact_store(out).open_reader(meta.artifact_id) as f:
                assert f.read() == f"trajectory of set {s.number}".encode()
        else:
            assert files == []
    assert len(improving) >= 2 and drawer.sets == improving
    assert summary.best is not None and summary.best.number in improving


@pytest.mark.parametrize("k", [1, 4, 7])  # killed after that many tests: inside the initial design, later
@pytest.mark.parametrize("damage", ["none", "deleted", "torn", "cut at a line", "emptied"])
def test_kill_damage_the_study_then_resume_equals_an_uninterrupted_run(reference, tmp_path: Path, k: int,
                                                                        damage: str) -> None:
    out = tmp_path / "c"
    with pytest.raises(Killed):
        run(out, bench=KilledAfter(SyntheticBench(), k))
    path = out / STUDY_FILE
    data = path.read_bytes()
    if damage == "deleted":
        path.unlink()
    elif damage == "torn":
        path.write_bytes(data[: len(data) * 2 // 3])
    elif damage == "cut at a line":
        path.write_bytes(b"".join(data.splitlines(keepends=True)[:-1]))
    elif damage == "emptied":
        path.write_bytes(b"")
    run(out, resume=True)
    assert essence(out) == reference[0]


def test_a_study_behind_its_journal_is_completed_not_rebuilt(reference, tmp_path: Path) -> None:
    """A campaign extended on resume adds its new sets' trials to the study as it was: a note written in the
    dashboard meanwhile (a study system attribute) survives."""
    out = tmp_path / "c"
    run(out, dataclasses.replace(CONFIG, trials=1))
    study = load(out)
    study._storage.set_study_system_attr(study._study_id, "dashboard:note", "kept")  # as the dashboard does
    run(out, resume=True)
    assert essence(out) == reference[0]
    study = load(out)
    assert study._storage.get_study_system_attrs(study._study_id)["dashboard:note"] == "kept"


def test_a_trial_a_kill_left_running_is_finished(reference, tmp_path: Path, monkeypatch) -> None:
    out = tmp_path / "c"

    def killed(self, *args, **kwargs):
        raise Killed

    with monkeypatch.context() as m:
        m.setattr(StudyMirror, "_finish", killed)
        with pytest.raises(Killed):
            run(out)
    assert [t.state for t in load(out).get_trials()] == [optuna.trial.TrialState.RUNNING]
    run(out, resume=True)
    assert essence(out) == reference[0]


def test_another_campaigns_study_is_replaced(reference, tmp_path: Path) -> None:
    other = tmp_path / "other" / "c"
    run(other, dataclasses.replace(CONFIG, seed=12))
    out = tmp_path / "c"
    run(out)
    shutil.copy(other / STUDY_FILE, out / STUDY_FILE)
    run(out, resume=True)
    assert essence(out) == reference[0]


def test_a_batch_writes_its_trials_in_set_order(tmp_path: Path) -> None:
    """Sets of a round finish in any order on several benches; trial i is still set i + 1."""
    config = CampaignConfig(init_points=4, trials=6, repeats=5, seed=11, optimizer="random", batch=3, noise=1.0)
    out = tmp_path / "c"
    mirror = StudyMirror(out, Drawer())
    summary = Campaign(config, out, ShuffledExecutor(NoisyBench(), 4, seed=3), on_sets=mirror.update).run()
    trials = load(out).get_trials()
    assert [(t.number, t.user_attrs["set"], t.value) for t in trials] == [(s.index, s.number, s.value)
                                                                         for s in summary.sets]


def test_integer_parameters_have_int_distributions(tmp_path: Path) -> None:
    space = ParameterSpace(params=(Parameter("Kp", Rx.KP, 0.0, 5.0), Parameter("Ki", Rx.KI, 0.0, 5.0),
                                   Parameter("Kd", Rx.KD, 0.0, 5.0, type="int")),
                           fixed=ParameterSpace.default().fixed)
    out = tmp_path / "c"
    run(out, dataclasses.replace(CONFIG, space=space))
    for t in load(out).get_trials():
        assert t.distributions["Kd"] == IntDistribution(0, 5) and isinstance(t.params["Kd"], int)
        assert t.distributions["Kp"] == FloatDistribution(0.0, 5.0)


def test_a_campaign_file_is_attached_to_the_study_once(tmp_path: Path) -> None:
    out = tmp_path / "c"
    run(out)
    png = out / "best_trajectory.png"
    png.write_bytes(b"first")
    attach(out, png)
    attach(out, png)  # a report rewritten on resume draws the same picture
    png.write_bytes(b"second")
    attach(out, png)
    assert [m.filename for m in get_all_artifact_meta(load(out))] == ["best_trajectory.png"] * 2
