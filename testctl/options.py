"""The campaign's command-line options, declared once for `hako run` and `testctl campaign`.

They are checked in the user's process, before any bench starts, so a bad space file, a folder that takes
no files or a resume under other settings is a one-line error at once. Nothing heavy is imported here:
`hako --help` must answer at once.
"""

from __future__ import annotations

import dataclasses
import datetime as dt
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import click

from hakoniwa.conventions import NOISE_SCALE, option_group
from hakoniwa.wire.rundir import LOCK_FILE, RunDirBusy, RunDirLock
from testctl.campaign.config import CampaignConfig
from testctl.campaign.journal import JOURNAL_FILE, JournalError, read_journal
from testctl.paper import GAIN_RANGE, MOTOR_POWER
from testctl.search.optimizers import HELP as OPTIMIZER_HELP
from testctl.search.optimizers import OPTIMIZERS, missing
from testctl.search.space import ParameterSpace, SpaceError

SMOKE: dict[str, Any] = {"trials": 2, "init_points": 2, "repeats": 1}  # a campaign that exercises every part in seconds

# --validate, the best set's draws (testctl.campaign.validate):
DEFAULT_DRAWS = 20
SMOKE_DRAWS = 3  # `--smoke` is a campaign in seconds; its validation only shows the parts work
# Past 1000 draws the estimates hardly move (the success rate's standard error is at most 1.6 points, the
# p90 within +-9 ranks of 1000), while the bench's own bias does not shrink, and 1000 draws already take
# about an hour on one bench. A longer look at a set: `hako test` with `from` and `seeds`.
MAX_DRAWS = 1000
VALIDATE_KEY = "validate"  # the journal header's --validate, which a resumed campaign keeps

_DEFAULT = CampaignConfig()  # the help text's defaults are the configuration's own
_RULE = _DEFAULT.rule


def _count(n: int, thing: str, things: str = "") -> str:
    return f"{n} {thing if n == 1 else things or thing + 's'}"


RUN_HELP = (  # `hako run`'s help, from the configuration's defaults
    f"Search the robot program's parameters by Bayesian optimization, as in the paper: "
    f"{_count(_DEFAULT.init_points, 'random set')}, then --trials sets proposed by GPyOpt (EI), --batch at a time; "
    f"each set tested until {_count(_RULE.needed, 'success', 'successes')} or "
    f"{_count(_RULE.failures_needed, 'failure')} "
    "(one test with --noise 0 on the real emulator's repeatable mode, where every test of a set is the same); the "
    "objective is the mean lap time (the time limit for a failure; with --objective completed, the mean time the "
    "program notified its completion; with --objective etrobocon, ET Robocon's mean score, maximised). Tests run "
    "on --benches benches at once; then the best set is tested on "
    "--validate fresh noise draws. Every test is journaled; kill and --resume at any time.")


_OPTIONS = [
    click.option("--trials", type=click.IntRange(min=0), default=None,
                 help=f"Optimization iterations (sets) after the initial points [{_DEFAULT.trials}]."),
    click.option("--init-points", type=click.IntRange(min=1), default=None,
                 help=f"Random initial parameter sets [{_DEFAULT.init_points}]."),
    click.option("--repeats", type=click.IntRange(min=1), default=None,
                 help=f"Tests per set at most; the first to a majority decides ({_RULE.needed} of {_RULE.repeats}) "
                      f"[{_DEFAULT.repeats}]."),
    click.option("--seed", type=click.IntRange(min=0), default=None,
                 help=f"Seed of the initial design, the optimizer and every test's noise [{_DEFAULT.seed}]."),
    click.option("--optimizer", type=click.Choice(list(OPTIMIZERS)), default=None,
                 help=f"{OPTIMIZER_HELP} [{_DEFAULT.optimizer}]."),
    click.option("--batch", type=click.IntRange(min=1), default=None,
                 help=f"Sets proposed per optimization round (constant liar) [{_DEFAULT.batch}, as in the paper; the "
                      "same command is the same campaign on any number of benches]."),
    click.option("--noise", type=NOISE_SCALE, default=None,
                 help="Scale of the course's sensor, motor and start-pose noise; 0 = an exactly repeatable "
                      f"bench [{_DEFAULT.noise:g}]."),
    click.option("--space", "space_file", type=click.Path(dir_okay=False, path_type=Path), default=None,
                 help=f"Parameter-space TOML (names, data offsets, ranges, fixed values); default: "
                      f"{', '.join(_DEFAULT.space.names)} in [{GAIN_RANGE[0]:g}, {GAIN_RANGE[1]:g}], power "
                      f"{MOTOR_POWER:g}. See docs/space-example.toml."),
    click.option("--out", type=click.Path(file_okay=False, path_type=Path), default=None,
                 help="Output directory (journal, results.csv, best.json, plots) [runs/campaign-TIME]."),
    click.option("--resume", type=click.Path(file_okay=False, path_type=Path), default=None,
                 help="Continue the campaign journaled in this directory (--trials may extend it)."),
    click.option("--smoke", is_flag=True,
                 help=f"A tiny campaign for CI: {_count(SMOKE['init_points'], 'initial point')}, "
                      f"{_count(SMOKE['trials'], 'iteration')}, {_count(SMOKE['repeats'], 'test')} each."),
]


