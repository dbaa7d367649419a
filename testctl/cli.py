"""`testctl`: the test controller process. The physics process starts it with $HAKO_RUN_DIR set."""

from __future__ import annotations

import json
from pathlib import Path

import click

from hakoniwa.protocol import ProtocolError, Unity
from testctl.result import TestResult
from testctl.runner import PhysicsGone, TrialRunner

RUN_DIR_OPTION = click.option("--run-dir", envvar="HAKO_RUN_DIR", required=True,
                              type=click.Path(file_okay=False, exists=True, path_type=Path),
                              help="The physics process's run directory [env: HAKO_RUN_DIR].")


def result_json(result: TestResult, params: dict[str, float]) -> dict:
    return {"event": result.event.name, "lap_time_s": result.lap_time_s, "goal_time_us": result.goal_time_us,
            "params": params}


@click.group()
def main() -> None:
    """Drive tests on a running physics process through the mapped files."""


@main.command()
@RUN_DIR_OPTION
@click.option("--kp", type=float, required=True)
@click.option("--ki", type=float, required=True)
@click.option("--kd", type=float, required=True)
@click.option("--power", type=float, default=15.0, show_default=True, help="Base motor power [%].")
@click.option("--out", type=click.Path(dir_okay=False, path_type=Path), required=True,
              help="Where to write the result as JSON.")
def trial(run_dir: Path, kp: float, ki: float, kd: float, power: float, out: Path) -> None:
    """Run one test with the given parameters, write its result, and end the physics process."""
    try:
        runner = TrialRunner(run_dir)
    except ProtocolError as e:
        raise click.ClickException(str(e)) from None
    try:
        result = runner.run_test({Unity.KP: kp, Unity.KI: ki, Unity.KD: kd, Unity.MOTOR_POWER: power})
    except PhysicsGone as e:
        raise click.ClickException(str(e)) from None
    finally:
        runner.end()
    out.write_text(json.dumps(result_json(result, {"kp": kp, "ki": ki, "kd": kd, "power": power}), indent=2))


if __name__ == "__main__":
    main()
