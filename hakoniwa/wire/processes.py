"""What every process of the bench needs to know about its children: that they die with it, what their
exit statuses mean, and the statuses the bench itself uses."""

from __future__ import annotations

import ctypes
import signal

_PR_SET_PDEATHSIG = 1
EXIT_BENCH_FAULT = 3  # a mock or native Athrill that could not use the mapped files: a bench fault
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
