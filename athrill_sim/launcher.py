"""A fresh Athrill process for every test (that is how the paper re-initializes the robot program).

Starting a Python process costs 0.1-0.3 s, a third of a whole test, so a program that allows it is started
one test ahead: when test N starts, the process for N+1 is launched too, imports everything, and waits
(without touching the files) until the physics side announces test N+1. The real emulator cannot wait like
that: it starts running the moment it is launched, so it is started with its test.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

from athrill_sim.programs import Program
from hakoniwa.wire.rundir import ATHRILL_LOG



class AthrillLauncher:
    def __init__(self, run_dir: Path, program: Program) -> None:
        self.run_dir = run_dir
        self.program = program
        self._spare: tuple[int, subprocess.Popen] | None = None
        self._log = open(run_dir / ATHRILL_LOG, "ab")
        program.prepare(run_dir)

    def take(self, seq: int) -> subprocess.Popen:
        """The process for test `seq` (OSError if it cannot be started)."""
        proc = None
        if self._spare is not None:
            spare_seq, spare = self._spare
            self._spare = None
            if spare_seq == seq and spare.poll() is None:
                proc = spare
            else:
                kill(spare)
        proc = proc or self.program.spawn(self.run_dir, seq, self._log)
        if self.program.prelaunch:
            try:
                self._spare = (seq + 1, self.program.spawn(self.run_dir, seq + 1, self._log))
            except OSError:  # the next test will try again, and fail on its own account if it must
                self._spare = None
        return proc

    def close(self) -> None:
        if self._spare is not None:
            kill(self._spare[1])
            self._spare = None
        self._log.close()


def kill(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        proc.kill()
    proc.wait()
