"""Runs a user's mms mouse program, unchanged, as a child process: its stdout lines are commands, the answers go
to its stdin, its stderr to a file, capped as our own logs are (the head and the tail of it kept). Headless and as
fast as the program can talk (no animation delays).

Every run ends with a `Stop`: why (a `StopReason`) and the facts its one line names. A fault (a line that is no
mms command, no line for `timeout` seconds, the program exiting with an error status, ...) ends it with the world
as it was, so the wall log written so far is kept. A run cut at the command cap is no fault, but has its own
reason, since the search did not end and CI must be able to tell.
"""

from __future__ import annotations

import enum
import os
import select
import selectors
import shlex
import shutil
import subprocess
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

from hakoniwa.wire.output import LOG_CAP_BYTES, CappedOutput

from ..errors import MazeError
from .mms import MmsCommandError, parse_command
from .mmsworld import MmsWorld

READ_BYTES = 65536
MAX_COMMANDS = 2_000_000  # mms's templates never stop on their own: a run ends here at the latest (minutes)
MAX_LINE_BYTES = 1 << 16  # a longer line without a newline is no command: the program is printing garbage
KILL_WAIT_S = 2.0
STARTUP_S = 30.0  # the wait for a program's first line at least: a JVM, or a loaded CI runner, starts slowly


class StopReason(enum.Enum):
    """Why a run ended; the value is its line, filled in from `Stop.facts`."""

    EXITED = "the program exited"
    MAX_STEPS = "--max-steps {max_steps} reached"
    TIME_BUDGET = "--time-budget {budget:g} s of modelled search time used up"
    COMMAND_CAP = "{cap} commands sent (a program that never ends its search; see --max-steps)"
    SILENT = "the program sent no command for {wait:g} s (last command: {last})"
    LONG_LINE = "line {line} of the program's output is longer than {limit} bytes (no mms command is)"
    BAD_COMMAND = "line {line} of the program's output: {error}"
    DEAF = "the program read none of its answers for {wait:g} s (last command: {last})"
    FAILED = "the program exited with status {status}{tail}"
    KILLED = "the program was killed by signal {signal}{tail}"
    INTERRUPTED = "interrupted (Ctrl-C) after {commands} command{s}"

    @property
    def is_fault(self) -> bool:
        """Something went wrong, as opposed to an end the user asked for or the program chose."""
        return self not in (StopReason.EXITED, StopReason.MAX_STEPS, StopReason.TIME_BUDGET, StopReason.COMMAND_CAP)


@dataclass(frozen=True)
class Stop:
    reason: StopReason
    facts: dict[str, object] = field(default_factory=dict)

    @property
    def message(self) -> str:
        return self.reason.value.format(**self.facts)


@dataclass
class MouseRun:
    world: MmsWorld
    commands: int
    stop: Stop
    status: int | None  # the program's exit status, if it exited
    wall_s: float

    @property
    def ended(self) -> str:
        """Why the run ended, in words: `fault` for a fault, whose line is `fault`."""
        return "fault" if self.stop.reason.is_fault else self.stop.message

    @property
    def fault(self) -> str | None:
        return self.stop.message if self.stop.reason.is_fault else None

    @property
    def at_command_cap(self) -> bool:
        """Ended by MAX_COMMANDS: the program never ended its search."""
        return self.stop.reason is StopReason.COMMAND_CAP


def program_argv(command: str) -> list[str]:
    """The command line of --mouse, checked before anything runs: its first word must be a program."""
    try:
        argv = shlex.split(command)
    except ValueError as e:
        raise MazeError(f"--mouse {command!r}: {e}") from None
    if not argv:
        raise MazeError("--mouse: empty command")
    exe = argv[0]
    found = shutil.which(exe) if os.sep not in exe else (exe if os.access(exe, os.X_OK) else None)
    if found is None:
        where = "not an executable file" if os.sep in exe else "not found on PATH"
        raise MazeError(f"--mouse {command!r}: {exe!r} is {where}")
    return argv


class LineReader:
    """The program's stdout as lines, each waited for at most a given time; a line is no longer than
    MAX_LINE_BYTES (a program printing garbage without newlines must not fill our memory)."""

    def __init__(self, fd: int) -> None:
        self.fd = fd
        self.selector = selectors.DefaultSelector()
        self.selector.register(fd, selectors.EVENT_READ)
        self.buffer, self.start = b"", 0  # lines are taken from `start` on, so a burst is not copied line by line
        self.lineno = 0  # lines read so far, blank ones included: how a user counts them
        self.heard = False  # the program has written anything at all

    def wait_for(self, timeout: float) -> float:
        """--timeout is per command; the first one also waits for the program to start."""
        return timeout if self.heard else max(timeout, STARTUP_S)

    def next_line(self, wait: float) -> str | StopReason:
        """The next line (its newline and a trailing CR removed), or EXITED, SILENT (nothing for `wait` seconds)
        or LONG_LINE."""
        while (newline := self.buffer.find(b"\n", self.start)) < 0:
            if not self.selector.select(wait):
                return StopReason.SILENT
            chunk = os.read(self.fd, READ_BYTES)
            if not chunk:
                return StopReason.EXITED
            self.heard = True
            self.buffer, self.start = self.buffer[self.start:] + chunk, 0
            if len(self.buffer) > MAX_LINE_BYTES and b"\n" not in self.buffer:
                return StopReason.LONG_LINE
        raw, self.start = self.buffer[self.start:newline], newline + 1
        self.lineno += 1
        return raw.decode("utf-8", "replace").rstrip("\r")

    def close(self) -> None:
        self.selector.close()


