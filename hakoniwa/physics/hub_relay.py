"""The transport of a program that reaches its SPIKE hub over a serial port (RasPike-ART's asp): the physics
side plays the hub (`raspike_hub.PtyHub`) on a pseudo-terminal of each test's own, in the lockstep.

asp keeps time through the mapped files like any lockstep program (its clock library rings the answer slot), but
its motors and sensors are the hub's business: before each snapshot is published the hub takes in what asp
counted as sent and answers it, with a status when one is due (every 10 ms of simulated time); after each answer
it takes in what asp sent during the step and its motor commands go where the loop takes commands from. So asp's
commands reach the motors at the step they were sent, as a native program's do, and its tasks read a status only
at the step it is sent (`asp_serial.c`). Between statuses asp's clock moves on without waiting for the physics
side (asp_time.c): alone while it sends nothing, and where it sends bytes that nothing of its waits to hear back
about, with an answer it does not wait on. The physics side catches up to the step of each answer
(`sync.run_lockstep`) and takes the bytes in there: nothing asp reads could have changed meanwhile. A link the
hub cannot keep (the pty closed, a malformed frame, another protocol version, a program that never opens the
port) is a fault of the bench, never a result of the parameters under test.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from hakoniwa.physics.raspike_hub import Hub, HubFault, PtyHub, SerialCounts
from hakoniwa.physics.relay import MappedFiles
from hakoniwa.physics.sensors import Sensors
from hakoniwa.physics.slots import Slots
from hakoniwa.physics.sync import AthrillCrash
from hakoniwa.wire.protocol import MOTOR_PORTS, BenchCause, CrashKind
from hakoniwa.wire.rundir import RASPIKE_PORT
from hakoniwa.wire.timebase import US_PER_S

# RasPike-ART's main shakes hands with the hub before anything else (raspike_protocol.c 136-160, from main.c):
# a program that has not by then never opens the port.
HANDSHAKE_BY_US = 5 * US_PER_S


class HubRelay(MappedFiles):
    """The mapped files carry asp's clock; the hub, on its pty, carries everything else."""

    def __init__(self, slots: Slots, run_dir: Path, kinds: dict[int, int]) -> None:
        """`kinds`: what is plugged into each of the hub's ports (`raspike_hub.hub_kinds`)."""
        self.slots = slots
        self.run_dir = run_dir
        self.kinds = kinds
        self._link: tuple[PtyHub, SerialCounts] | None = None  # this test's hub and the run's byte counts
        self._relayed: tuple[tuple[int, ...], tuple[int, ...]] | None = None  # the motors as last written to TX

    def launching(self) -> None:
        """A fresh hub on a fresh pty for this test's asp, and both byte counts at zero."""
        self.ended()
        self._relayed = None
        try:
            pty = PtyHub(Hub(self.kinds))
            self._link = pty, SerialCounts(self.run_dir)
            link = self.run_dir / RASPIKE_PORT
            link.unlink(missing_ok=True)
            link.symlink_to(pty.device)
        except OSError as e:
            raise OSError(f"cannot play the SPIKE hub on a pseudo-terminal: {e}") from e

    reads_files = False

    def publishing(self, read: Callable[[], Sensors], now_us: int) -> None:
        if self._link is None:
            return
        pty, counts = self._link
        counts.publish(self._exchange(pty, counts, read, now_us), pty.next_status_us)
        if not pty.hub.shook_hands and now_us >= HANDSHAKE_BY_US:
            raise AthrillCrash(CrashKind.BENCH, 0, f"the program did not open the hub's serial port in "
                               f"{HANDSHAKE_BY_US // US_PER_S} s of simulated time", BenchCause.HUB_FAILED)

    def answered(self, now_us: int) -> None:
        if self._link is not None:
            self._exchange(*self._link, None, now_us)  # its count goes out with the next snapshot

    def _exchange(self, pty: PtyHub, counts: SerialCounts, read: Callable[[], Sensors] | None, now_us: int) -> int:
        """The hub takes in what asp counted as sent and answers it (`PtyHub.exchange`), and what it was asked
        of the motors goes where the loop takes commands from; the bytes the hub has sent. A link it cannot
        keep ends the test as the bench's fault."""
        try:
            sent = pty.exchange(read, now_us, counts.program_sent)
        except HubFault as e:
            raise AthrillCrash(CrashKind.BENCH, 0, str(e), BenchCause.HUB_FAILED) from None
        motors = pty.hub.powers(MOTOR_PORTS)
        if motors != self._relayed:  # twice a stop: written only when they change
            self.slots.relay_commands(*motors)
            self._relayed = motors
        return sent

    def ended(self) -> None:
        if self._link is not None:
            pty, counts = self._link
            pty.close()
            counts.close()
            self._link = None

    def close(self) -> None:
        self.ended()