_NOISE_OPTIONS = [
    click.option("--seed", type=click.IntRange(0, 2**32 - 1), default=0, show_default=True,
                 help="Which noise draw the test gets."),
    click.option("--noise", type=NOISE_SCALE, default=_DEFAULT.noise, show_default=True,
                 help="Scale of the course's noise levels; 0 = an exactly repeatable bench."),
]


campaign_options = option_group(_OPTIONS)
noise_options = option_group(_NOISE_OPTIONS)  # for one test: `hako try`, `testctl try`


@dataclass(frozen=True)
class CampaignPlan:
    config: CampaignConfig
    out_dir: Path
    resume: bool
    bench: dict[str, Any]  # the bench the journal records (course, app, time limit), empty for a new one
    lock: RunDirLock  # held from the plan to the end of the campaign: one live campaign per folder
    validate: int | None = None  # the journal's --validate (None: a new campaign, or a journal without it)
    created: bool = False  # the plan made the folder: a campaign refused before it starts leaves none behind

    def abandon(self) -> None:
        """The campaign was refused before it started: let the folder go as it was, and remove it if the plan
        made it (an empty --out left behind looks like a campaign that ran there)."""
        (self.out_dir / LOCK_FILE).unlink(missing_ok=True)
        self.lock.release()
        if self.created and not any(self.out_dir.iterdir()):
            self.out_dir.rmdir()


def plan(trials: int | None, init_points: int | None, repeats: int | None, seed: int | None,
         optimizer: str | None, batch: int | None, noise: float | None, space_file: Path | None,
         out: Path | None, resume: Path | None, smoke: bool, *, penalty_s: float,
         objective: str | None = None) -> CampaignPlan:
    """Turn the options into a campaign, or fail with a one-line click error. `penalty_s`, the bench's time
    limit, is what a failure scores in a new campaign, `objective` the bench's (what a test's value is); a
    resumed one keeps its journal's."""
    named = {"trials": trials, "init_points": init_points, "repeats": repeats, "seed": seed, "optimizer": optimizer,
             "batch": batch, "noise": noise}
    given: dict[str, Any] = {k: v for k, v in named.items() if v is not None}
    try:
        if resume is not None:
            if out is not None and out.resolve() != resume.resolve():
                raise click.UsageError("--resume DIR writes into DIR; do not give another --out")
            if space_file is not None or set(given) - {"trials"} or smoke:
                raise click.UsageError("--resume takes the campaign's settings from its journal; only --trials "
                                       "may be given (to extend it)")
            lock = lock_folder(resume) if resume.is_dir() else None  # no folder: read_journal says so
            try:
                header, _ = read_journal(resume / JOURNAL_FILE)
                config = CampaignConfig.from_header(header)
            except JournalError:
                if lock is not None:
                    lock.release()
                raise
            if trials is not None:
                config = dataclasses.replace(config, trials=trials)
            assert lock is not None
            if (why := missing(config.optimizer)) is not None:
                lock.release()
                raise click.ClickException(f"{why} (the campaign in {resume} uses it)")
            return CampaignPlan(config, resume, True, dict(header.get("bench", {})), lock, header.get(VALIDATE_KEY))
        space = ParameterSpace.load(space_file) if space_file is not None else ParameterSpace.default()
        config = CampaignConfig(space=space, penalty_s=penalty_s, objective=objective or "lap",
                                **{**(SMOKE if smoke else {}), **given})
        if (why := missing(config.optimizer)) is not None:
            raise click.ClickException(why)
    except (SpaceError, JournalError, ValueError) as e:
        raise click.ClickException(str(e)) from None
    out_dir = out or Path("runs") / f"campaign-{dt.datetime.now():%Y%m%d-%H%M%S}"
    created = not out_dir.exists()
    make_out_dir(out_dir)
    lock = lock_folder(out_dir)
    if (out_dir / JOURNAL_FILE).exists():
        lock.release()
        raise click.ClickException(f"{out_dir} already holds a campaign; use --resume {out_dir} to continue it "
                                   "or choose another --out")
    return CampaignPlan(config, out_dir, False, {}, lock, created=created)


def lock_folder(out_dir: Path) -> RunDirLock:
    """Take the campaign folder for this process's whole life, so that a second run or a resume of a campaign
    that is still running is refused before it can write a line (two writers would interleave the journal)."""
    lock = RunDirLock(out_dir, "campaign folder")
    try:
        lock.acquire()
    except RunDirBusy as e:
        raise click.ClickException(f"{e}; wait for it to end, or stop it, before running or resuming it "
                                   "here") from None
    except OSError as e:
        raise click.ClickException(f"{out_dir}: cannot lock the campaign folder: {e.strerror or e}") from None
    return lock


def make_out_dir(out_dir: Path) -> None:
    """Create the output folder and prove it takes files, so that a folder under a file, a read-only or
    immutable one, or one in /proc is a one-line error now rather than a traceback when the first test ends."""
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
        # A name of this process's own: two runs started on one folder at once must not unlink each other's
        # probe (the loser would report an unwritable folder instead of the lock's refusal).
        with tempfile.NamedTemporaryFile(dir=out_dir, prefix=".hako-write-test-"):
            pass
    except OSError as e:
        raise click.ClickException(f"--out {out_dir}: cannot write there: {e.strerror or e}") from None