def run_mouse(argv: list[str], world: MmsWorld, stderr_path: Path, max_steps: int | None,
              time_budget: float | None, timeout: float) -> MouseRun:
    """Talk to the program until it exits, `max_steps` cells are entered or the modelled search time passes
    `time_budget`; a fault ends the run early and says why in one line."""
    t0 = time.perf_counter()
    with open(stderr_path, "wb") as err:
        err_read, err_write = os.pipe()
        try:
            proc = subprocess.Popen(argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=err_write, bufsize=0)
        except OSError as e:
            os.close(err_read)
            raise MazeError(f"--mouse: cannot start {argv[0]!r}: {e.strerror}") from None
        finally:
            os.close(err_write)
        stderr = CappedOutput(open(err_read, "rb"), err, threading.Lock(), "the program", cap=LOG_CAP_BYTES,
                              log_name=stderr_path.name, per="")
        assert proc.stdout is not None and proc.stdin is not None
        in_fd = proc.stdin.fileno()
        os.set_blocking(in_fd, False)  # a program that never reads its answers must not block us once the pipe is full
        reader = LineReader(proc.stdout.fileno())
        talk = _Talk(world, in_fd, max_steps, time_budget, timeout)
        stop: Stop | None = None
        try:
            stop = talk.run(reader)
        except KeyboardInterrupt:
            stop = Stop(StopReason.INTERRUPTED, {"commands": talk.commands, "s": "s" * (talk.commands != 1)})
        finally:
            reader.close()
            status = _finish(proc, stop is not None and stop.reason is StopReason.EXITED)
            stderr.join()  # its last words are in the file before the run is reported
    if stop.reason is StopReason.EXITED and status:
        tail = " ".join(stderr.last_lines(1)).strip()
        facts = {"tail": f": {tail}" if tail else ""}
        stop = Stop(StopReason.KILLED, {"signal": -status, **facts}) if status < 0 else \
            Stop(StopReason.FAILED, {"status": status, **facts})
    return MouseRun(world, talk.commands, stop, status, time.perf_counter() - t0)


class _Talk:
    """The conversation: each command the reader gives is played in the world and answered, until a stop."""

    def __init__(self, world: MmsWorld, in_fd: int, max_steps: int | None, time_budget: float | None,
                 timeout: float) -> None:
        self.world, self.in_fd = world, in_fd
        self.max_steps, self.time_budget, self.timeout = max_steps, time_budget, timeout
        self.commands = 0
        self.last = "(none yet)"

    def run(self, reader: LineReader) -> Stop:
        while True:
            wait = reader.wait_for(self.timeout)
            line = reader.next_line(wait)
            if line is StopReason.SILENT:
                return Stop(line, {"wait": wait, "last": self.last})
            if line is StopReason.LONG_LINE:
                return Stop(line, {"line": reader.lineno + 1, "limit": MAX_LINE_BYTES})
            if isinstance(line, StopReason):
                return Stop(line)
            if line.strip() and (stop := self.play(line, reader.lineno)) is not None:
                return stop

    def play(self, line: str, lineno: int) -> Stop | None:
        """One command line, answered; the stop it brings, if any."""
        world = self.world
        try:
            cmd = parse_command(line)
        except MmsCommandError as e:
            if e.fatal:
                return Stop(StopReason.BAD_COMMAND, {"line": lineno, "error": e})
            # no answer was due: mms drops it and the program carries on
            world.warnings.append(f"line {lineno} of the program's output: {e} (ignored, as mms does)")
            return None
        reply = world.handle(cmd)
        self.commands += 1
        self.last = f"{line[:40]!r} (line {lineno})"
        if reply is not None:
            try:
                if not _send(self.in_fd, reply.encode() + b"\n", self.timeout):
                    return Stop(StopReason.DEAF, {"wait": self.timeout, "last": self.last})
            except BrokenPipeError:
                return Stop(StopReason.EXITED)
        if self.max_steps is not None and world.steps >= self.max_steps:
            return Stop(StopReason.MAX_STEPS, {"max_steps": self.max_steps})
        if self.commands >= MAX_COMMANDS:
            return Stop(StopReason.COMMAND_CAP, {"cap": MAX_COMMANDS})
        if self.time_budget is not None and world.search().seconds > self.time_budget:
            return Stop(StopReason.TIME_BUDGET, {"budget": self.time_budget})
        return None


def _send(fd: int, data: bytes, timeout: float) -> bool:
    """Write all of `data`, waiting at most `timeout` seconds at a time for the program to make room."""
    while data:
        try:
            data = data[os.write(fd, data):]
        except BlockingIOError:
            if not select.select([], [fd], [], timeout)[1]:
                return False
    return True


def _finish(proc: subprocess.Popen[bytes], exited: bool) -> int | None:
    """Reap the program; one still running (we stopped the run) is terminated, then killed."""
    for stream in (proc.stdin, proc.stdout):
        assert stream is not None  # started with both piped
        try:
            stream.close()
        except OSError:
            pass
    try:
        return proc.wait(timeout=KILL_WAIT_S if exited else 0.05)
    except subprocess.TimeoutExpired:
        proc.terminate()
    try:
        proc.wait(timeout=KILL_WAIT_S)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
    return None
