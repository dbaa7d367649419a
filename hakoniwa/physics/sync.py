"""The three ways physics and Athrill keep simulation time together, one loop each.

`lockstep` (our mock and native programs): Athrill's clock is its task's wake-up time and computation
takes no simulated time. At each `tslp_tsk` Athrill publishes its outputs and the time it will wake
(`Tx.NEXT_WAKE`), then waits; physics steps to exactly that instant, publishes the sensor snapshot with
the unity time set to it, and waits for the next answer. Each side sleeps on the word the other changes
(`hakoniwa.wire.waiting.wait_word`) and is woken by it. At every handshake the time difference is 0, so
the same parameters give the same event and goal time to the microsecond under any machine load.

`hakoniwa` (the real TOPPERS Athrill): the real protocol. Athrill never blocks: it reads the unity time
(RX header 16), writes its own clock (TX header 8), and only refuses to skip idle cycles past the unity
time. Physics steps while `athrill_time - world_time > -ALLOWED_TIME_DIFF_US`, in whole 1 ms steps that
never take it more than the allowed 20 ms ahead, and then publishes its time; results depend on how fast
the emulator runs, as with the real Unity. Over UDP (athrill2's `vdev_udp`) the loop is the same: the
transport (`hakoniwa.physics.relay`) brings Athrill's packets into the TX file when the loop receives, and
sends each published snapshot as a packet.

`repeatable` (the real TOPPERS Athrill built with scripts/athrill-patches, its wait turned on by the device
config): Athrill stops only where the program could observe physics, at a load or store of the mapped files at a
clock at or past the end of the published snapshot (`snapshot_end_us`, one step after it), or at a clock that
reaches the unity time (the horizon, `REPEATABLE_HORIZON_US` ahead: a program that never touches the files
still lets the test's time run). Two loads never stop, as what they read cannot depend on where physics is: the
buttons before the scenario's next press or release (`Rx.BUTTONS_UNTIL`), and TX bytes that hold 0 (physics
writes nothing there but the zeros that take a reset request). Stopped, Athrill publishes its clock
(`Tx.STOPPED_AT`) and sleeps until the bound passes it. Physics waits for that stop, applies the actuators
Athrill wrote if they changed (so that a command draws its motor noise once, as a lockstep answer does, not once
a step), steps to the 1 ms step Athrill's clock is in and publishes that step's snapshot. A program's accesses in
[t, t + 1 ms) read the snapshot of t and its commands drive the step from t, exactly as when Athrill stopped at
every step, while the steps it cannot observe cost no round trip. Athrill's clock is a count of emulated cycles,
so where it stops and which cycle reads which snapshot depend on nothing but the image and its inputs: the same
image, parameters and noise draw give the same result to the microsecond under any load. The time difference
noted is how old the snapshot is that Athrill reads: under one step.

All three leave the test when the physics server raises an event, and raise `AthrillCrash` when Athrill
dies, goes silent or breaks the protocol. What they need of the server is `SyncServer`, and all they read of
Athrill they read through `Slots`.
"""

from __future__ import annotations

import signal
import subprocess
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

from hakoniwa.wire.processes import CpuUse, cpu_use, describe_exit, take_bench_fault
from hakoniwa.wire.protocol import BenchCause, CrashKind, SyncMode
from hakoniwa.wire.timebase import ALLOWED_TIME_DIFF_US, PHYSICS_STEP_US, Scheduler
from hakoniwa.wire.waiting import wait_word

if TYPE_CHECKING:
    from hakoniwa.physics.relay import Transport
    from hakoniwa.physics.slots import Slots

HAKONIWA_START_US = 1  # the real Unity's clock starts at 1 us: a unity time of 0 lets Athrill run unchecked
REPEATABLE_HORIZON_US = 1_000_000  # how far a patched Athrill may run without touching the files: one stop a
# simulated second lets a program that never does so have its test's time pass
SPINNING_CPU_SHARE = 0.1  # a silent Athrill that had this share of a core or more was running: the program spins


