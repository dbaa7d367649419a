"""Running our commands as a user would, in a process of their own, and what a refused command must look
like to that user."""

from __future__ import annotations

import subprocess
import sys

from click.testing import CliRunner, Result


def run_module(module: str, *args: str, timeout: float = 600, **kwargs) -> subprocess.CompletedProcess:
    """`python -m MODULE ARGS` with this interpreter, its output captured as text."""
    return subprocess.run([sys.executable, "-m", module, *args], capture_output=True, text=True, timeout=timeout,
                          **kwargs)


def hako(*args: str, timeout: float = 600, **kwargs) -> subprocess.CompletedProcess:
    return run_module("testctl.hako", *args, timeout=timeout, **kwargs)


def one_line_error(r: subprocess.CompletedProcess, *words: str) -> None:
    """A refused command as a user should see it: non-zero, no traceback, one line of error (besides click's
    usage lines) that names each of `words`."""
    assert r.returncode != 0, r.stdout
    assert "Traceback" not in r.stderr and "Aborted" not in r.stderr, r.stderr
    lines = [line for line in r.stderr.strip().splitlines() if line and not line.startswith(("Usage:", "Try "))]
    assert len(lines) == 1, r.stderr
    for w in words:
        assert w in lines[0], r.stderr


def mazelog(*args: object, **kwargs) -> Result:
    """`mazelog ARGS` in this process through click's test runner (fast enough for hypothesis to call it many
    times); every argument is given as its text, so a test may pass paths and numbers."""
    from maze.cli import main

    return CliRunner().invoke(main, [str(a) for a in args], **kwargs)
