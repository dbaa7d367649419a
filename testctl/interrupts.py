"""How a command of the bench stops when the user stops it: Ctrl-C or SIGTERM, one line and the status a
shell expects (130, 143), within a second, never a traceback or click's "Aborted!". Light, for `hako try`,
`hako run`, `hako test` and `hako dashboard`.

Python's own Ctrl-C raises KeyboardInterrupt in whatever Python code runs when the signal comes, and that
may be a library's callback: distributed's garbage-collector hook, a finalizer, a `__del__`. Raised there,
the interrupt is printed as "Exception ignored in ..." and lost, or it breaks the library's state (an
AssertionError in `distributed/gc.py`), and the run goes on. So `interrupts()` raises it only at a point of
our own code, or of code that merely waits or computes for us (the standard library, NumPy): when the signal
lands in a callback or inside Dask or its event loop, it is raised at the next such point, looked for every
RETRY_S. Whatever then goes wrong, the signal wins: a process still alive EXIT_WITHIN_S after it (cleaning up
slowly, or its interrupt swallowed after all) says its line and ends with the status; so does a second
Ctrl-C. That loses nothing: every finished test is in the journal already (fsynced), the benches die with
their parents, and the campaign folder's lock is the kernel's.
"""

from __future__ import annotations

import atexit
import gc
import os
import signal
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType
from typing import NoReturn

import click

from hakoniwa.wire.exits import EXIT_INTERRUPTED, EXIT_TERMINATED

RETRY_S = 0.02  # how often an interrupt that came at a bad moment looks for a good one
EXIT_WITHIN_S = 0.5  # from the signal to the end of the process, whatever it is doing (the promise: 1 s)

# Packages whose code runs callbacks for others (the event loop, the cluster's bookkeeping): an interrupt
# raised in them breaks them or is swallowed.
_CALLBACK_PACKAGES = frozenset({"distributed", "tornado", "dask", "asyncio", "weakref", "concurrent", "zict",
                                "msgpack", "cloudpickle"})
_OUR_PACKAGES = frozenset({"testctl", "hakoniwa", "athrill_sim"})


class Terminated(KeyboardInterrupt):
    """SIGTERM, turned into an interrupt so that it unwinds like Ctrl-C: benches and the cluster closed, the
    journal's place and the resume command said."""


class _Stop:
    """The state of one stop: which signal, when, whether it was raised and whether its line was said."""

    def __init__(self) -> None:
        self.signum: int | None = None
        self.at = 0.0
        self.raised = False
        self.said = False
        self.hint = ""  # what the line adds once the command knows it (the resume command)
        self.pid = os.getpid()  # the process whose stop this is; a child forked from it inherits the handler

    @property
    def status(self) -> int:
        return EXIT_TERMINATED if self.signum == signal.SIGTERM else EXIT_INTERRUPTED

    def line(self, hint: str = "") -> str:
        how = "terminated" if self.signum == signal.SIGTERM else "interrupted"
        return f"\n{how}: {hint}" if hint else f"hako: {how}"


_stop: _Stop | None = None  # set while `interrupts()` is in force


def _package(frame: FrameType) -> str:
    """The top-level package (or module) a frame's code belongs to, as imported."""
    return (frame.f_globals.get("__name__") or "").partition(".")[0]


def _is_callback(frame: FrameType) -> bool:
    code = frame.f_code
    return code.co_name == "__del__" or any(getattr(getattr(cb, "__func__", cb), "__code__", None) is code
                                            for cb in gc.callbacks)


def safe_to_raise(frame: FrameType | None) -> bool:
    """Whether an interrupt raised in `frame` unwinds through our own code: no callback and no frame of the
    cluster's machinery between it and the nearest frame of ours."""
    while frame is not None:
        package = _package(frame)
        if _is_callback(frame) or package in _CALLBACK_PACKAGES:
            return False
        if package in _OUR_PACKAGES:
            return True
        frame = frame.f_back
    return True  # nothing of ours on the stack: the interpreter's own start or end


def _hard_exit(stop: _Stop) -> NoReturn:
    if not stop.said:
        os.write(2, (stop.line(stop.hint) + "\n").encode())
    os._exit(stop.status)


def _handle(signum: int, frame: FrameType | None) -> None:
    stop = _stop
    assert stop is not None
    if os.getpid() != stop.pid:
        # A child between fork and exec (Popen's preexec_fn, the interpreter's after-fork hooks) got the
        # group's Ctrl-C: it ends as the program it was about to become would, by the signal and silently,
        # not with a KeyboardInterrupt printed from the middle of Popen.
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)
        return
    if signum == signal.SIGALRM:
        if stop.signum is None:
            return
    elif stop.signum is not None:  # a second Ctrl-C: the user will not wait for the cleanup
        _hard_exit(stop)
    else:
        stop.signum, stop.at = signum, time.monotonic()
    left = stop.at + EXIT_WITHIN_S - time.monotonic()
    if left <= 0:
        _hard_exit(stop)
    if not stop.raised and safe_to_raise(frame):
        stop.raised = True
        signal.setitimer(signal.ITIMER_REAL, left)
        raise Terminated if stop.signum == signal.SIGTERM else KeyboardInterrupt
    signal.setitimer(signal.ITIMER_REAL, left if stop.raised else min(RETRY_S, left))


@contextmanager
def interrupts() -> Iterator[None]:
    """Ctrl-C and SIGTERM as an interrupt raised at a safe point (KeyboardInterrupt, `Terminated`), and the
    process ended EXIT_WITHIN_S after the signal whatever it is doing."""
    global _stop
    _stop = _Stop()
    # A command started with Ctrl-C ignored (a background job, nohup) keeps ignoring it, as Python would.
    ours = [s for s in (signal.SIGINT, signal.SIGTERM, signal.SIGALRM) if signal.getsignal(s) is not signal.SIG_IGN]
    previous = {s: signal.signal(s, _handle) for s in ours}
    atexit.register(_end)  # after every exit handler registered later: the libraries' (Dask's) run first
    try:
        yield
    finally:
        if _stop.signum is None:
            atexit.unregister(_end)
            signal.setitimer(signal.ITIMER_REAL, 0)
            for s, handler in previous.items():
                signal.signal(s, handler)
            _stop = None
        # else the process is ending: the deadline stays armed over the interpreter's own shutdown


def _end() -> None:
    """The last exit handler of a stopped process: end it now, with its status. What the interpreter would
    do next undoes our handlers while the deadline is armed, and its alarm would end it as a signal."""
    if _stop is not None and _stop.signum is not None:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(_stop.status)


def on_stop_say(hint: str) -> None:
    """What the one line says if a stop comes from here on, also when the deadline ends the process before
    the interrupt has unwound to `stopped_by` (a loaded machine's slow cleanup)."""
    if _stop is not None:
        _stop.hint = hint


def stopped_by(interrupt: KeyboardInterrupt, hint: str = "") -> NoReturn:
    """One line for Ctrl-C or SIGTERM (after a newline that ends a progress bar's line, when there is a
    campaign to resume), and the exit status a shell expects of either."""
    stop = _stop or _Stop()
    if stop.signum is None:  # an interrupt `interrupts()` did not see: Python's own Ctrl-C
        stop.signum = signal.SIGTERM if isinstance(interrupt, Terminated) else signal.SIGINT
    click.echo(stop.line(hint), err=True)
    sys.stderr.flush()
    stop.said = True
    sys.exit(stop.status)
