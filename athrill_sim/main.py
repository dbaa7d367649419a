"""`athrill-sim`: the mock Athrill process. The physics process starts a fresh one for every test."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from athrill_sim.apps import load_app
from athrill_sim.bus import MemoryBus
from athrill_sim.ev3api import Ev3Api, SensorPortError
from athrill_sim.kernel import Kernel, KernelExit, wait_for_test
from hakoniwa.protocol import ProtocolError


@click.command()
@click.option("--run-dir", type=click.Path(file_okay=False, path_type=Path), required=True,
              help="Folder holding unity_mmap.bin and athrill_mmap.bin.")
@click.option("--app", default="line_trace", show_default=True,
              help="Robot program: a built-in name or module:function taking an Ev3Api.")
@click.option("--test", "test_seq", type=int, default=None,
              help="Wait until the physics process starts this test number (default: run at once).")
def main(run_dir: Path, app: str, test_seq: int | None) -> None:
    """Run a robot program on the mock EV3RT until the physics process stops it."""
    try:
        task = load_app(app)
        bus = MemoryBus(run_dir)
    except (ValueError, ProtocolError) as e:
        raise click.ClickException(str(e)) from None
    try:
        if test_seq is not None:
            wait_for_test(bus.unity, test_seq)
        kernel = Kernel(bus.unity, bus.athrill)
        task(Ev3Api(bus, kernel))
        kernel.finish()
    except KernelExit as e:
        click.echo(f"athrill-sim: {e}", err=True)
        sys.exit(0)
    except (SensorPortError, ProtocolError) as e:  # the program's own bugs still show their traceback
        raise click.ClickException(f"robot program stopped: {e}") from None


if __name__ == "__main__":
    main()
