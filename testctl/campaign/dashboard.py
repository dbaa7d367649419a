"""`hako dashboard RUN_DIR...`: optuna-dashboard on the studies of several campaigns at once, live.

optuna-dashboard serves one storage and one artifact store; each campaign has its own (`optuna.log`,
`optuna-artifacts/`, `testctl.campaign.study`). So the campaigns' storages are put behind one (`CampaignStorages`):
study and trial ids are interleaved (id = local id x n + k for campaign k of n), every call goes to the
campaign that owns the id, and each campaign's JournalStorage reads what its campaign appended since the last
call, which is what makes the page live while a campaign runs. Artifacts are looked up in every campaign's
store (their ids are UUIDs). Writes the dashboard makes (notes, a trial's user attributes) go to the owning
study's file, under Optuna's lock, beside the campaign's own writes; creating and deleting studies is
refused: a campaign's study is the mirror of its journal.

optuna-dashboard is an optional extra; without it `DashboardError` says what to install.
"""

from __future__ import annotations

import copy
import errno
import importlib.util
from collections.abc import Container, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, BinaryIO

from optuna.storages import BaseStorage

from hakoniwa.wire.errors import HakoError
from testctl.campaign.journal import JOURNAL_FILE
from testctl.campaign.study import ARTIFACT_DIR, STUDY_FILE, open_storage

if TYPE_CHECKING:
    from optuna.study import StudyDirection
    from optuna.study._frozen import FrozenStudy  # optuna.study exports it at run time only
    from optuna.trial import FrozenTrial, TrialState

INSTALL = "pip install -e '.[dashboard]' (or pip install optuna-dashboard)"


class DashboardError(HakoError, RuntimeError):
    """A one-line reason the dashboard cannot start."""


def check_installed() -> None:
    if importlib.util.find_spec("optuna_dashboard") is None:
        raise DashboardError(f"hako dashboard needs optuna-dashboard, which is not installed: {INSTALL}")


def campaign_storage(run_dir: Path) -> BaseStorage:
    """The study storage of the campaign in `run_dir`, or a DashboardError saying why there is none."""
    run_dir = Path(run_dir)
    if not run_dir.is_dir():
        raise DashboardError(f"{run_dir}: no such folder")
    if not (run_dir / JOURNAL_FILE).is_file():
        raise DashboardError(f"{run_dir} is no campaign (it has no {JOURNAL_FILE})")
    if not (run_dir / STUDY_FILE).is_file():
        raise DashboardError(f"{run_dir} has no {STUDY_FILE} yet (a campaign from before studies): "
                             f"hako run --resume {run_dir} writes it")
    try:
        return open_storage(run_dir)
    except ValueError as e:
        raise DashboardError(f"{run_dir / STUDY_FILE}: Optuna cannot read it ({e}); hako run --resume {run_dir} "
                             "rebuilds it from the journal") from None