class SyncServer(Protocol):
    """What a sync loop needs of the physics server (`hakoniwa.physics.server.PhysicsServer`): the test's
    clock and its steps, the files and their transport, and the watchdog's limits. Nothing else of the server
    is the loops' business, so a loop can be read, and driven in a test, against these alone."""

    @property
    def slots(self) -> Slots: ...
    @property
    def transport(self) -> Transport: ...
    @property
    def scheduler(self) -> Scheduler: ...
    @property
    def now_us(self) -> int: ...
    @property
    def run_dir(self) -> Path: ...
    @property
    def athrill_timeout_s(self) -> float: ...
    @property
    def answer_before_start(self) -> int:
        """Athrill's answer counter before this test (`Slots.begin`): the first answer is the next one."""
        ...

    def advance_to(self, target_us: int) -> bool:
        """Step the test to `target_us` through every tick due on the way; True once it has an event (it
        stops at the tick that raised it)."""
        ...

    def check_ceiling(self) -> None:
        """Raise `AthrillCrash` (a bench fault) once the test is past its wall-clock ceiling."""
        ...

    def note_time_diff(self, diff_us: int) -> None: ...
    def publish_sensors(self) -> None: ...
    def apply_actuators(self) -> None: ...


class AthrillCrash(Exception):
    """The test ends as CRASH; `kind` says whose fault it may be, `detail` the exit status or -signal."""

    def __init__(self, kind: CrashKind, detail: int, message: str, cause: BenchCause = BenchCause.NONE) -> None:
        super().__init__(message)
        self.kind = kind
        self.detail = detail
        self.cause = cause  # what spoiled the test, for a BENCH crash


def exit_crash(proc: subprocess.Popen, *, started: bool, run_dir: Path) -> AthrillCrash:
    """The crash an exited Athrill stands for. One that marked a bench fault (`hakoniwa.wire.processes`), that
    exited before it got going (before it opened the files), or that was killed by SIGKILL is the bench's
    fault; one killed by another signal, or that exited once running, whatever its status, is the program's.
    SIGKILL is what the OOM killer and `kill -9` send, and no program crash raises it (a wild pointer is
    SIGSEGV, an abort SIGABRT), so a test it ends says nothing of the parameters: the campaign runs it again,
    and stops with one line when they come in a row (`testctl.campaign.loop.MAX_BENCH_FAULTS_IN_A_ROW`)."""
    code = proc.returncode
    assert code is not None
    reason = take_bench_fault(run_dir, proc.pid)
    if reason is not None:
        return AthrillCrash(CrashKind.BENCH, code, f"athrill {describe_exit(code)}: {reason}",
                            BenchCause.ATHRILL_FAILED)
    if code == -signal.SIGKILL:
        return AthrillCrash(CrashKind.BENCH, code, f"athrill {describe_exit(code)}, from outside the program (the "
                            "OOM killer, or kill -9)", BenchCause.ATHRILL_KILLED)
    if code > 0 and not started:
        return AthrillCrash(CrashKind.BENCH, code, f"athrill {describe_exit(code)}", BenchCause.ATHRILL_FAILED)
    return AthrillCrash(CrashKind.PROGRAM, code, f"athrill {describe_exit(code)}")


