"""The campaign's command-line options, declared once for `hako run` and `testctl campaign`.

`hako run` validates them in the user's process (so a bad space file fails before any process starts)
and forwards the very same options to the controller the physics process starts.
"""

from __future__ import annotations

import dataclasses
import datetime as dt
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

import click

from testctl.journal import JOURNAL_FILE, JournalError
from testctl.space import ParameterSpace, SpaceError

if TYPE_CHECKING:
    from testctl.campaign import CampaignConfig

SMOKE = {"trials": 2, "init_points": 2, "repeats": 1}  # a campaign that exercises every part in seconds

_OPTIONS = [
    click.option("--trials", type=int, default=None, help="Optimization iterations after the initial points [100]."),
    click.option("--init-points", type=int, default=None, help="Random initial parameter sets [5]."),
    click.option("--repeats", type=int, default=None,
                 help="Tests per set at most; the first to a majority decides (3 of 5) [5]."),
    click.option("--seed", type=int, default=None, help="Seed of the initial design and the optimizer [0]."),
    click.option("--optimizer", type=click.Choice(["gpyopt", "random"]), default=None,
                 help="Bayesian optimization with EI, or uniform random search as a baseline [gpyopt]."),
    click.option("--space", "space_file", type=click.Path(dir_okay=False, path_type=Path), default=None,
                 help="Parameter-space TOML (names, data offsets, ranges, fixed values); default: Kp, Ki, Kd "
                      "in [0, 5], power 15. See docs/space-example.toml."),
    click.option("--out", type=click.Path(file_okay=False, path_type=Path), default=None,
                 help="Output directory (journal, results.csv, best.json, plots) [runs/campaign-TIME]."),
    click.option("--resume", type=click.Path(file_okay=False, path_type=Path), default=None,
                 help="Continue the campaign journaled in this directory (--trials may extend it)."),
    click.option("--smoke", is_flag=True,
                 help="A tiny campaign for CI: 2 initial points, 2 iterations, 1 test each."),
]


def campaign_options(f: Callable) -> Callable:
    for option in reversed(_OPTIONS):
        f = option(f)
    return f


def forward(params: dict[str, Any]) -> list[str]:
    """The campaign options given on one command line, as arguments for another."""
    args: list[str] = []
    for option in _OPTIONS:
        param = option(lambda: None).__click_params__[0]
        value = params.get(param.name)
        if value is None or value is False:
            continue
        flag = param.opts[0]
        args += [flag] if value is True else [flag, str(value)]
    return args


@dataclass(frozen=True)
class CampaignPlan:
    config: CampaignConfig
    out_dir: Path
    resume: bool


def plan(trials: int | None, init_points: int | None, repeats: int | None, seed: int | None,
         optimizer: str | None, space_file: Path | None, out: Path | None, resume: Path | None,
         smoke: bool) -> CampaignPlan:
    """Turn the options into a campaign, or fail with a one-line click error."""
    from testctl.campaign import CampaignConfig, load_config  # NumPy: not for --help

    given = {k: v for k, v in {"trials": trials, "init_points": init_points, "repeats": repeats, "seed": seed,
                               "optimizer": optimizer}.items() if v is not None}
    try:
        if resume is not None:
            if out is not None and out.resolve() != resume.resolve():
                raise click.UsageError("--resume DIR writes into DIR; do not give another --out")
            if space_file is not None or set(given) - {"trials"} or smoke:
                raise click.UsageError("--resume takes the campaign's settings from its journal; only --trials "
                                       "may be given (to extend it)")
            config = load_config(resume)
            if trials is not None:
                config = dataclasses.replace(config, trials=trials)
            return CampaignPlan(config, resume, True)
        space = ParameterSpace.load(space_file) if space_file is not None else ParameterSpace.default()
        config = CampaignConfig(space=space, **{**(SMOKE if smoke else {}), **given})
    except (SpaceError, JournalError, ValueError) as e:
        raise click.ClickException(str(e)) from None
    out_dir = out or Path("runs") / f"campaign-{dt.datetime.now():%Y%m%d-%H%M%S}"
    if (out_dir / JOURNAL_FILE).exists():
        raise click.ClickException(f"{out_dir} already holds a campaign; use --resume {out_dir} to continue it "
                                   "or choose another --out")
    make_out_dir(out_dir)
    return CampaignPlan(config, out_dir, False)


def make_out_dir(out_dir: Path) -> None:
    """Create the output folder and prove it takes files, so that a folder under a file, a read-only or
    immutable one, or one in /proc is a one-line error now rather than a traceback when the first test ends."""
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
        probe = out_dir / ".hako-write-test"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as e:
        raise click.ClickException(f"--out {out_dir}: cannot write there: {e.strerror or e}") from None
