"""`hakoniwa-physics`: the physics process ("Unity" role). It starts first, owns the mapped files, and
starts the test controller given after `--`, exiting when the controller sets end = 1 or exits."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import click

from hakoniwa.course import CourseError, load_course
from hakoniwa.launch import die_with_parent
from hakoniwa.rundir import RunDirBusy, RunDirLock
from hakoniwa.server import PhysicsServer

RUN_DIR_ENV = "HAKO_RUN_DIR"
COURSE_ENV = "HAKO_COURSE"


@click.command(context_settings={"ignore_unknown_options": True})
@click.option("--run-dir", type=click.Path(file_okay=False, path_type=Path), required=True,
              help="Folder for unity_mmap.bin, athrill_mmap.bin, logs and the last trajectory (one run each).")
@click.option("--course", default="oval", show_default=True, help="Built-in course name or course folder.")
@click.option("--app", default="line_trace", show_default=True, help="Robot program Athrill runs.")
@click.option("--athrill-timeout", default=10.0, show_default=True,
              help="Wall seconds a silent Athrill is waited for before the test counts as a crash.")
@click.argument("controller", nargs=-1, type=click.UNPROCESSED)
def main(run_dir: Path, course: str, app: str, athrill_timeout: float, controller: tuple[str, ...]) -> None:
    """Serve tests on COURSE until the end flag is set; CONTROLLER (after --) is started once the files exist
    and gets the run directory in $HAKO_RUN_DIR and the course folder in $HAKO_COURSE."""
    try:
        world_course = load_course(course)
        lock = RunDirLock(run_dir)
        lock.acquire()
    except (CourseError, RunDirBusy) as e:
        raise click.ClickException(str(e)) from None
    try:
        server = PhysicsServer(run_dir, world_course, app=app, athrill_timeout_s=athrill_timeout)
        proc = None
        if controller:
            env = dict(os.environ, **{RUN_DIR_ENV: str(run_dir.resolve()),
                                      COURSE_ENV: str(world_course.folder.resolve())})
            try:
                proc = subprocess.Popen(list(controller), env=env, preexec_fn=die_with_parent)
            except OSError as e:
                raise click.ClickException(f"cannot start controller {controller[0]!r}: {e}") from None
        code = server.serve(proc)
    finally:
        lock.release()
    sys.exit(code)


if __name__ == "__main__":
    main()
