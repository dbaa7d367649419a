"""`hakoniwa-physics`: the physics process of a bench ("Unity" role). It starts first, owns the mapped files,
and starts the test controller given after `--`, exiting when the controller sets end = 1 or exits.

This is where the two peers meet: the physics server (`hakoniwa.physics`) gets the robot program's launcher
(`athrill_sim`) as a `hakoniwa.wire.launch.Launcher`. Neither imports the other, so the process that joins
them belongs to the controller, which builds benches.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import click

from hakoniwa.conventions import HELP, OneLineErrors
from hakoniwa.wire.exits import EXIT_INTERRUPTED, exit_status
from hakoniwa.wire.processes import describe_exit, die_with_parent
from hakoniwa.wire.rundir import COURSE_ENV, OBJECTIVE_ENV, RUN_DIR_ENV, TIME_LIMIT_ENV, RunDirLock
from hakoniwa.wire.timebase import US_PER_S
from testctl.bench_options import BenchOptions, bench_options, load_bench


@click.command(cls=OneLineErrors, context_settings={"ignore_unknown_options": True, **HELP})
@click.option("--run-dir", type=click.Path(file_okay=False, path_type=Path), required=True,
              help="Folder for unity_mmap.bin, athrill_mmap.bin, logs and the last trajectory (one run each).")
@click.option("--view", "view_speed", type=float, default=None, hidden=True,
              help="Show the tests in MuJoCo's viewer, paced at this speed (hako try --view).")
@bench_options
@click.argument("controller", nargs=-1, type=click.UNPROCESSED)
def main(run_dir: Path, controller: tuple[str, ...], view_speed: float | None, **bench) -> None:
    """Serve tests on COURSE until the end flag is set; CONTROLLER (after --) is started once the files exist
    and gets the run directory in $HAKO_RUN_DIR, the course folder in $HAKO_COURSE and the time limit in
    $HAKO_TIME_LIMIT_S."""
    options = BenchOptions(**bench)
    try:
        world_course, robot, scenario = load_bench(options)  # before a build: its errors take no time
        program = options.program()
        check = program.start_check()
        lock = RunDirLock(run_dir)
        lock.acquire()
    except OSError as e:
        raise click.ClickException(str(e)) from None
    if view_speed is not None:
        os.environ["MUJOCO_GL"] = "glfw"  # a window, whatever a headless film would have used
    view = None
    try:
        from athrill_sim.programs.launcher import AthrillLauncher
        from hakoniwa.physics.server import PhysicsServer  # MuJoCo: only once the arguments are known to be good

        server = PhysicsServer(run_dir, world_course, AthrillLauncher(run_dir, program),
                               athrill_timeout_s=options.athrill_timeout_s,
                               time_limit_us=options.time_limit_us(world_course.time_limit_us), robot=robot,
                               scenario=scenario, objective=options.scored_by)
        program.finish_check(check)
        if view_speed is not None:
            from hakoniwa.pictures.viewer import LiveView

            view = LiveView(server.env, view_speed)
        code = serve(server, run_dir, world_course.folder, controller)
    finally:
        if view is not None:
            view.close()
        lock.release()
    sys.exit(code)


def serve(server, run_dir: Path, course_folder: Path, controller: tuple[str, ...]) -> int:
    """Serve the controller; report how it ended if it did not end well."""
    proc = None
    if controller:
        env = dict(os.environ, **{RUN_DIR_ENV: str(run_dir.resolve()), COURSE_ENV: str(course_folder.resolve()),
                                  TIME_LIMIT_ENV: repr(server.env.task.time_limit_us / US_PER_S),
                                  OBJECTIVE_ENV: server.objective.key})
        try:
            proc = subprocess.Popen(list(controller), env=env, preexec_fn=die_with_parent)
        except OSError as e:
            raise click.ClickException(f"cannot start controller {controller[0]!r}: {e}") from None
    try:
        code = server.serve(proc)
    except KeyboardInterrupt:  # Ctrl-C reached the whole process group: the controller says what to do next
        code = proc.wait() if proc is not None else EXIT_INTERRUPTED
    if code < 0 and proc is not None:
        click.echo(f"hakoniwa-physics: the test controller (pid {proc.pid}) {describe_exit(code)}", err=True)
        code = exit_status(code)
    return code


if __name__ == "__main__":
    main()
