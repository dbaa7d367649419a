"""`hako`: the user's entry point to the test bench.

It only parses, checks and launches: the physics process and the controller do the work, in processes of
their own. Nothing heavy (NumPy, MuJoCo, GPyOpt, matplotlib) is imported here except where a command
draws, so `hako --help` and a bad option answer at once.
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import Callable

import click

from hakoniwa.clickutil import HELP, Float32
from hakoniwa.launch import (INTERRUPTED, BenchOptions, controller_command, describe_exit, exit_status,
                             run_physics)
from hakoniwa.rundir import TRAJECTORY_FILE, diagnose
from testctl import paper
from testctl.options import campaign_options, forward, plan

POWER = Float32(-100.0, 100.0)
POSITIVE = click.FloatRange(min=0, min_open=True, max=1e9)

_BENCH_OPTIONS = [
    click.option("--course", default="oval", show_default=True, help="Built-in course name or course folder."),
    click.option("--app", default="line_trace", show_default=True,
                 help="Robot program: a built-in name, a Python module:function, or a v850 ELF image (run in "
                      "the real athrill2)."),
    click.option("--athrill2", default=None, help="The TOPPERS athrill2 emulator for an ELF --app [default: on PATH]."),
    click.option("--athrill-timeout", type=POSITIVE, default=10.0, show_default=True,
                 help="Wall seconds a silent Athrill is waited for before the test counts as a crash."),
    click.option("--time-limit", type=POSITIVE, default=60.0, show_default=True,
                 help="Simulated seconds before a test ends as TIME_OVER."),
]


def bench_options(f: Callable) -> Callable:
    for option in reversed(_BENCH_OPTIONS):
        f = option(f)
    return f


def _bench(course: str, app: str, athrill2: str | None, athrill_timeout: float, time_limit: float) -> BenchOptions:
    return BenchOptions(course, app, athrill2, athrill_timeout, time_limit)


def report_death(code: int, run_dir: Path, resume: Path | None) -> None:
    """Exit like the bench did, saying what died if nobody else could, and how to resume a campaign."""
    if code == 0:
        return
    if code < 0:
        damaged = diagnose(run_dir)
        click.echo(f"hako: the physics process {describe_exit(code)}"
                   + (f" ({damaged})" if damaged else ""), err=True)
    if resume is not None and code not in (1, 2, INTERRUPTED):
        click.echo(f"hako: every finished test is in {resume / 'journal.jsonl'}; continue with: "
                   f"hako run --resume {resume}", err=True)
    raise SystemExit(exit_status(code))


@click.group(context_settings=HELP)
@click.version_option(package_name="hakoniwa-py")
def main() -> None:
    """Hakoniwa-style robot test bench: MuJoCo physics, an Athrill (our mock, or the real TOPPERS emulator)
    running the robot program, and a test controller: three processes over memory-mapped files."""


def _writable_file(path: Path, option: str) -> None:
    if path.is_dir():
        raise click.BadParameter(f"{path} is a folder", param_hint=option)
    parent = path.parent.resolve()
    if not parent.is_dir():
        raise click.BadParameter(f"folder {path.parent} does not exist", param_hint=option)
    if not os.access(parent, os.W_OK):
        raise click.BadParameter(f"folder {path.parent} is not writable", param_hint=option)


@main.command(context_settings=HELP)
@click.option("--kp", type=Float32(), default=paper.BEST_GAINS[0], show_default=True, help="Proportional gain.")
@click.option("--ki", type=Float32(), default=paper.BEST_GAINS[1], show_default=True, help="Integral gain.")
@click.option("--kd", type=Float32(), default=paper.BEST_GAINS[2], show_default=True, help="Derivative gain.")
@click.option("--power", type=POWER, default=paper.MOTOR_POWER, show_default=True,
              help="Base motor power [%], -100..100.")
@bench_options
@click.option("--run-dir", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Keep the run's files here (default: a temporary folder).")
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@click.option("--trajectory", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="Draw the course and the robot's path into this PNG.")
def trial(kp: float, ki: float, kd: float, power: float, run_dir: Path | None, as_json: bool,
          trajectory: Path | None, **bench) -> None:
    """Run one test with the given parameters and print the event and lap time."""
    if trajectory is not None:
        _writable_file(trajectory, "--trajectory")
    options = _bench(**bench)
    with tempfile.TemporaryDirectory(prefix="hako-") as tmp:
        rd = run_dir or Path(tmp)
        out = rd / "result.json"
        try:
            out.unlink(missing_ok=True)
        except OSError as e:
            raise click.ClickException(f"--run-dir {rd}: {e.strerror}") from None
        ctl = controller_command("trial", "--kp", repr(kp), "--ki", repr(ki), "--kd", repr(kd),
                                 "--power", repr(power), "--out", str(out))
        report_death(run_physics(options.physics_command(rd, ctl)), rd, None)
        result = json.loads(out.read_text())
        if trajectory is not None:
            from hakoniwa.course import load_course
            from hakoniwa.plot import draw_trajectory, read_trajectory

            lap = f"lap {result['lap_time_s']:.2f} s" if result["lap_time_s"] is not None else result["event"]
            draw_trajectory(load_course(options.course), read_trajectory(rd / TRAJECTORY_FILE), trajectory,
                            title=f"Kp={kp:g} Ki={ki:g} Kd={kd:g} power={power:g}: {lap}")
    if as_json:
        click.echo(json.dumps(result, sort_keys=True))
    else:
        lap = f"{result['lap_time_s']:.3f} s" if result["lap_time_s"] is not None else "-"
        why = f" ({result['crash_reason']})" if result.get("crash_reason") else ""
        click.echo(f"event: {result['event']}{why}  lap time: {lap}  distance: {result['distance_m']:.2f} m  "
                   f"checkpoints: {result['checkpoints']}")


@main.command(context_settings=HELP)
@bench_options
@campaign_options
def run(course: str, app: str, athrill2: str | None, athrill_timeout: float, time_limit: float,
        **options) -> None:
    """Search the robot program's parameters by Bayesian optimization, as in the paper: 5 random sets, then
    --trials sets proposed by GPyOpt (EI); each set tested until 3 successes or 3 failures; the objective is
    the mean lap time (60 s for a failure). Every test is journaled; kill and --resume at any time."""
    bench = _bench(course, app, athrill2, athrill_timeout, time_limit)
    p = plan(**options)
    args = forward({**options, "out": None if p.resume else p.out_dir})
    run_dir = p.out_dir / "run"
    code = run_physics(bench.physics_command(run_dir, controller_command("campaign", *args)))
    report_death(code, run_dir, p.out_dir)


if __name__ == "__main__":
    main()
