"""`testctl`: the test controller process. The physics process starts it with $HAKO_RUN_DIR set."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import click

from hakoniwa.clickutil import HELP, Float32
from hakoniwa.protocol import ProtocolError
from testctl import paper
from testctl.campaign import Campaign, Progress
from testctl.journal import JournalError
from testctl.options import campaign_options, plan
from testctl.result import TestResult
from testctl.runner import PhysicsGone, TrialRunner

RUN_DIR_OPTION = click.option("--run-dir", envvar="HAKO_RUN_DIR", required=True,
                              type=click.Path(file_okay=False, exists=True, path_type=Path),
                              help="The physics process's run directory [env: HAKO_RUN_DIR].")
BEST_TRAJECTORY_PNG = "best_trajectory.png"


def result_json(result: TestResult, params: dict[str, float]) -> dict:
    return {**result.to_dict(), "params": params}


def connect(run_dir: Path) -> TrialRunner:
    try:
        return TrialRunner(run_dir)
    except ProtocolError as e:
        raise click.ClickException(str(e)) from None


@click.group(context_settings=HELP)
def main() -> None:
    """Drive tests on a running physics process through the mapped files."""


@main.command(context_settings=HELP)
@RUN_DIR_OPTION
@click.option("--kp", type=Float32(), required=True)
@click.option("--ki", type=Float32(), required=True)
@click.option("--kd", type=Float32(), required=True)
@click.option("--power", type=Float32(-100, 100), default=paper.MOTOR_POWER, show_default=True,
              help="Base motor power [%], -100..100.")
@click.option("--out", type=click.Path(dir_okay=False, path_type=Path), required=True,
              help="Where to write the result as JSON.")
def trial(run_dir: Path, kp: float, ki: float, kd: float, power: float, out: Path) -> None:
    """Run one test with the given parameters, write its result, and end the physics process."""
    runner = connect(run_dir)
    try:
        result = runner.run_test(paper.line_trace_params(kp, ki, kd, power))
    except PhysicsGone as e:
        raise click.ClickException(str(e)) from None
    finally:
        runner.end()
    out.write_text(json.dumps(result_json(result, {"kp": kp, "ki": ki, "kd": kd, "power": power}), indent=2))


class ProgressBar:
    """A click progress bar over parameter sets, showing the best lap so far."""

    def __init__(self, bar) -> None:
        self.bar = bar
        self.shown = 0

    def __call__(self, p: Progress) -> None:
        best = f"best lap {p.best.value:.2f} s" if p.best else "no lap yet"
        self.bar.update(p.sets_done - self.shown, current_item=f"{best}, {p.tests_done} tests")
        self.shown = p.sets_done


@main.command(context_settings=HELP)
@RUN_DIR_OPTION
@campaign_options
def campaign(run_dir: Path, **options) -> None:
    """Search the control parameters with repeated tests (the paper's experiment), journaling every test."""
    from testctl.report import format_summary, write_report

    p = plan(**options)
    runner = connect(run_dir)
    try:
        with click.progressbar(length=p.config.total_sets, label=f"campaign {p.out_dir}",
                               item_show_func=lambda s: s, file=sys.stderr) as bar:
            summary = Campaign(p.config, p.out_dir, runner.run_test, on_progress=ProgressBar(bar),
                               resume=p.resume).run()
        files = write_report(p.out_dir, summary)
        if summary.best is not None:
            files.append(draw_best(runner, p.config.space.to_offsets(summary.best.x), summary.best.value,
                                   p.out_dir / BEST_TRAJECTORY_PNG))
    except (JournalError, PhysicsGone) as e:
        raise click.ClickException(str(e)) from None
    except KeyboardInterrupt:
        click.echo(f"\ninterrupted: every finished test is in {p.out_dir}/journal.jsonl; "
                   f"continue with: hako run --resume {p.out_dir}", err=True)
        sys.exit(130)
    finally:
        runner.end()
    click.echo(format_summary(summary))
    click.echo("wrote " + ", ".join(str(f) for f in files))


def draw_best(runner: TrialRunner, params: dict[int, float], lap_s: float, out: Path) -> Path:
    """Run the best parameters once more (a trial is deterministic, so it is the same lap) and draw it."""
    from hakoniwa.course import load_course
    from hakoniwa.plot import draw_trajectory, read_trajectory
    from hakoniwa.rundir import TRAJECTORY_FILE

    result = runner.run_test(params)
    course = load_course(os.environ.get("HAKO_COURSE", "oval"))
    lap = f"lap {result.lap_time_s:.2f} s" if result.lap_time_s is not None else result.event.name
    names = ", ".join(f"{v:.3f}" for v in params.values())
    draw_trajectory(course, read_trajectory(runner.run_dir / TRAJECTORY_FILE), out,
                    title=f"best parameters [{names}]: {lap} (campaign mean {lap_s:.2f} s)")
    return out


if __name__ == "__main__":
    main()
