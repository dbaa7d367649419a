"""Child processes a test signals or must find again: Ctrl-C that reaches them, and a tag in their
environment that survives their parent."""

from __future__ import annotations

import os
import signal
from pathlib import Path


def interruptible() -> None:
    """preexec_fn for a child a test sends SIGINT (Ctrl-C): with the default action restored, so that
    Python installs its KeyboardInterrupt handler even when the tests run where SIGINT is ignored (a
    background job, as `nohup` or some CI runners start them), which the child would otherwise inherit."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


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
