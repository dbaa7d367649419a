"""Every campaign is also an Optuna study: `optuna.log` in the campaign folder, an Optuna journal
(`JournalStorage` over `JournalFileBackend`) that optuna-dashboard, `optuna.load_study` and the rest of Optuna's
ecosystem read as they read any study.

`journal.jsonl` stays the one source of truth; the study mirrors it, through Optuna's API only. Each decided
parameter set is a trial, numbered as the set less one (Optuna counts from 0), written when the set is
decided and in set order (a batch's sets finish in any order; a trial waits for the sets before it), with:
- its params and their distributions (`optuna_samplers.distributions`: IntDistribution for an integer one);
- its value as the journal scores it, penalties included, so a failed set is a COMPLETE trial at the limit;
- user attributes: each test's repetition, noise seed, event, lap, checkpoints and distance, the verdict's
  counts, and the campaign's seed, program hash and bench. Nothing that depends on the clock or on which
  bench ran it (wall times, bench names): a study rebuilt from the journal equals the one written live;
- for a set that was the best so far when it was decided, its trajectory PNG (kept under `trajectories/`)
  as an Optuna artifact in `optuna-artifacts/`. Optuna takes artifacts only on a trial not yet finished, so
  such a trial is added RUNNING, given its artifact, then told its value; the campaign's best set, not
  known until the end, is always one of them. Files known only at the end (best_trajectory.png) go to the
  study (`attach`).

When the study is missing, damaged (a torn last line, a line that is not Optuna's) or disagrees with the
journal, it is rebuilt from the journal; when it is only behind (a kill between a test and the study's
write), the missing trials are added. A trial left RUNNING by a kill is finished. Notes written in the
dashboard live in the study and are lost only when it has to be rebuilt.
"""

from __future__ import annotations

import hashlib
import json
import shutil
import warnings
from collections.abc import Callable, Sequence
from datetime import datetime, timedelta
from pathlib import Path
from typing import TYPE_CHECKING, Any

from testctl.campaign.journal import JOURNAL_FILE, TestRecord, read_journal
from testctl.campaign.loop import CampaignConfig, SetResult
from testctl.search.optuna_samplers import distributions, params_of, quiet_optuna

if TYPE_CHECKING:
    import optuna

STUDY_FILE = "optuna.log"
ARTIFACT_DIR = "optuna-artifacts"
TRAJECTORY_DIR = "trajectories"
# Draws set `s`'s trajectory into the PNG at the path given.
DrawSet = Callable[[SetResult, Path], object]  # what it returns is not used


def study_name(out_dir: Path) -> str:
    """The campaign's name: its folder's."""
    return Path(out_dir).resolve().name


def open_storage(out_dir: Path) -> optuna.storages.JournalStorage:
    """The campaign's study storage; a file Optuna cannot read raises ValueError."""
    from optuna.storages import JournalStorage
    from optuna.storages.journal import JournalFileBackend

    quiet_optuna()
    return JournalStorage(JournalFileBackend(str(Path(out_dir) / STUDY_FILE)))


def artifact_store(out_dir: Path) -> Any:
    from optuna.artifacts import FileSystemArtifactStore

    folder = Path(out_dir) / ARTIFACT_DIR
    folder.mkdir(exist_ok=True)
    return FileSystemArtifactStore(str(folder))


def trajectory_png(out_dir: Path, s: SetResult) -> Path:
    return Path(out_dir) / TRAJECTORY_DIR / f"set-{s.number:03d}.png"


def test_attrs(r: TestRecord) -> dict[str, Any]:
    """One test as the trial shows it; the keys a person looks for first."""
    res = r.result
    d = {"rep": r.rep, "noise_seed": r.noise_seed, "event": res.event.name, "lap_s": res.lap_time_s,
         "checkpoints": res.checkpoints, "distance_m": res.distance_m}
    if (reason := res.crash_reason()) is not None:
        d["crash"] = reason
    if res.score is not None:
        d["score"] = res.score.total
    return d


