"""The robot program as the physics side sees it: something that starts a fresh Athrill for every test.

In Hakoniwa the physics asset and the Athrill asset are peers that share only the wire, and a conductor
starts them. Here the physics process starts each test's Athrill (that is how the paper re-initializes the
program), but what runs, how it is built and how it is tuned is the robot-program side's business
(`athrill_sim`). So the physics server takes a `Launcher` from whoever builds the bench, and never imports
the program side: this protocol is all the two share besides the mapped files.
"""

from __future__ import annotations

import subprocess
from typing import Protocol

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.protocol import MappedFile, SyncMode
from hakoniwa.wire.vdev_udp import UdpLink


class ProgramRefused(HakoError, ValueError):
    """This test's parameter values make no program that runs (a value it does not build with): the test is
    the program's failure, and the message, one line, is what the user reads of it."""


class Launcher(Protocol):
    """The per-test launch of one robot program, for the physics server that owns it (and closes it)."""

    @property
    def sync(self) -> SyncMode:
        """How the program keeps time with physics: the sync loop the physics server runs it in."""

    @property
    def udp(self) -> UdpLink | None:
        """athrill2's UDP endpoints for a program run over UDP; None where the mapped files carry everything."""

    @property
    def serial_hub(self) -> bool:
        """The program reaches a SPIKE hub over a serial port (RasPike-ART's asp), not through the mapped
        files: the physics side plays the hub on a pseudo-terminal linked at the run directory's
        `rundir.RASPIKE_PORT`."""

    def prepare(self, seq: int, unity: MappedFile) -> None:
        """Make the program test `seq`'s parameter values (in `unity`'s parameter area) ask for, with its data
        files written, before the test is announced.

        Raises:
            ProgramRefused: the values make no program that runs (the program's failure).
            OSError: the program cannot be prepared (the bench's failure), with a message that says for what.
        """

    def take(self, seq: int) -> subprocess.Popen:
        """The Athrill process of test `seq`, running the program `prepare` made; OSError if it cannot start."""

    def end(self, proc: subprocess.Popen) -> None:
        """The test of `proc` is over: stop it as the robot's program is stopped (a Ctrl-C first, for a program
        that takes one), and keep what it leaves."""

    def last_lines(self, proc: subprocess.Popen, n: int) -> list[str]:
        """The last lines an ended process printed: a crashed program's own error."""

    def close(self) -> None:
        """No test follows: stop what runs ahead, and close the output."""
