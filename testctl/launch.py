"""Starting a bench in the foreground with this controller attached, as `hako trial` does for the user
(the paper's arrangement: the physics process starts the controller)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys

from hakoniwa.wire.processes import die_with_parent


def controller_command(*args: str) -> list[str]:
    return [sys.executable, "-m", "testctl.cli", *args]


def run_physics(cmd: list[str]) -> int:
    """Run the physics process (and the controller it starts) and return its exit status.

    The bench runs in a process group of its own, so a Ctrl-C reaches this process alone: caught by a
    process of the bench, it would end as a traceback of whatever that process was importing, or as click's
    "Aborted!". This process ends the bench with SIGTERM instead, which each of its processes dies of
    quietly (the Athrill with its physics process), and raises the KeyboardInterrupt for its caller to say
    one line."""
    proc = subprocess.Popen(cmd, preexec_fn=die_with_parent, process_group=0)
    try:
        return proc.wait()
    except KeyboardInterrupt:
        try:
            os.killpg(proc.pid, signal.SIGTERM)
        except ProcessLookupError:
            pass
        proc.wait()
        raise