class CampaignStorages(BaseStorage):
    """Several storages as one, for optuna-dashboard (see the module's docstring)."""

    def __init__(self, storages: Sequence[BaseStorage], labels: Sequence[str]) -> None:
        self._storages = list(storages)
        self._labels = list(labels)  # what names a study when two campaigns' studies share a name

    # -- ids ------------------------------------------------------------------------------------------
    def _split(self, global_id: int) -> tuple[BaseStorage, int, int]:
        n = len(self._storages)
        return self._storages[global_id % n], global_id // n, global_id % n

    def _local(self, method: str, global_id: int, *args: Any) -> Any:
        """Call `method` of the storage owning `global_id` with its local id."""
        storage, local, _ = self._split(global_id)
        return getattr(storage, method)(local, *args)

    def _join(self, local_id: int, k: int) -> int:
        return local_id * len(self._storages) + k

    def _trial(self, trial: FrozenTrial, k: int) -> FrozenTrial:
        out = copy.copy(trial)
        out._trial_id = self._join(trial._trial_id, k)
        return out

    # -- studies --------------------------------------------------------------------------------------
    def get_all_studies(self) -> list[FrozenStudy]:
        studies = [(k, s) for k, storage in enumerate(self._storages) for s in storage.get_all_studies()]
        names = [s.study_name for _, s in studies]
        out = []
        for k, s in studies:
            s = copy.copy(s)
            if names.count(s.study_name) > 1:
                s.study_name = f"{s.study_name} ({self._labels[k]})"
            s._study_id = self._join(s._study_id, k)
            out.append(s)
        return out

    def get_study_name_from_id(self, study_id: int) -> str:
        return next(s.study_name for s in self.get_all_studies() if s._study_id == study_id)

    def get_study_id_from_name(self, study_name: str) -> int:
        for s in self.get_all_studies():
            if s.study_name == study_name:
                return s._study_id
        raise KeyError(f"no study named {study_name!r}")

    def get_study_directions(self, study_id: int) -> list[StudyDirection]:
        return self._local("get_study_directions", study_id)

    def get_study_user_attrs(self, study_id: int) -> dict[str, Any]:
        return self._local("get_study_user_attrs", study_id)

    def get_study_system_attrs(self, study_id: int) -> dict[str, Any]:
        return self._local("get_study_system_attrs", study_id)

    def set_study_user_attr(self, study_id: int, key: str, value: Any) -> None:
        self._local("set_study_user_attr", study_id, key, value)

    def set_study_system_attr(self, study_id: int, key: str, value: Any) -> None:
        self._local("set_study_system_attr", study_id, key, value)

    def create_new_study(self, directions: Sequence[StudyDirection], study_name: str | None = None) -> int:
        raise NotImplementedError("hako dashboard shows campaigns; start one with hako run")

    def delete_study(self, study_id: int) -> None:
        raise NotImplementedError("a campaign's study mirrors its journal; delete the campaign's folder instead")

    # -- trials ---------------------------------------------------------------------------------------
    def get_all_trials(self, study_id: int, deepcopy: bool = True,
                       states: Container[TrialState] | None = None) -> list[FrozenTrial]:
        storage, local, k = self._split(study_id)
        return [self._trial(t, k) for t in storage.get_all_trials(local, deepcopy=deepcopy, states=states)]

    def get_trial(self, trial_id: int) -> FrozenTrial:
        storage, local, k = self._split(trial_id)
        return self._trial(storage.get_trial(local), k)

    def get_trial_id_from_study_id_trial_number(self, study_id: int, trial_number: int) -> int:
        storage, local, k = self._split(study_id)
        return self._join(storage.get_trial_id_from_study_id_trial_number(local, trial_number), k)

    def create_new_trial(self, study_id: int, template_trial: FrozenTrial | None = None) -> int:
        storage, local, k = self._split(study_id)
        return self._join(storage.create_new_trial(local, template_trial), k)

    def set_trial_param(self, trial_id: int, param_name: str, param_value_internal: float,
                        distribution: Any) -> None:
        self._local("set_trial_param", trial_id, param_name, param_value_internal, distribution)

    def set_trial_state_values(self, trial_id: int, state: TrialState,
                               values: Sequence[float] | None = None) -> bool:
        return self._local("set_trial_state_values", trial_id, state, values)

    def set_trial_intermediate_value(self, trial_id: int, step: int, intermediate_value: float) -> None:
        self._local("set_trial_intermediate_value", trial_id, step, intermediate_value)

    def set_trial_user_attr(self, trial_id: int, key: str, value: Any) -> None:
        self._local("set_trial_user_attr", trial_id, key, value)

    def set_trial_system_attr(self, trial_id: int, key: str, value: Any) -> None:
        self._local("set_trial_system_attr", trial_id, key, value)


class CampaignArtifacts:
    """The campaigns' artifact stores as one (Optuna's ArtifactStore protocol): an id is in one of them."""

    def __init__(self, run_dirs: Sequence[Path]) -> None:
        from optuna.artifacts import FileSystemArtifactStore

        self._stores = [FileSystemArtifactStore(str(Path(d) / ARTIFACT_DIR)) for d in run_dirs]
        self._folders = [Path(d) / ARTIFACT_DIR for d in run_dirs]

    def _owner(self, artifact_id: str) -> Any:
        from optuna.artifacts.exceptions import ArtifactNotFound

        for store, folder in zip(self._stores, self._folders):
            if (folder / artifact_id).is_file():
                return store
        raise ArtifactNotFound(f"no artifact {artifact_id}")

    def open_reader(self, artifact_id: str) -> BinaryIO:
        return self._owner(artifact_id).open_reader(artifact_id)

    def write(self, artifact_id: str, content_body: BinaryIO) -> None:
        raise NotImplementedError("artifacts come from the campaigns")

    def remove(self, artifact_id: str) -> None:
        self._owner(artifact_id).remove(artifact_id)


def make_app(run_dirs: Sequence[Path]) -> Any:
    """optuna-dashboard's WSGI application on the campaigns in `run_dirs`."""
    check_installed()
    import optuna_dashboard

    storages = [campaign_storage(d) for d in run_dirs]
    return optuna_dashboard.wsgi(CampaignStorages(storages, [str(d) for d in run_dirs]),
                                 artifact_store=CampaignArtifacts(run_dirs))


def make_server(app: Any, host: str, port: int) -> Any:
    """A threaded WSGI server bound to (host, port), quiet about each request; a port in use (or a host that
    is not this machine's) is a DashboardError."""
    from socketserver import ThreadingMixIn
    from wsgiref.simple_server import WSGIRequestHandler, WSGIServer
    from wsgiref.simple_server import make_server as wsgi_server

    class Server(ThreadingMixIn, WSGIServer):
        daemon_threads = True

    class Quiet(WSGIRequestHandler):
        def log_message(self, format: str, *args: Any) -> None:
            pass

    try:
        return wsgi_server(host, port, app, server_class=Server, handler_class=Quiet)
    except OSError as e:
        raise DashboardError(f"cannot serve on {host}:{port}: {e.strerror or e}"
                             + ("; choose another with --port" if e.errno == errno.EADDRINUSE else "")) from None
