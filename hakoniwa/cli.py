"""`hako`: the user's entry point to the test bench."""

from __future__ import annotations

import json
import tempfile
from pathlib import Path

import click

from hakoniwa.course import Course, CourseError, load_course
from hakoniwa.launch import controller_command, physics_command, run_physics
from hakoniwa.server import TRAJECTORY_FILE
from testctl import paper
from testctl.options import campaign_options, forward, plan


@click.group()
@click.version_option(package_name="hakoniwa-py")
def main() -> None:
    """Hakoniwa-style robot test bench: MuJoCo physics, a mock EV3RT Athrill and a test controller, three
    processes over memory-mapped files."""


def _course(name: str) -> Course:
    try:
        return load_course(name)
    except CourseError as e:
        raise click.ClickException(str(e)) from None


@main.command()
@click.option("--kp", type=float, default=paper.BEST_GAINS[0], show_default=True, help="Proportional gain.")
@click.option("--ki", type=float, default=paper.BEST_GAINS[1], show_default=True, help="Integral gain.")
@click.option("--kd", type=float, default=paper.BEST_GAINS[2], show_default=True, help="Derivative gain.")
@click.option("--power", type=float, default=paper.MOTOR_POWER, show_default=True, help="Base motor power [%].")
@click.option("--course", default="oval", show_default=True, help="Built-in course name or course folder.")
@click.option("--run-dir", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Keep the run's files here (default: a temporary folder).")
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@click.option("--trajectory", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="Draw the course and the robot's path into this PNG.")
def trial(kp: float, ki: float, kd: float, power: float, course: str, run_dir: Path | None, as_json: bool,
          trajectory: Path | None) -> None:
    """Run one test of the line tracer with the given PID gains and print the event and lap time."""
    course_obj = _course(course)
    with tempfile.TemporaryDirectory(prefix="hako-") as tmp:
        rd = run_dir or Path(tmp)
        out = rd / "result.json"
        out.unlink(missing_ok=True)
        ctl = controller_command("trial", "--kp", repr(kp), "--ki", repr(ki), "--kd", repr(kd),
                                 "--power", repr(power), "--out", str(out))
        code = run_physics(physics_command(rd, course, ctl))
        if code != 0 or not out.exists():
            raise click.ClickException(f"the trial did not complete (exit code {code})")
        result = json.loads(out.read_text())
        if trajectory is not None:
            from hakoniwa.plot import draw_trajectory, read_trajectory

            lap = f"lap {result['lap_time_s']:.2f} s" if result["lap_time_s"] is not None else result["event"]
            draw_trajectory(course_obj, read_trajectory(rd / TRAJECTORY_FILE), trajectory,
                            title=f"Kp={kp:g} Ki={ki:g} Kd={kd:g} power={power:g}: {lap}")
    if as_json:
        click.echo(json.dumps(result, sort_keys=True))
    else:
        lap = f"{result['lap_time_s']:.3f} s" if result["lap_time_s"] is not None else "-"
        click.echo(f"event: {result['event']}  lap time: {lap}")


@main.command()
@click.option("--course", default="oval", show_default=True, help="Built-in course name or course folder.")
@campaign_options
def run(course: str, **options) -> None:
    """Search the line tracer's parameters by Bayesian optimization, as in the paper: 5 random sets, then
    --trials sets proposed by GPyOpt (EI); each set tested until 3 successes or 3 failures; the objective is
    the mean lap time (60 s for a failure). Every test is journaled; kill and --resume at any time."""
    _course(course)  # fail here, before any process starts
    p = plan(**options)
    p.out_dir.mkdir(parents=True, exist_ok=True)
    args = forward({**options, "out": None if p.resume else p.out_dir})
    code = run_physics(physics_command(p.out_dir / "run", course, controller_command("campaign", *args)))
    if code:
        raise SystemExit(code)


if __name__ == "__main__":
    main()
