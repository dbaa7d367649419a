"""Starting the physics process with a controller command and waiting for it, as `hako` does for the user,
and saying what happened when a process of the bench died."""

from __future__ import annotations

import ctypes
import signal
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

_PR_SET_PDEATHSIG = 1
INTERRUPTED = 130  # the exit status of a campaign stopped with Ctrl-C (the controller prints how to resume)


def die_with_parent() -> None:
    """preexec_fn: have the kernel kill this child when its parent dies, so that killing `hako` (even with
    SIGKILL) takes the physics process and the controller with it instead of leaving them running."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    except (OSError, AttributeError):  # not Linux: children merely outlive a killed parent
        pass


def describe_exit(code: int) -> str:
    """A child's exit status (negative: the signal that killed it) in words."""
    if code < 0:
        try:
            return f"was killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"was killed by signal {-code}"
    return f"exited with status {code}"


def exit_status(code: int) -> int:
    """What a parent should exit with after a child ended with `code`: 128 + N for a death by signal N."""
    return 128 - code if code < 0 else code


@dataclass(frozen=True)
class BenchOptions:
    """What the physics process needs to know besides its run directory: the course and the program."""

    course: str = "oval"
    app: str = "line_trace"
    athrill2: str | None = None
    athrill_timeout_s: float = 10.0
    time_limit_s: float | None = None

    def physics_command(self, run_dir: Path, controller: list[str]) -> list[str]:
        cmd = [sys.executable, "-m", "hakoniwa.physics_main", "--run-dir", str(run_dir), "--course", self.course,
               "--app", self.app, "--athrill-timeout", repr(self.athrill_timeout_s)]
        if self.athrill2 is not None:
            cmd += ["--athrill2", self.athrill2]
        if self.time_limit_s is not None:
            cmd += ["--time-limit", repr(self.time_limit_s)]
        return [*cmd, "--", *controller]


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
