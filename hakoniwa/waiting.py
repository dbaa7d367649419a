"""Waiting on a peer across the mapped files: spin briefly, then nap, and check the peer is still there.

A lockstep handshake costs two waits per control period. Sleeping, even for 50 us, costs 100+ us on a
virtual machine, which would dominate a trial; spinning costs nothing while the peer answers within a few
milliseconds, which it does unless the machine is overloaded, when napping takes over so the spinner does
not starve the very process it waits for.
"""

from __future__ import annotations

import os
import time
from typing import Callable

SPIN_S = 0.002  # busy-wait this long before napping
NAP_S = 0.00005
CHECK_EVERY_S = 0.02  # how often `on_idle` runs while waiting


def wait_for(ready: Callable[[], bool], on_idle: Callable[[], None], *, spin_s: float = SPIN_S,
             nap_s: float = NAP_S, spin_from_s: float = 0.0) -> None:
    """Return once `ready()` is true: nap until `spin_from_s` has passed, spin for `spin_s`, then nap.
    `on_idle` runs every CHECK_EVERY_S and raises to give up.

    `spin_from_s` is for a waiter that knows roughly when the answer comes (Athrill waiting out a control
    period): it naps through most of the wait and spins only around the expected moment."""
    start = time.perf_counter()
    next_check = start + CHECK_EVERY_S
    n = 0
    while not ready():
        n += 1
        if n & 255:
            continue
        now = time.perf_counter()
        if not spin_from_s <= now - start <= spin_from_s + spin_s:
            time.sleep(nap_s)
        if now > next_check:
            next_check = now + CHECK_EVERY_S
            on_idle()


def pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by someone else
        return True
    return True
