"""`hakoniwa-physics`: the physics process ("Unity" role). It starts first, owns the mapped files, and
starts the test controller given after `--`, exiting when the controller sets end = 1 or exits."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import click

from hakoniwa.course import CourseError, load_course
from hakoniwa.clickutil import HELP, SECONDS
from hakoniwa.launch import describe_exit, die_with_parent
from hakoniwa.programs import ProgramError, resolve_program
from hakoniwa.rundir import RunDirBusy, RunDirLock
from hakoniwa.timebase import US_PER_S

RUN_DIR_ENV = "HAKO_RUN_DIR"
COURSE_ENV = "HAKO_COURSE"


@click.command(context_settings={"ignore_unknown_options": True, **HELP})
@click.option("--run-dir", type=click.Path(file_okay=False, path_type=Path), required=True,
              help="Folder for unity_mmap.bin, athrill_mmap.bin, logs and the last trajectory (one run each).")
@click.option("--course", default="oval", show_default=True, help="Built-in course name or course folder.")
@click.option("--app", default="line_trace", show_default=True,
              help="Robot program: a built-in name, a Python module:function, an EV3RT C program (app.c or its "
                   "workspace folder), or a v850 ELF image.")
@click.option("--athrill2", default=None, help="The TOPPERS athrill2 emulator for an ELF --app [default: on PATH].")
@click.option("--athrill-timeout", type=SECONDS, default=10.0, show_default=True,
              help="Wall seconds a silent Athrill is waited for before the test counts as a crash.")
@click.option("--time-limit", type=SECONDS, default=None,
              help="Simulated seconds before TIME_OVER [default: the course's].")
@click.argument("controller", nargs=-1, type=click.UNPROCESSED)
def main(run_dir: Path, course: str, app: str, athrill2: str | None, athrill_timeout: float,
         time_limit: float | None, controller: tuple[str, ...]) -> None:
    """Serve tests on COURSE until the end flag is set; CONTROLLER (after --) is started once the files exist
    and gets the run directory in $HAKO_RUN_DIR and the course folder in $HAKO_COURSE."""
    try:
        program = resolve_program(app, athrill2=athrill2)
        check = program.start_check()
        world_course = load_course(course)
        lock = RunDirLock(run_dir)
        lock.acquire()
    except (CourseError, RunDirBusy, ProgramError, OSError) as e:
        raise click.ClickException(str(e)) from None
    try:
        from hakoniwa.server import PhysicsServer  # MuJoCo: only once the arguments are known to be good

        server = PhysicsServer(run_dir, world_course, program, athrill_timeout_s=athrill_timeout,
                               time_limit_us=round(time_limit * US_PER_S) if time_limit else None)
        program.finish_check(check)
        code = serve(server, run_dir, world_course.folder, controller)
    except ProgramError as e:
        raise click.ClickException(str(e)) from None
    finally:
        lock.release()
    sys.exit(code)


def serve(server, run_dir: Path, course_folder: Path, controller: tuple[str, ...]) -> int:
    """Serve the controller; report how it ended if it did not end well."""
    proc = None
    if controller:
        env = dict(os.environ, **{RUN_DIR_ENV: str(run_dir.resolve()), COURSE_ENV: str(course_folder.resolve())})
        try:
            proc = subprocess.Popen(list(controller), env=env, preexec_fn=die_with_parent)
        except OSError as e:
            raise click.ClickException(f"cannot start controller {controller[0]!r}: {e}") from None
    try:
        code = server.serve(proc)
    except KeyboardInterrupt:  # Ctrl-C reached the whole process group: the controller says what to do next
        code = proc.wait() if proc is not None else 130
    if code < 0:
        click.echo(f"hakoniwa-physics: the test controller (pid {proc.pid}) {describe_exit(code)}", err=True)
        code = 128 - code
    return code


if __name__ == "__main__":
    main()