def campaign_attrs(header: dict[str, Any]) -> dict[str, Any]:
    """What every trial says of its campaign: the seed, the program's hash and the bench."""
    bench = {k: v for k, v in header.get("bench", {}).items() if k != "files" and v is not None}
    app_files = header.get("bench", {}).get("files", {}).get("app")
    attrs: dict[str, Any] = {"campaign_seed": header["options"]["seed"],
                             "bench": ", ".join(f"{k} {v}" for k, v in bench.items())}
    if app_files:
        attrs["program_hash"] = hashlib.sha256(json.dumps(app_files, sort_keys=True).encode()).hexdigest()[:16]
    return attrs


def study_attrs(header: dict[str, Any]) -> dict[str, Any]:
    """The campaign's settings, one attribute each, as the dashboard lists them; not `trials`, which a resume
    may extend."""
    options = {k: v for k, v in header["options"].items() if k != "trials"}
    space = CampaignConfig.from_header(header).space.describe()
    return {**options, "space": space, **{k: v for k, v in campaign_attrs(header).items() if k != "campaign_seed"}}


def trial_attrs(s: SetResult, campaign: dict[str, Any]) -> dict[str, Any]:
    v = s.verdict
    return {"set": s.number, "phase": s.phase, "success": v.success, "successes": v.successes,
            "failures": v.failures, "crashes": v.crashes, "tests": [test_attrs(t) for t in s.tests], **campaign}


def _span(s: SetResult) -> tuple[datetime, datetime]:
    """When the set's first test began and its last ended, as the journal recorded them."""
    ends = [(datetime.fromisoformat(t.timestamp).astimezone().replace(tzinfo=None), t.result.wall_s)
            for t in s.tests]  # local and naive, as Optuna's own times
    return min(end - timedelta(seconds=wall) for end, wall in ends), max(end for end, _ in ends)


