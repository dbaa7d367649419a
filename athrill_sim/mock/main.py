"""`athrill-sim`: the mock Athrill process. The physics process starts a fresh one for every test.

When the mapped files cannot be used (the bench's fault, never scored) it marks a bench fault and exits with
EXIT_BENCH_FAULT; once the robot program runs, every exit is the program's: its own `sys.exit(3)` too, and an
exception, whose traceback's last lines the physics process shows the user.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import click

from athrill_sim.apps import load_app
from athrill_sim.mock.bus import MemoryBus
from athrill_sim.mock.ev3api import Ev3Api
from athrill_sim.mock.kernel import Kernel, KernelExit, wait_for_test
from hakoniwa.conventions import HELP, OneLineErrors
from hakoniwa.wire.exits import EXIT_BENCH_FAULT
from hakoniwa.wire.processes import mark_bench_fault
from hakoniwa.wire.protocol import LayoutError


@click.command(cls=OneLineErrors, context_settings=HELP)
@click.option("--run-dir", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Folder holding unity_mmap.bin and athrill_mmap.bin.")
@click.option("--app", required=True, help="Robot program: a built-in name or module:function taking an Ev3Api.")
@click.option("--test", "test_seq", type=int, default=None,
              help="Wait until the physics process starts this test number (default: run at once).")
@click.option("--check", is_flag=True, help="Only check that the program can be loaded, and exit.")
def main(run_dir: Path | None, app: str, test_seq: int | None, check: bool) -> None:
    """Run a robot program on the mock EV3RT until the physics process stops it."""
    task = load_app(app)
    if not callable(task):
        raise click.ClickException(f"--app {app}: {type(task).__name__} {task!r} is not a function (a robot "
                                   "program is a function taking the Ev3Api)")
    if check:
        return
    if run_dir is None:
        raise click.UsageError("--run-dir is required to run a program")
    try:
        bus = MemoryBus(run_dir)
    except LayoutError as e:
        click.echo(f"athrill-sim: bench fault: {e}", err=True)
        mark_bench_fault(run_dir, str(e))
        sys.exit(EXIT_BENCH_FAULT)
    try:
        if test_seq is not None:
            wait_for_test(bus.unity, test_seq)
        kernel = Kernel(bus.unity, bus.athrill)
        api = Ev3Api(bus, kernel)
        os.chdir(api.sdcard)  # the program's working directory is the SD card, as in the C runtime
        task(api)
        kernel.finish()
    except KernelExit as e:
        click.echo(f"athrill-sim: {e}", err=True)
        sys.exit(0)
    except LayoutError as e:  # a wild pointer in the program; other bugs show their traceback
        raise click.ClickException(f"robot program stopped: {e}") from None


if __name__ == "__main__":
    main()
