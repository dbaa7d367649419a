"""Runs a user's mms mouse program, unchanged, as a child process: its stdout lines are commands, the answers go
to its stdin, its stderr to a file, capped as our own logs are (the head and the tail of it kept). Headless and as
fast as the program can talk (no animation delays).

Every way a run can go wrong ends it with one line in `MouseRun.fault` (and the world as it was, so the wall log
written so far is kept): a line that is no mms command, no line for `timeout` seconds, the program exiting with
an error status. A run cut at the command cap is no fault, but is marked (`MouseRun.at_command_cap`), since the
search did not end and CI must be able to tell.
"""

from __future__ import annotations

import os
import select
import selectors
import shlex
import shutil
import subprocess
import threading
import time
from dataclasses import dataclass
from pathlib import Path

from hakoniwa.wire.output import LOG_CAP_BYTES, CappedOutput

from .errors import MazeError
from .mms import MmsCommandError, parse_command
from .mmsworld import MmsWorld

READ_BYTES = 65536
MAX_COMMANDS = 2_000_000  # mms's templates never stop on their own: a run ends here at the latest (minutes)
MAX_LINE_BYTES = 1 << 16  # a longer line without a newline is no command: the program is printing garbage
KILL_WAIT_S = 2.0
STARTUP_S = 30.0  # the wait for a program's first line at least: a JVM, or a loaded CI runner, starts slowly


@dataclass
class MouseRun:
    world: MmsWorld
    commands: int
    ended: str  # why the run ended, in words
    fault: str | None  # one line when the run ended because something went wrong
    status: int | None  # the program's exit status, if it exited
    wall_s: float
    at_command_cap: bool = False  # ended by MAX_COMMANDS: the program never ended its search


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
        out_fd, in_fd = proc.stdout.fileno(), proc.stdin.fileno()
        os.set_blocking(in_fd, False)  # a program that never reads its answers must not block us once the pipe is full
        selector = selectors.DefaultSelector()
        selector.register(out_fd, selectors.EVENT_READ)
        buffer, start = b"", 0  # lines are taken from `start` on, so a burst of lines is not copied line by line
        commands, lineno = 0, 0
        ended, fault, capped = "", None, False
        last = "(none yet)"
        try:
            while True:
                newline = buffer.find(b"\n", start)
                if newline < 0:
                    wait = timeout if lineno or buffer else max(timeout, STARTUP_S)  # --timeout is per command
                    if not selector.select(wait):
                        fault = f"the program sent no command for {wait:g} s (last command: {last})"
                        break
                    chunk = os.read(out_fd, READ_BYTES)
                    if not chunk:
                        ended = "the program exited"
                        break
                    buffer, start = buffer[start:] + chunk, 0
                    if len(buffer) > MAX_LINE_BYTES and b"\n" not in buffer:
                        fault = (f"line {lineno + 1} of the program's output is longer than {MAX_LINE_BYTES} bytes "
                                 f"(no mms command is)")
                        break
                    continue
                raw, start = buffer[start:newline], newline + 1
                lineno += 1
                line = raw.decode("utf-8", "replace").rstrip("\r")
                if not line.strip():
                    continue
                try:
                    cmd = parse_command(line)
                except MmsCommandError as e:
                    if not e.fatal:  # no answer was due: mms drops it and the program carries on
                        world.warnings.append(f"line {lineno} of the program's output: {e} (ignored, as mms does)")
                        continue
                    fault = f"line {lineno} of the program's output: {e}"
                    break
                reply = world.handle(cmd)
                commands += 1
                last = f"{line[:40]!r} (line {lineno})"
                if reply is not None:
                    try:
                        if not _send(in_fd, reply.encode() + b"\n", timeout):
                            fault = (f"the program read none of its answers for {timeout:g} s (last command: "
                                     f"{last})")
                            break
                    except BrokenPipeError:
                        ended = "the program exited"
                        break
                if max_steps is not None and world.steps >= max_steps:
                    ended = f"--max-steps {max_steps} reached"
                    break
                if commands >= MAX_COMMANDS:
                    ended = f"{MAX_COMMANDS} commands sent (a program that never ends its search; see --max-steps)"
                    capped = True
                    break
                if time_budget is not None and world.search().seconds > time_budget:
                    ended = f"--time-budget {time_budget:g} s of modelled search time used up"
                    break
        except KeyboardInterrupt:
            fault = f"interrupted (Ctrl-C) after {commands} command{'s' * (commands != 1)}"
        finally:
            selector.close()
            status = _finish(proc, ended == "the program exited")
            stderr.join()  # its last words are in the file before the run is reported
    if ended == "the program exited" and status:
        tail = " ".join(stderr.last_lines(1)).strip()
        how = f"was killed by signal {-status}" if status < 0 else f"exited with status {status}"
        fault = f"the program {how}" + (f": {tail}" if tail else "")
    if fault is not None:
        ended = "fault"
    return MouseRun(world, commands, ended, fault, status, time.perf_counter() - t0, capped and fault is None)


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
