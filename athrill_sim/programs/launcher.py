"""A fresh Athrill process for every test (that is how the paper re-initializes the robot program): the
program side of `hakoniwa.wire.launch.Launcher`, which the physics server is given.

Starting a Python process costs 0.1-0.3 s, a third of a whole test, so a program that allows it is started
one test ahead: when test N starts, the process for N+1 is launched too, imports everything, and waits
(without touching the files) until the physics side announces test N+1. The real emulator cannot wait like
that: it starts running the moment it is launched, so it is started with its test.

Each process's output reaches `athrill.log` through `CappedOutput`, capped per test. A program with a working
folder (`athrill_sim.programs.working_folder`) gets a fresh copy of it per test, made before its test starts, and the
test's end keeps it in the run directory once the process is gone; a program that takes a Ctrl-C at the end of
its test (a native one, which may close its logs then) gets SIGINT and END_BOUND_S to end before it is stopped.
"""

from __future__ import annotations

import signal
import subprocess
import threading
from pathlib import Path

from athrill_sim.programs import working_folder
from athrill_sim.programs.program import MOCK_ARGV, Program
from athrill_sim.programs.zygote import ForkedProcess, Zygote
from athrill_sim.tuning.forms.form import BindingError
from hakoniwa.wire.launch import ProgramRefused
from hakoniwa.wire.output import CappedOutput
from hakoniwa.wire.processes import kill
from hakoniwa.wire.protocol import MappedFile, SyncMode
from hakoniwa.wire.rundir import ATHRILL_LOG, SDCARD_DIR
from hakoniwa.wire.vdev_udp import UdpLink

END_BOUND_S = 2.0  # how long an interrupted program may take to end, in wall time


class AthrillLauncher:
    def __init__(self, run_dir: Path, program: Program) -> None:
        self.run_dir = run_dir
        self.program = program
        self._spare: tuple[int, Program, subprocess.Popen] | None = None
        self._log = open(run_dir / ATHRILL_LOG, "ab")
        self._write_lock = threading.Lock()
        self._outputs: dict[int, CappedOutput] = {}  # by pid, while the process or its output lasts
        self._zygote: Zygote | None = None  # started by the first test of a program it can fork
        self._forks = True  # until the zygote fails once
        self._taken: int | None = None  # the pid of the process running the current test
        self._prepared = program  # what the current test runs (`prepare`)
        self._running: tuple[int, subprocess.Popen, Program] | None = None  # the current test's
        self._folders: dict[int, Path] = {}  # each test's working folder, until it is kept or discarded
        program.prepare(run_dir)

    @property
    def sync(self) -> SyncMode:
        return self.program.sync

    @property
    def udp(self) -> UdpLink | None:
        return self.program.udp

    @property
    def serial_hub(self) -> bool:
        return self.program.serial_hub

    def prepare(self, seq: int, unity: MappedFile) -> None:
        """The program test `seq`'s parameter values make (the program itself unless it is tuned by forms
        other than `offset`), with its data files written onto its SD card: its working folder, made now if
        its process is not started yet, or the run directory's SD card. A value the program does not build
        with is the program's failure; a file that cannot be written, the bench's."""
        tuning = self.program.tuning
        if tuning is None:
            return
        values = tuning.values(unity)
        card = self._folder(seq) if self.program.working_folder is not None else self.run_dir / SDCARD_DIR
        try:
            self._prepared = tuning.for_test(self.run_dir, card, values)
        except BindingError as e:
            raise ProgramRefused(str(e)) from None
        except OSError as e:
            raise OSError(f"cannot prepare the program for {values}: {e}") from e

    def _folder(self, seq: int) -> Path:
        assert self.program.working_folder is not None
        if seq not in self._folders:
            folder = working_folder.test_folder(self.run_dir, seq)
            working_folder.discard(folder)  # a run before this one in the same directory may have left it
            self._folders[seq] = self.program.working_folder.make(folder)
        return self._folders[seq]

    def _spawn(self, seq: int, program: Program) -> subprocess.Popen:
        cwd = self._folder(seq) if program.working_folder is not None else None
        proc = (program.forkable and self._fork(seq, program)) or program.spawn(self.run_dir, seq, subprocess.PIPE,
                                                                                cwd)
        # Kept: outputs still being copied (`close` waits for them), and the test's own process, which may
        # have crashed, and so ended its output, before the spare for the next test is started here.
        self._outputs = {pid: out for pid, out in self._outputs.items() if out.running or pid == self._taken}
        assert proc.stdout is not None  # spawned with stdout=PIPE
        self._outputs[proc.pid] = CappedOutput(proc.stdout, self._log, self._write_lock, f"the Athrill of test {seq}")
        return proc

    def _fork(self, seq: int, program: Program) -> ForkedProcess | None:
        """The mock for test `seq` forked by the bench's zygote; None where there is none (the caller then
        starts it the usual way, and so does every later test)."""
        if not self._forks:
            return None
        try:
            if self._zygote is None:
                self._zygote = Zygote()
            return self._zygote.spawn(program.args(self.run_dir, seq)[len(MOCK_ARGV):],
                                      self.run_dir if program.in_run_dir else None)
        except OSError:  # ZygoteGone too
            self._forks = False
            if self._zygote is not None:
                self._zygote.close()
                self._zygote = None
            return None

    def last_lines(self, proc: subprocess.Popen, n: int) -> list[str]:
        """The last lines an ended process printed: a crashed program's own error."""
        out = self._outputs.get(proc.pid)
        return out.last_lines(n) if out is not None else []

    def take(self, seq: int, program: Program | None = None) -> subprocess.Popen:
        """The process for test `seq` (OSError if it cannot be started), running `program` (by default what
        `prepare` made: a variant of the launcher's for this test's parameter values, `athrill_sim.tuning`).
        The process launched ahead runs the variant of the test before: a test with other values discards it."""
        program = program or self._prepared
        proc = None
        if self._spare is not None:
            spare_seq, spare_program, spare = self._spare
            self._spare = None
            if spare_seq == seq and spare_program == program and spare.poll() is None:
                proc = spare
            else:
                kill(spare)
        proc = proc or self._spawn(seq, program)
        self._taken = proc.pid
        self._running = (seq, proc, program)
        if program.prelaunch:
            try:
                self._spare = (seq + 1, program, self._spawn(seq + 1, program))
            except OSError:  # the next test will try again, and fail on its own account if it must
                self._spare = None
        return proc

    def end(self, proc: subprocess.Popen) -> None:
        """The test of `proc` is over: stop it (after a Ctrl-C, for a program that takes one), and keep its
        working folder in the run directory."""
        running = self._running if self._running is not None and self._running[1] is proc else None
        if running is not None and running[2].interrupted_at_end and proc.poll() is None:
            proc.send_signal(signal.SIGINT)
            try:
                proc.wait(timeout=END_BOUND_S)
            except subprocess.TimeoutExpired:
                pass
        kill(proc)
        if running is not None:
            self._running = None
            folder = self._folders.pop(running[0], None)
            if folder is not None:
                working_folder.keep(self.run_dir, folder)

    def close(self) -> None:
        if self._running is not None:
            self.end(self._running[1])
        if self._spare is not None:
            kill(self._spare[2])
            self._spare = None
        for folder in self._folders.values():
            working_folder.discard(folder)
        self._folders.clear()
        if self._zygote is not None:
            self._zygote.close()
            self._zygote = None
        for out in self._outputs.values():
            out.join()
        self._log.close()
