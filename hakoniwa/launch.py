"""Start the physics process with a controller command and wait for it, as `hako` does for the user."""

from __future__ import annotations

import ctypes
import signal
import subprocess
import sys
from pathlib import Path

_PR_SET_PDEATHSIG = 1


def die_with_parent() -> None:
    """preexec_fn: have the kernel kill this child when its parent dies, so that killing `hako` (even with
    SIGKILL) takes the physics process and the controller with it instead of leaving them running."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    except (OSError, AttributeError):  # not Linux: children merely outlive a killed parent
        pass


def physics_command(run_dir: Path, course: str, controller: list[str], *, app: str = "line_trace",
                    athrill_timeout_s: float = 10.0) -> list[str]:
    return [sys.executable, "-m", "hakoniwa.physics_main", "--run-dir", str(run_dir), "--course", course,
            "--app", app, "--athrill-timeout", str(athrill_timeout_s), "--", *controller]


def controller_command(*args: str) -> list[str]:
    return [sys.executable, "-m", "testctl.cli", *args]


def run_physics(cmd: list[str]) -> int:
    """Run the physics process in the foreground; Ctrl-C reaches it (and its children) through the
    process group, so it is simply waited for."""
    proc = subprocess.Popen(cmd, preexec_fn=die_with_parent)
    try:
        return proc.wait()
    except KeyboardInterrupt:
        return proc.wait()
