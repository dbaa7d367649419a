"""Starting a bench in the foreground with this controller attached, as `hako trial` does for the user
(the paper's arrangement: the physics process starts the controller)."""

from __future__ import annotations

import signal
import subprocess
import sys

from hakoniwa.wire.processes import die_with_parent


def controller_command(*args: str) -> list[str]:
    return [sys.executable, "-m", "testctl.cli", *args]


def run_physics(cmd: list[str]) -> int:
    """Run the physics process in the foreground and return its exit status. Ctrl-C reaches it and the
    controller through the process group and they end the run (the controller saying how to resume), so
    this process ignores it and just waits."""
    proc = subprocess.Popen(cmd, preexec_fn=die_with_parent)
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        return proc.wait()
    finally:
        signal.signal(signal.SIGINT, previous)
