"""`testctl`: the test controller attached to one running physics process (the paper's arrangement: the
physics process starts it with $HAKO_RUN_DIR set). `hako try` uses it for its one test; a campaign on
several benches is `hako run`."""

from __future__ import annotations

import json
import threading
from pathlib import Path

import click

from hakoniwa.conventions import HELP, SECONDS, Float32, OneLineErrorsGroup
from hakoniwa.wire.objective import DEFAULT
from hakoniwa.wire.rundir import COURSE_ENV, OBJECTIVE_ENV, RUN_DIR_ENV, TIME_LIMIT_ENV
from testctl import paper
from testctl.bench_options import ObjectiveKey
from testctl.executor import SerialExecutor, TestSpec
from testctl.options import campaign_options, noise_options, plan
from testctl.runner import TestRunner

RUN_DIR_OPTION = click.option("--run-dir", envvar=RUN_DIR_ENV, required=True,
                              type=click.Path(file_okay=False, exists=True, path_type=Path),
                              help="The physics process's run directory [env: HAKO_RUN_DIR].")
@click.group(cls=OneLineErrorsGroup, context_settings=HELP)
def main() -> None:
    """Drive tests on a running physics process through the mapped files."""


@main.command("try", context_settings=HELP)
@RUN_DIR_OPTION
@click.option("--kp", type=Float32(), required=True)
@click.option("--ki", type=Float32(), required=True)
@click.option("--kd", type=Float32(), required=True)
@click.option("--power", type=Float32(-100, 100), default=paper.MOTOR_POWER, show_default=True,
              help="Base motor power [%], -100..100.")
@noise_options
@click.option("--out", type=click.Path(dir_okay=False, path_type=Path), required=True,
              help="Where to write the result as JSON.")
def try_once(run_dir: Path, kp: float, ki: float, kd: float, power: float, seed: int, noise: float,
             out: Path) -> None:
    """Run one test with the given parameters, write its result, and end the physics process."""
    runner = TestRunner(run_dir)
    try:
        result = runner.run_test(paper.line_trace_params(kp, ki, kd, power), noise_seed=seed, noise_scale=noise)
    finally:
        runner.end()
    params = {"kp": kp, "ki": ki, "kd": kd, "power": power}
    out.write_text(json.dumps({**result.to_dict(), "params": params, "seed": seed, "noise": noise}, indent=2))


@main.command(context_settings=HELP)
@RUN_DIR_OPTION
@click.option("--course", envvar=COURSE_ENV, required=True, type=click.Path(file_okay=False, exists=True),
              help="The bench's course folder, for the best set's picture [env: HAKO_COURSE].")
@click.option("--time-limit", envvar=TIME_LIMIT_ENV, required=True, type=SECONDS,
              help="The bench's time limit: what a failed test scores [env: HAKO_TIME_LIMIT_S].")
@click.option("--objective", envvar=OBJECTIVE_ENV, default=DEFAULT, show_default=True, type=ObjectiveKey(),
              help="The bench's objective: what a test's value is [env: HAKO_OBJECTIVE].")
@campaign_options
def campaign(run_dir: Path, course: str, time_limit: float, objective: str, **options) -> None:
    """Search the control parameters with repeated tests (the paper's experiment) on this one bench,
    journaling every test."""
    from testctl.campaign.session import run_campaign

    p = plan(**options, penalty_s=time_limit, objective=objective)
    if p.config.space.bindings() is not None:
        p.lock.release()
        raise click.ClickException("--space: define, symbol, file and source parameters need a bench that knows "
                                   "where they go, which this one was started without: run the campaign with "
                                   "hako run")
    runner = TestRunner(run_dir)
    one_at_a_time = threading.Lock()  # the study mirror draws improving sets on this bench from a thread of its own

    def run_test(spec: TestSpec):
        with one_at_a_time:
            return runner.run_test(spec.params, noise_seed=spec.noise_seed, noise_scale=spec.noise_scale,
                                   slot_types=spec.slot_types)

    try:
        run_campaign(p, SerialExecutor(run_test, name=str(run_dir)), bench_info={},
                     test_once=lambda spec: (run_test(spec), runner.run_dir),
                     course_folder=Path(course))
    finally:
        runner.end()


if __name__ == "__main__":
    main()