class StudyMirror:
    """Keeps `out_dir`'s study equal to its journal's decided sets. `update` takes every set decided so far
    (the campaign calls it at its start, with none, and whenever one more is decided); `draw`, when given,
    draws a set's trajectory (a test on a bench), for the sets that improve on the best so far."""

    def __init__(self, out_dir: Path, draw: DrawSet | None = None) -> None:
        self.out_dir = Path(out_dir)
        self.draw = draw
        self._study: optuna.Study | None = None
        self._existing: list[optuna.trial.FrozenTrial] = []  # the trials the study held when opened
        self._written = 0  # trials 0 .. written-1 are the sets' and finished
        self._best: float | None = None  # the best successful value among them

    def update(self, sets: Sequence[SetResult]) -> None:
        by_index = {s.index: s for s in sets}
        if self._study is None:
            self._open()
        while self._written in by_index:
            s = by_index[self._written]
            if self._written >= len(self._existing):
                self._write(s)
                continue
            trial = self._existing[self._written]
            if self._same(trial, s):
                self._written += 1
                self._note_best(s)
            elif self._running(trial, s) and self._written == len(self._existing) - 1:  # what a kill left
                self._finish(trial, s)
            else:  # the study disagrees with the journal: it is rebuilt, and this loop writes it from set 1
                self._rebuild()

    @property
    def _metric(self) -> str:
        return self._config.measure.metric  # Optuna minimises what the campaign minimises

    # -- opening: create, check against the journal, or rebuild -----------------------------------------
    def _open(self) -> None:
        """Load the study (its trials are checked against the sets as they come), or create it."""
        header, _ = read_journal(self.out_dir / JOURNAL_FILE)
        self._config = CampaignConfig.from_header(header)
        self._campaign = campaign_attrs(header)
        self._header = header
        study = self._load()
        if study is None or study.user_attrs != study_attrs(header) or study.metric_names != [self._metric]:
            self._rebuild()  # missing, damaged, another campaign's, or cut before its attributes
        else:
            self._study = study
            self._existing = study.get_trials(deepcopy=False)

    def _load(self) -> optuna.Study | None:
        """The study as the file holds it, or None for no file, or one to be rebuilt."""
        import optuna

        path = self.out_dir / STUDY_FILE
        if not path.exists():
            return None
        data = path.read_bytes()
        if data and not data.endswith(b"\n"):  # torn by a kill: Optuna would append after the torn line
            return None
        try:
            return optuna.load_study(study_name=study_name(self.out_dir), storage=open_storage(self.out_dir))
        except (KeyError, ValueError):  # another study's file, or lines that are not Optuna's
            return None

    def _running(self, t: optuna.trial.FrozenTrial, s: SetResult) -> bool:
        from optuna.trial import TrialState

        return t.state == TrialState.RUNNING and t.number == s.index and t.params == params_of(self._config.space, s.x)

    def _same(self, t: optuna.trial.FrozenTrial, s: SetResult) -> bool:
        from optuna.trial import TrialState

        return (t.state == TrialState.COMPLETE and t.number == s.index and t.value == s.value
                and t.params == params_of(self._config.space, s.x) and t.user_attrs == trial_attrs(s, self._campaign))

    def _rebuild(self) -> None:
        import optuna

        for path in (self.out_dir / STUDY_FILE, self.out_dir / (STUDY_FILE + ".lock")):
            path.unlink(missing_ok=True)
        shutil.rmtree(self.out_dir / ARTIFACT_DIR, ignore_errors=True)  # the old study's; its ids die with it
        self._written, self._best, self._existing = 0, None, []
        study = optuna.create_study(storage=open_storage(self.out_dir), study_name=study_name(self.out_dir),
                                    direction="minimize")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
            study.set_metric_names([self._metric])
        for key, value in study_attrs(self._header).items():
            study.set_user_attr(key, value)
        self._study = study

    # -- writing ---------------------------------------------------------------------------------------
    def _write(self, s: SetResult) -> None:
        from optuna.trial import FrozenTrial, TrialState

        artifacts = self._artifacts(s)
        start, end = _span(s)
        state = TrialState.RUNNING if artifacts else TrialState.COMPLETE
        trial = FrozenTrial(number=s.index, state=state, value=None if artifacts else s.value, datetime_start=start,
                            datetime_complete=None if artifacts else end, params=params_of(self._config.space, s.x),
                            distributions=distributions(self._config.space),
                            user_attrs=trial_attrs(s, self._campaign), system_attrs={}, intermediate_values={},
                            trial_id=s.index)
        assert self._study is not None
        self._study.add_trial(trial)
        if artifacts:
            self._finish(self._study.get_trials(deepcopy=False)[s.index], s, artifacts)
        else:
            self._written += 1
            self._note_best(s)

    def _finish(self, trial: optuna.trial.FrozenTrial, s: SetResult, artifacts: list[Path] | None = None) -> None:
        """Give a RUNNING trial its artifacts (those it lacks) and tell it its set's value."""
        import optuna
        from optuna.artifacts import get_all_artifact_meta, upload_artifact

        assert self._study is not None
        have = {m.filename for m in get_all_artifact_meta(trial, storage=self._study._storage)}
        for path in self._artifacts(s) if artifacts is None else artifacts:
            if path.name not in have:
                upload_artifact(artifact_store=artifact_store(self.out_dir), file_path=str(path),
                                study_or_trial=optuna.Trial(self._study, trial._trial_id))
        self._study.tell(trial.number, s.value)
        self._written += 1
        self._note_best(s)

    def _artifacts(self, s: SetResult) -> list[Path]:
        """The files set `s`'s trial carries: its trajectory, if it improves on the sets before it."""
        if not self._improves(s):
            return []
        png = trajectory_png(self.out_dir, s)
        if not png.exists():
            if self.draw is None:
                return []
            png.parent.mkdir(exist_ok=True)
            self.draw(s, png)
        return [png]

    def _improves(self, s: SetResult) -> bool:
        return s.verdict.success and (self._best is None or s.value < self._best)

    def _note_best(self, s: SetResult) -> None:
        if self._improves(s):
            self._best = s.value


def attach(out_dir: Path, path: Path) -> None:
    """Put a file of the whole campaign (best_trajectory.png; a video of the best lap) into its study as an
    artifact, unless the study already holds the same bytes under that name (a report rewritten on
    resume draws the same picture again)."""
    import optuna
    from optuna.artifacts import get_all_artifact_meta, upload_artifact

    storage = open_storage(out_dir)
    study = optuna.load_study(study_name=study_name(out_dir), storage=storage)
    store = artifact_store(out_dir)
    data = Path(path).read_bytes()
    for meta in get_all_artifact_meta(study):
        if meta.filename == Path(path).name:
            with store.open_reader(meta.artifact_id) as f:
                if f.read() == data:
                    return
    upload_artifact(artifact_store=store, file_path=str(path), study_or_trial=study)
