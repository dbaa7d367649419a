"""How a command of the bench stops when the user stops it: Ctrl-C or SIGTERM, one line and the status a
shell expects (130, 143), never a traceback or click's "Aborted!". Light, for `hako trial` and `hako run`."""

from __future__ import annotations

import signal
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import NoReturn

import click

from hakoniwa.wire.processes import INTERRUPTED

TERMINATED = 128 + signal.SIGTERM


class Terminated(KeyboardInterrupt):
    """SIGTERM, turned into an interrupt so that it unwinds like Ctrl-C: benches and the cluster closed, the
    journal's place and the resume command said."""


@contextmanager
def sigterm_interrupts() -> Iterator[None]:
    def handler(signum: int, frame: object) -> None:
        raise Terminated

    previous = signal.signal(signal.SIGTERM, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def stopped_by(interrupt: KeyboardInterrupt, hint: str = "") -> NoReturn:
    """One line for Ctrl-C or SIGTERM (after a newline that ends a progress bar's line, when there is a
    campaign to resume), and the exit status a shell expects of either."""
    terminated = isinstance(interrupt, Terminated)
    how = "terminated" if terminated else "interrupted"
    click.echo(f"\n{how}: {hint}" if hint else f"hako: {how}", err=True)
    sys.exit(TERMINATED if terminated else INTERRUPTED)
