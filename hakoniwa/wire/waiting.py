"""Waiting on a peer across the mapped files, and checking that the peer is still there.

The lockstep's two handshakes per control period wait on a 32-bit word in a mapped file that the peer
changes: Athrill's `Tx.ANSWER_SEQ`, and the low word of the unity time in the RX header. The waiter sleeps on
that word in the kernel (a futex, which works across processes on a shared file mapping), and the peer, having
changed it, wakes it: no CPU is burned while waiting, which matters once several benches share the cores, and
a wake-up costs about 10 us here (30 us with every core busy). Napping, the alternative, costs 100+ us per
wake-up on a virtual machine, and spinning starves the very process being waited for once cores are scarce.
The data never leaves the files: the futex is only the doorbell.

Where the peer does not ring (the real athrill2 keeps no doorbell), or off Linux, waits poll: spin briefly,
then nap.
"""

from __future__ import annotations

import ctypes
import os
import platform
import sys
import time
from collections.abc import Callable

SPIN_S = 0.002  # polling: busy-wait this long before napping
NAP_S = 0.00005
CHECK_EVERY_S = 0.02  # how often `on_idle` runs while waiting

_SYS_FUTEX = {"x86_64": 202, "aarch64": 98}.get(platform.machine()) if sys.platform == "linux" else None
_FUTEX_WAIT, _FUTEX_WAKE = 0, 1
_WAKE_ALL = 0x7FFFFFFF


class _Timespec(ctypes.Structure):
    _fields_ = [("tv_sec", ctypes.c_long), ("tv_nsec", ctypes.c_long)]


_libc = ctypes.CDLL(None, use_errno=True) if _SYS_FUTEX is not None else None


def futex_wake(address: int) -> None:
    """Wake every process sleeping on the word at `address` (after changing it)."""
    if _libc is not None:
        _libc.syscall(_SYS_FUTEX, ctypes.c_void_p(address), _FUTEX_WAKE, _WAKE_ALL, None, None, 0)


def _futex_wait(address: int, expected: int, timeout_s: float) -> None:
    """Sleep while the word at `address` still holds `expected`, at most `timeout_s` (or until a signal)."""
    assert _libc is not None  # wait_word falls back to polling without it
    ts = _Timespec(int(timeout_s), int((timeout_s % 1) * 1e9))
    _libc.syscall(_SYS_FUTEX, ctypes.c_void_p(address), _FUTEX_WAIT, ctypes.c_uint32(expected), ctypes.byref(ts),
                  None, 0)


def wait_word(address: int, word: Callable[[], int], ready: Callable[[], bool],
              on_idle: Callable[[], None]) -> None:
    """Return once `ready()`; meanwhile sleep on the u32 word at `address` (whose value `word()` reads), which
    the peer changes and then wakes with `futex_wake`. `on_idle` runs every CHECK_EVERY_S and raises to give
    up. The futex compares before it sleeps, so a change made between the read and the sleep is not missed."""
    if _libc is None:
        return wait_for(ready, on_idle)
    next_check = time.monotonic() + CHECK_EVERY_S
    while not ready():
        expected = word()
        if ready():  # it changed before the read: sleeping on the new value would wait for nothing
            break
        _futex_wait(address, expected, CHECK_EVERY_S)
        now = time.monotonic()
        if now > next_check:
            next_check = now + CHECK_EVERY_S
            on_idle()


def wait_for(ready: Callable[[], bool], on_idle: Callable[[], None], *, spin_s: float = SPIN_S,
             nap_s: float = NAP_S) -> None:
    """Return once `ready()` is true, polling: spin for `spin_s`, then nap. `on_idle` runs every CHECK_EVERY_S
    and raises to give up."""
    start = time.perf_counter()
    next_check = start + CHECK_EVERY_S
    n = 0
    napping = False
    while not ready():
        if napping:
            time.sleep(nap_s)
        else:
            n += 1
            if n & 255:  # while spinning, read the clock only now and then: it costs more than `ready()`
                continue
        now = time.perf_counter()
        napping = now - start > spin_s
        if now > next_check:
            next_check = now + CHECK_EVERY_S
            on_idle()


def pid_alive(pid: int) -> bool:
    """Whether process `pid` still runs. A process that died but that its parent has not yet reaped (a
    zombie) still answers signals, so on Linux its state is read too."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by someone else
        return True
    try:
        with open(f"/proc/{pid}/stat", "rb") as f:
            return f.read().rsplit(b")", 1)[1].split()[0] not in (b"Z", b"X")
    except (OSError, IndexError):
        return True
