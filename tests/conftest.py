"""What many test modules share: running our commands as a user would, in a process of their own.

The test modules import these helpers (`from conftest import hako`): pytest puts tests/ on sys.path."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

# Films render headless: MuJoCo picks its OpenGL backend when first imported, by whichever test module that is.
os.environ.setdefault("MUJOCO_GL", "egl")


def interruptible() -> None:
    """preexec_fn for a child a test sends SIGINT (Ctrl-C): with the default action restored, so that
    Python installs its KeyboardInterrupt handler even when the tests run where SIGINT is ignored (a
    background job, as `nohup` or some CI runners start them), which the child would otherwise inherit."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def run_module(module: str, *args: str, timeout: float = 600, **kwargs) -> subprocess.CompletedProcess:
    """`python -m MODULE ARGS` with this interpreter, its output captured as text."""
    return subprocess.run([sys.executable, "-m", module, *args], capture_output=True, text=True, timeout=timeout,
                          **kwargs)


def hako(*args: str, timeout: float = 600, **kwargs) -> subprocess.CompletedProcess:
    return run_module("hakoniwa.cli", *args, timeout=timeout, **kwargs)


def one_line_error(r: subprocess.CompletedProcess, *words: str) -> None:
    """A refused command as a user should see it: non-zero, no traceback, one line of error (besides click's
    usage lines) that names each of `words`."""
    assert r.returncode != 0, r.stdout
    assert "Traceback" not in r.stderr and "Aborted" not in r.stderr, r.stderr
    lines = [line for line in r.stderr.strip().splitlines() if line and not line.startswith(("Usage:", "Try "))]
    assert len(lines) == 1, r.stderr
    for w in words:
        assert w in lines[0], r.stderr


TAG_VARIABLE = "HAKO_TEST_TAG"


def tagged_env(tag: str, env: dict | None = None) -> dict:
    """An environment that marks every process started with it, and their children, with `tag`: a test can
    then find them all even after their parent was reaped and they were re-parented to init."""
    return {**(os.environ if env is None else env), TAG_VARIABLE: tag}


def tagged_processes(tag: str, cmdline_contains: bytes = b"") -> list[int]:
    """The live processes (not zombies) carrying `tag`, optionally only those whose command line contains
    `cmdline_contains`."""
    mark = f"{TAG_VARIABLE}={tag}".encode()
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            if mark not in (entry / "environ").read_bytes().split(b"\0"):
                continue
            if cmdline_contains not in (entry / "cmdline").read_bytes():
                continue
            if (entry / "stat").read_text().rsplit(")", 1)[1].split()[0] == "Z":
                continue
        except OSError:
            continue
        found.append(int(entry.name))
    return found