def watchdog(server: SyncServer, proc: subprocess.Popen, progress: Callable[[], int],
             started: Callable[[], bool], *, emulator: bool = False) -> Callable[[], None]:
    """An `on_idle` check for waits on Athrill: raises when it exits, when the test is past its wall-clock
    ceiling (`PhysicsServer.check_ceiling`), or when `progress()` (its clock or its answer counter) has not
    moved for the Athrill timeout of wall time. Whose fault the silence is, its CPU time says: a program that
    spins without sleeping uses the CPU it gets (the program's fault); a process that was stopped (SIGSTOP),
    or was runnable and got next to no CPU, was stalled by the machine (the bench's fault: the test runs
    again, never scored). One that sleeps in the kernel outside the handshake hangs on its own. The real
    emulator (`emulator`) is different: its clock counts the cycles it runs, so no program can stop it, and a
    clock that stands still is the emulator's own stall, the bench's."""
    timeout_s, run_dir = server.athrill_timeout_s, server.run_dir
    last_progress, since = progress(), time.monotonic()
    use = cpu_use(proc.pid)
    cpu_at, stopped = (use.cpu_s if use else 0.0), False

    def check() -> None:
        nonlocal last_progress, since, cpu_at, stopped
        if proc.poll() is not None:
            raise exit_crash(proc, started=started(), run_dir=run_dir)
        server.check_ceiling()
        now, seen, use = time.monotonic(), progress(), cpu_use(proc.pid)
        stopped = stopped or (use is not None and use.state in "Tt")
        if seen != last_progress:
            last_progress, since, cpu_at, stopped = seen, now, (use.cpu_s if use else 0.0), False
        elif now - since > timeout_s:
            raise silent_crash(now - since, use, cpu_at, stopped, emulator)

    return check


def silent_crash(silent_s: float, use: CpuUse | None, cpu_at: float, stopped: bool,
                 emulator: bool = False) -> AthrillCrash:
    if use is None:  # no /proc: the silence cannot be told apart, and is charged to the program as before
        return AthrillCrash(CrashKind.SILENT, 0, f"athrill silent for {silent_s:.0f} s")
    used = use.cpu_s - cpu_at
    had = f"{used:.1f} s of CPU in {silent_s:.0f} s"
    if stopped:
        return AthrillCrash(CrashKind.BENCH, 0, f"athrill was stopped ({had}): a stall of the machine",
                            BenchCause.ATHRILL_STALLED)
    if emulator:
        return AthrillCrash(CrashKind.BENCH, 0, f"the emulator's clock did not move for {silent_s:.0f} s ({had})",
                            BenchCause.TIME_STALLED)
    if used >= SPINNING_CPU_SHARE * silent_s:
        return AthrillCrash(CrashKind.SILENT, 0, f"athrill silent for {silent_s:.0f} s while running ({had}): "
                                                 "the program does not sleep")
    if use.state in "RD":
        return AthrillCrash(CrashKind.BENCH, 0, f"athrill got no CPU ({had}, state {use.state}): a stall of "
                                                "the machine", BenchCause.ATHRILL_STALLED)
    return AthrillCrash(CrashKind.SILENT, 0, f"athrill silent for {silent_s:.0f} s, blocked outside tslp_tsk")


def run_lockstep(server: SyncServer, proc: subprocess.Popen) -> None:
    slots = server.slots
    answer = slots.answer_seq
    # One watchdog for the test, not one per answer (each reads /proc): it runs only in waits that last, and
    # the answers that came since its last run are the progress it sees.
    check = watchdog(server, proc, answer, lambda: slots.athrill_pid() == proc.pid)
    catches_up = not server.transport.reads_files  # a program that reads the files is answered every step

    def await_answer(last: int) -> int:
        """Wait for Athrill's answer to the snapshot at `server.now_us`; apply it and return its wake time."""
        wait_word(slots.answer_address, answer, lambda: answer() != last, check)
        next_wake, athrill_us = slots.next_wake_us(), slots.athrill_time_us()
        answered_at = athrill_us - athrill_us % PHYSICS_STEP_US
        if catches_up and answered_at > server.now_us:
            # asp moved on without us, where nothing it reads could change (asp_time.c): its answer, and what
            # it sent the hub, are of the step it answered in
            if server.advance_to(answered_at):
                return next_wake  # the test ended on the way: the loop stops at once
        now = server.now_us
        diff = athrill_us - now
        server.note_time_diff(diff)
        if abs(diff) > ALLOWED_TIME_DIFF_US:
            raise AthrillCrash(CrashKind.PROTOCOL, 0, f"athrill time {athrill_us} us, physics {now} us")
        if next_wake <= now:
            raise AthrillCrash(CrashKind.PROTOCOL, 0, f"athrill wakes at {next_wake} us, physics is at {now} us")
        server.apply_actuators()
        return next_wake

    next_wake = await_answer(server.answer_before_start)
    while not server.advance_to(next_wake):
        server.check_ceiling()  # a program that answers, ever more slowly, is never silent
        last = answer()
        server.publish_sensors()
        next_wake = await_answer(last)


