"""Building small EV3RT C programs for the native mock, and playing the physics side of the lockstep to one run
directly (no MuJoCo), for the tests of athrill_sim/native.

Tests that build need a C compiler; without one they skip with the reason in pytest's summary.
"""

from __future__ import annotations

import os
import subprocess
import time
from pathlib import Path

import pytest

from hakoniwa.wire.protocol import Header, MappedFile, Rx, Tx, open_athrill, open_unity
from hakoniwa.wire.rundir import SDCARD_DIR
from hakoniwa.wire.waiting import futex_wake
from tests.helpers.processes import interruptible

NO_CC = "needs a C compiler (cc) to build native apps"


def need_cc() -> None:
    from athrill_sim.native import NativeBuildError
    from athrill_sim.native.build import find_compiler

    try:
        find_compiler()
    except NativeBuildError:
        pytest.skip(NO_CC)


def build(folder: Path, source: str, cfg: str | None = None, name: str = "app.c") -> Path:
    """Write a program (and its app.cfg) into `folder` and build it; returns the native Athrill."""
    from athrill_sim.native.build import build_app

    need_cc()
    folder.mkdir(parents=True, exist_ok=True)
    (folder / name).write_text(source)
    if cfg is not None:
        (folder / "app.cfg").write_text(cfg)
    return build_app(folder if cfg is not None else folder / name)


class FakePhysics:
    """The physics side of the lockstep over real files: answers each wake-up by moving the unity time to it."""

    def __init__(self, run_dir: Path) -> None:
        run_dir.mkdir(parents=True, exist_ok=True)
        self.run_dir = run_dir
        self.unity: MappedFile = open_unity(run_dir, create=True)
        self.athrill: MappedFile = open_athrill(run_dir, create=True)
        self.unity.write_u32(Rx.PHYSICS_PID, os.getpid())
        self.answers = 0

    def start(self, exe: Path, test: int | None = None) -> subprocess.Popen:
        args = [str(exe), "--run-dir", str(self.run_dir)] + (["--test", str(test)] if test is not None else [])
        card = self.run_dir / SDCARD_DIR  # the program's working folder: its SD card, as the bench's copy is
        card.mkdir(exist_ok=True)
        # SIGINT's default action even where pytest runs with it ignored (a background job of a shell), which
        # the program would inherit: the tests that interrupt it need it to act as the bench's program does
        return subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True, cwd=card, preexec_fn=interruptible)

    def next_wake(self, proc: subprocess.Popen, timeout_s: float = 10.0) -> int:
        """Wait for the program's next answer and return the wake-up time it published."""
        deadline = time.monotonic() + timeout_s
        while self.athrill.read_u32(Tx.ANSWER_SEQ) == self.answers:
            assert proc.poll() is None, f"exited {proc.returncode}: {proc.communicate()[1]}"
            assert time.monotonic() < deadline, "no answer"
            time.sleep(0.0005)
        self.answers += 1
        return int(self.athrill.read("q", Tx.NEXT_WAKE))

    def wakes(self, proc: subprocess.Popen, until_us: int) -> list[int]:
        """Run the program in lockstep until its wake-up time passes `until_us`; the wake-ups it published."""
        seen = []
        while True:
            wake = self.next_wake(proc)
            seen.append(wake)
            if wake > until_us:
                return seen
            self.answer(wake)

    def answer(self, wake_us: int) -> None:
        """Move the unity time to the wake-up and ring the doorbell, as the physics process does after each
        snapshot (without the ring the program notices within waiting.CHECK_EVERY_S)."""
        self.unity.unity_time_us = wake_us
        futex_wake(self.unity.address(Header.UNITY_TIME))

    def close(self) -> None:
        self.unity.close()
        self.athrill.close()


def finish(proc: subprocess.Popen, stdout: bool = False) -> str:
    """Stop the program (as the physics process does after a test) and return its log (with what it printed
    on stdout first, which the bench writes to the same athrill.log)."""
    if proc.poll() is None:
        proc.kill()
    out, err = proc.communicate(timeout=10)
    return out + err if stdout else err
