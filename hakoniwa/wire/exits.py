"""The exit statuses of every program of the bench and of mazelog, besides 0 and click's own (1 for an error,
2 for a bad option): what a shell, CI or a parent process reads of how a run ended. Standard library only, so
that `maze` may use it too (`tests/project/test_layers.py`'s SHARED_WITH_STANDALONE)."""

from __future__ import annotations

import signal

SIGNAL_BASE = 128  # a shell's status for a process killed by signal N is SIGNAL_BASE + N

EXIT_CASES_FAILED = 1  # `hako test`: a case failed (the program's fault)
EXIT_RUN_BROKEN = 2  # `hako test`: the input is bad or the run itself broke, so nothing was shown of the program
EXIT_BENCH_FAULT = 3  # what a mock or native Athrill that could not use the mapped files exits with (beside the marker)
EXIT_COMMAND_CAP = 3  # mazelog: a --mouse run cut at the command cap: its logs are written, but its search never ended
EXIT_INTERRUPTED = SIGNAL_BASE + signal.SIGINT  # Ctrl-C (130): a campaign prints how to resume
EXIT_TERMINATED = SIGNAL_BASE + signal.SIGTERM  # SIGTERM (143)


def exit_status(code: int) -> int:
    """What a parent should exit with after a child ended with `code` (a `Popen.returncode`): SIGNAL_BASE + N
    for a death by signal N, else the child's own status."""
    return SIGNAL_BASE - code if code < 0 else code
