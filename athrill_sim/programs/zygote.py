"""A fork server for the mock Athrill: one process per bench imports the mock once and forks a fresh one for
every test.

Why: a new Python process that imports click and the mock costs 0.07-0.12 s of CPU, about a fifth of the CPU
of a whole test on a campaign's busy cores (it is started one test ahead, so it costs no wall time on an idle
core, but a campaign has none). A fork of a process that has already imported them costs about a millisecond.

Each child is still the fresh process the paper restarts the robot program in: the zygote never imports or
runs the robot program (the child does, after the fork, exactly as `athrill-sim` does), its `random` is
reseeded, and it gets a session, a working directory and an output pipe of its own. A pidfd tells the
physics side when it has exited; the zygote, its parent, reaps it and says how.

The zygote is an optimization only: where it cannot be started or stops answering, the launcher starts
`athrill-sim` processes the usual way (`athrill_sim.programs.program.Program.spawn`).
"""

from __future__ import annotations

import json
import os
import select
import signal
import socket
import subprocess
import sys
from pathlib import Path

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.processes import die_with_parent

MAX_MESSAGE = 65536  # one request or answer: a command line, well under a page or two


class ZygoteGone(HakoError, OSError):
    """The zygote cannot serve: it died, or this system lacks what it needs (pidfds)."""


class Zygote:
    """The physics side's handle on one fork server (started here, killed with `close`)."""

    def __init__(self) -> None:
        if not hasattr(os, "pidfd_open"):
            raise ZygoteGone("no pidfd_open on this system")
        self._sock, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        try:
            self._proc = subprocess.Popen(
                [sys.executable, "-m", "athrill_sim.programs.zygote", str(theirs.fileno())],
                pass_fds=(theirs.fileno(),),
                stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                start_new_session=True, preexec_fn=die_with_parent)
        finally:
            theirs.close()

    def _ask(self, request: dict, fds: list[int] | None = None) -> dict:
        try:
            if fds:
                socket.send_fds(self._sock, [json.dumps(request).encode()], fds)
            else:
                self._sock.send(json.dumps(request).encode())
            answer = self._sock.recv(MAX_MESSAGE)
        except OSError as e:
            raise ZygoteGone(f"the mock's fork server: {e}") from None
        if not answer:
            raise ZygoteGone("the mock's fork server has exited")
        reply = json.loads(answer)
        if "error" in reply:
            raise ZygoteGone(f"the mock's fork server: {reply['error']}")
        return reply

    def spawn(self, args: list[str], cwd: Path | None) -> ForkedProcess:
        """Fork `athrill-sim ARGS` (what `python -m athrill_sim.mock.main ARGS` runs), its output to a new pipe."""
        read, write = os.pipe()
        try:
            pid = self._ask({"spawn": args, "cwd": str(cwd) if cwd is not None else None}, [write])["pid"]
        except BaseException:
            os.close(read)
            raise
        finally:
            os.close(write)
        try:
            pidfd = os.pidfd_open(pid)
        except OSError as e:  # it exited and was reaped already: cannot be, the zygote reaps only when asked
            os.close(read)
            raise ZygoteGone(f"no pidfd for the forked mock {pid}: {e}") from None
        return ForkedProcess(self, pid, pidfd, open(read, "rb"), args)

    def exit_status(self, pid: int) -> int:
        """Reap an exited child: its exit status as Popen's returncode (negative: the signal)."""
        return os.waitstatus_to_exitcode(self._ask({"wait": pid})["status"])

    def close(self) -> None:
        self._sock.close()  # the zygote exits when its socket closes; kill it in case it is stuck
        if self._proc.poll() is None:
            self._proc.kill()
        self._proc.wait()


class ForkedProcess(subprocess.Popen):
    """A child of the zygote, seen from the physics process as the `Popen` it would otherwise have started:
    the sync loops and the launcher use `pid`, `stdout`, `poll`, `wait`, `kill` and `returncode`, and its
    pid is its own (the mock writes it into the TX area). It subclasses Popen only to be one to the type
    checker and to those callers; Popen's own start-up is never run."""

    def __init__(self, zygote: Zygote, pid: int, pidfd: int, stdout, args: list[str]) -> None:
        self._zygote, self._pidfd = zygote, pidfd
        self.pid, self.stdout, self.args = pid, stdout, ["athrill-sim", *args]
        self.stdin = self.stderr = None
        self.returncode = None
        self._child_created = False  # Popen.__del__: nothing of Popen's own to clean up

    def poll(self) -> int | None:
        return self.wait(timeout=0) if self.returncode is None else self.returncode

    def wait(self, timeout: float | None = None) -> int | None:  # type: ignore[override]
        if self.returncode is not None:
            return self.returncode
        ready, _, _ = select.select([self._pidfd], [], [], timeout)
        if not ready:
            if timeout == 0:
                return None
            raise subprocess.TimeoutExpired(self.args, timeout or 0)
        self.returncode = self._zygote.exit_status(self.pid)
        os.close(self._pidfd)
        return self.returncode

    def send_signal(self, sig: int) -> None:
        if self.returncode is None:  # not reaped yet, so the pid is still this process's (a zombie at worst)
            try:
                os.kill(self.pid, sig)
            except ProcessLookupError:
                pass

    def terminate(self) -> None:
        self.send_signal(signal.SIGTERM)

    def kill(self) -> None:
        self.send_signal(signal.SIGKILL)


def _child(sock: socket.socket, out_fd: int, args: list[str], cwd: str | None) -> None:
    """In the forked child: become what `python -m athrill_sim.mock.main ARGS` would be, run it, and exit."""
    code: int | str | None = 1
    try:
        sock.close()
        os.setsid()
        die_with_parent()
        stdin = os.open(os.devnull, os.O_RDONLY)
        os.dup2(stdin, 0)
        os.dup2(out_fd, 1)
        os.dup2(out_fd, 2)
        for fd in (stdin, out_fd):
            os.close(fd)
        if cwd is not None:
            os.chdir(cwd)
        if "random" in sys.modules:  # imported by the zygote's modules: a fresh process draws a fresh seed
            sys.modules["random"].seed()
        sys.argv = ["athrill-sim", *args]
        from athrill_sim.mock.main import main

        main.main(args=args, prog_name="athrill-sim")
        code = 0
    except SystemExit as e:
        code = e.code
    except BaseException:  # what an uncaught exception does to a Python process: its traceback, status 1
        import traceback

        traceback.print_exc()
        code = 1
    finally:
        if isinstance(code, str):
            print(code, file=sys.stderr)
            code = 1
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
        os._exit(code or 0)


def serve(sock: socket.socket) -> None:
    """The zygote's loop: fork on request, reap on request, exit when the physics side hangs up."""
    import athrill_sim.mock.main  # noqa: F401  # the mock's modules, imported once for every child

    while True:
        try:
            message, fds, _, _ = socket.recv_fds(sock, MAX_MESSAGE, 1)
        except OSError:
            return
        if not message:
            return
        request = json.loads(message)
        try:
            if "spawn" in request:
                sys.stdout.flush()
                sys.stderr.flush()
                pid = os.fork()
                if pid == 0:
                    _child(sock, fds[0], request["spawn"], request["cwd"])
                for fd in fds:
                    os.close(fd)
                answer: dict = {"pid": pid}
            else:
                answer = {"status": os.waitpid(request["wait"], 0)[1]}
        except OSError as e:
            answer = {"error": str(e)}
        sock.send(json.dumps(answer).encode())


if __name__ == "__main__":
    serve(socket.socket(fileno=int(sys.argv[1])))