def run_hakoniwa(server: SyncServer, proc: subprocess.Popen) -> None:
    clock = server.slots.athrill_time_us
    link = server.transport  # over UDP, what Athrill sent reaches the TX file when the loop receives it
    check = watchdog(server, proc, clock, lambda: clock() > 0, emulator=True)
    sched = server.scheduler
    while True:
        link.receive()
        now = server.now_us
        # Whole steps that keep physics at most the allowed difference ahead of Athrill's clock.
        steps = (clock() + ALLOWED_TIME_DIFF_US - now) // PHYSICS_STEP_US
        if steps <= 0:
            link.wait_for(lambda: clock() + ALLOWED_TIME_DIFF_US - server.now_us >= PHYSICS_STEP_US, check)
            continue
        server.note_time_diff(clock() - now)
        server.apply_actuators()
        if server.advance_to(min(sched.next_tick(), now + steps * PHYSICS_STEP_US)):
            return
        server.publish_sensors()
        server.note_time_diff(clock() - server.now_us)
        check()


def run_repeatable(server: SyncServer, proc: subprocess.Popen) -> None:
    slots = server.slots
    stopped = slots.stopped_at_us
    check = watchdog(server, proc, slots.athrill_time_us, lambda: slots.athrill_time_us() > 0, emulator=True)
    applied = None  # the TX commands last applied: a command is applied (and draws its noise) once, when new
    while True:
        end = snapshot_end_us(server.now_us)  # published with the last snapshot
        # B023: the end is waited on in this turn only
        wait_word(slots.stopped_address, slots.stopped_word, lambda: stopped() >= end, check)  # noqa: B023
        at = stopped()
        if slots.command_words() != applied:
            server.apply_actuators()
            applied = slots.command_words()  # after the reset requests it took were cleared
        reached = at - at % PHYSICS_STEP_US  # the step Athrill's clock is in: the snapshot it must read
        if server.advance_to(reached):  # through the ticks due on the way, as every step in between
            return
        server.note_time_diff(at - server.now_us)  # how old the snapshot it reads is
        server.check_ceiling()
        server.publish_sensors()


def unity_time_us(sync: SyncMode, now_us: int) -> int:
    """The unity time published with the snapshot for `now_us`: how far Athrill may run on it. The real
    Unity's clock starts at 1 us (a unity time of 0 lets an unpatched Athrill run unchecked); the repeatable
    mode lets a patched Athrill run up to its horizon as long as it does not touch the files."""
    if sync == SyncMode.REPEATABLE:
        return now_us + REPEATABLE_HORIZON_US
    return max(now_us, HAKONIWA_START_US) if sync == SyncMode.HAKONIWA else now_us


def snapshot_end_us(now_us: int) -> int:
    """The instant up to which the snapshot for `now_us` holds: the next one physics steps to. A patched Athrill
    that loads or stores at or past it waits for the next snapshot (the repeatable mode)."""
    return now_us + PHYSICS_STEP_US


SYNC_LOOPS: dict[SyncMode, Callable[[SyncServer, subprocess.Popen], None]] = {
    SyncMode.LOCKSTEP: run_lockstep, SyncMode.HAKONIWA: run_hakoniwa, SyncMode.REPEATABLE: run_repeatable}
