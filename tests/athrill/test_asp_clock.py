"""asp's clock library (athrill_sim/raspike_art/clock.py, athrill_sim/native/runtime/asp/asp_time.c): an aarch64
program that uses time as RasPike-ART's asp does runs under qemu-user on the bench's clock, in lockstep with a
physics side played over the real bench files (tests/helpers/native_fixtures.py's FakePhysics)."""

from __future__ import annotations

import shutil
import subprocess
import time
from functools import partial
from pathlib import Path

import pytest

from athrill_sim.raspike_art import AspError
from athrill_sim.raspike_art.build import CROSS_GCC
from athrill_sim.raspike_art.clock import LIBRARY, RUN_DIR_ENV, TEST_ENV, build_clock_library
from athrill_sim.raspike_art.launch import QEMU, SYSROOT
from hakoniwa.wire.protocol import Rx, Tx
from hakoniwa.wire.timebase import CALL_COST_US, PHYSICS_STEP_US
from tests.helpers.native_fixtures import FakePhysics

PROBE = Path(__file__).parent.parent / "programs" / "asp_clock_probe" / "probe.c"


@pytest.fixture(scope="module")
def probe(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The probe built for aarch64, and the clock library."""
    if shutil.which(CROSS_GCC) is None or shutil.which(QEMU) is None:
        pytest.skip(f"needs {CROSS_GCC} and {QEMU} (apt-get install gcc-aarch64-linux-gnu qemu-user)")
    try:
        library = build_clock_library()
    except AspError as e:
        pytest.fail(str(e))
    exe = tmp_path_factory.mktemp("asp-clock") / "probe"
    subprocess.run([CROSS_GCC, "-O2", "-o", str(exe), str(PROBE)], check=True, timeout=120)
    return exe, library


def start(exe: Path, library: Path, run_dir: Path, test: int | None = None) -> subprocess.Popen:
    env = ["-E", f"{RUN_DIR_ENV}={run_dir}"] + (["-E", f"{TEST_ENV}={test}"] if test is not None else [])
    return subprocess.Popen([str(shutil.which(QEMU)), "-L", str(SYSROOT), "-E", f"LD_PRELOAD={library}", *env,
                             str(exe)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def test_the_library_exports_only_the_calls_it_puts_on_simulated_time_or_the_baton(probe: tuple[Path, Path]) -> None:
    _, library = probe
    assert library.name == LIBRARY
    nm = shutil.which("aarch64-linux-gnu-nm") or pytest.skip("needs aarch64-linux-gnu-nm (binutils)")
    out = subprocess.run([nm, "-D", "--defined-only", str(library)], capture_output=True, text=True, check=True)
    names = {line.split()[-1] for line in out.stdout.splitlines()}
    assert names == {"clock_gettime", "gettimeofday", "time", "clock", "sleep", "usleep", "nanosleep",
                     "clock_nanosleep", "getitimer", "setitimer", "sigsuspend", "pthread_cond_timedwait",
                     "pthread_cond_wait", "pthread_cond_clockwait", "pthread_cond_signal", "pthread_cond_broadcast",
                     "pthread_mutex_lock", "pthread_create", "pthread_join", "open", "read", "write"}


def test_timer_clock_and_sleeps_follow_the_bench(probe: tuple[Path, Path], tmp_path: Path) -> None:
    exe, library = probe
    physics = FakePhysics(tmp_path / "run")
    proc = start(exe, library, physics.run_dir)
    try:
        s = 30_000_000  # probe.c's sleep(30): asp's main.c sleeps 1 s; 30 s is one no load would pass for
        tick = 10_000  # probe.c's one-shot, re-armed in its handler
        # main's sleep; five ticks of the sigsuspend idle, each at the step its time falls in; then the 3 ms
        # periodic timer during a 10 ms sleep
        expected_wakes = [s, *(s + tick * i for i in range(1, 6)), s + 5 * tick + 3_000, s + 5 * tick + 6_000,
                          s + 5 * tick + 9_000, s + 6 * tick]
        started = time.monotonic()
        for wake in expected_wakes:
            assert physics.next_wake(proc) == wake
            physics.answer(wake)
        out, err = proc.communicate(timeout=30)
        wall = time.monotonic() - started
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
        physics.close()
    assert proc.returncode == 0, err
    assert all(w % PHYSICS_STEP_US == 0 for w in expected_wakes)
    lines = out.splitlines()
    c = CALL_COST_US
    assert lines == [
        "start 0",  # the first read at a tick reads the tick (sim_time.h); each read then spends a call
        f"slept {s}",
        # each one-shot counts from the read before it: the handler's read, a call after it fell due
        *(f"tick {s + tick * i + c * i}" for i in range(1, 6)),
        f"left {tick}",  # stopped with nothing read since it was armed
        # the periodic timer reloads from its due time, not from the handler's read
        *(f"during {s + 5 * tick + 6 * c + 3_000 * i}" for i in range(1, 4)),
        f"woke {s + 6 * tick}",  # a sleep counts from the tick, in whole steps (posix_time.c)
        "unanswered ETIMEDOUT",  # a deadline of time(0) + 0 has passed: the clock is simulated, not the wall's
        "answered 0",  # the other thread's answer within the deadline of time(0) + 1
        # no simulated time passed waiting for it, only the calls: the read of "woke", then time(0) and the
        # wait, twice
        f"acked {s + 6 * tick + 5 * c}",
    ]
    assert wall < 30  # simulated time, not the wall's: 30.06 s of it passed


def test_it_waits_for_its_test_and_without_the_bench_it_says_so(probe: tuple[Path, Path], tmp_path: Path) -> None:
    exe, library = probe
    physics = FakePhysics(tmp_path / "run")
    proc = start(exe, library, physics.run_dir, test=3)
    try:
        time.sleep(0.5)
        assert physics.athrill.read_u32(Tx.ANSWER_SEQ) == 0 and proc.poll() is None  # waiting for test 3
        physics.unity.write_u32(Rx.TEST_SEQ, 3)
        assert physics.next_wake(proc) == 30_000_000  # then on: main's sleep(30)
    finally:
        proc.kill()
        proc.communicate()
        physics.close()
    bare = subprocess.run([str(shutil.which(QEMU)), "-L", str(SYSROOT), "-E", f"LD_PRELOAD={library}", str(exe)],
                          capture_output=True, text=True, timeout=60)
    assert bare.returncode != 0
    assert bare.stderr.strip().splitlines() == [
        f"athrill-native: bench fault: {RUN_DIR_ENV} is not set: asp's clock library runs only under the bench"]


def run_sample(asp: Path, library: Path, folder: Path) -> tuple[list[int], int | None]:
    """sample_c5_spike's asp with the clock library, its hub on a pty answered between the steps, as the
    physics side does (the program's counted bytes in, the hub's count out before the next unity time), until
    the motors turn; the wake-ups it published, and when the force sensor was pressed."""
    from athrill_sim.raspike_art.launch import asp_argv, prefix_folder
    from hakoniwa.physics.raspike_hub import Hub, PtyHub, SerialCounts
    from tests.physics.test_raspike_hub import KINDS, readings

    hub = PtyHub(Hub(KINDS))
    physics = FakePhysics(folder / "run")
    counts = SerialCounts(physics.run_dir)
    argv = asp_argv(asp, prefix_folder(folder / "prefix", hub.device), (library,),
                    ((RUN_DIR_ENV, str(physics.run_dir)),))
    proc = subprocess.Popen(argv, cwd=folder, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wakes: list[int] = []
    pressed_at = None
    try:
        while not wakes or wakes[-1] < 10_000_000:
            wakes.append(physics.next_wake(proc))
            if pressed_at is None and hub.hub.ports[3].configured:
                pressed_at = wakes[-1] + 500_000  # the program waits on the force sensor: press it later
            now = wakes[-1]
            pressed = pressed_at is not None and now >= pressed_at
            counts.publish(hub.exchange(partial(readings, hub.hub, pressed=pressed), now, counts.program_sent),
                           hub.next_status_us)
            physics.answer(now)
            if hub.hub.powers(4)[0] != (0, 0, 0, 0):
                break
    finally:
        proc.kill()
        proc.communicate()
        hub.close()
        counts.close()
        physics.close()
    assert hub.hub.powers(4) == ((64, -4, 0, 0), (0, 1, 0, 0)), "the motors never turned"
    return wakes, pressed_at


@pytest.mark.slow
def test_raspike_arts_own_sample_runs_on_the_bench_clock(probe: tuple[Path, Path], tmp_path: Path) -> None:
    """sample_c5_spike under the library: past main's sleep(1) and the force-sensor press it drives the motors
    by the reflection (LineTracer.c 52-79; tests/physics/test_raspike_hub.py works the numbers out), at the
    same simulated instants twice: the serial exchange is in the lockstep, not the wall's race (two runs reached
    the motors at 1.626 s and 2.560 s before it). How fast it runs is scripts/benchmark_sim.py's to say, not a
    test's."""
    from athrill_sim.programs.third_party import RASPIKE_ART
    from athrill_sim.raspike_art.build import DEFAULT_FOLDER, build_asp
    from tests.helpers.paths import needs_shared

    if not DEFAULT_FOLDER.is_dir():
        pytest.skip(needs_shared("RasPike-ART", DEFAULT_FOLDER, RASPIKE_ART))
    _, library = probe
    asp = build_asp(DEFAULT_FOLDER / "sdk" / "workspace" / "sample_c5_spike")
    wakes, pressed_at = run_sample(asp, library, tmp_path / "first")
    # the hub answers the handshake between steps, at the first; then main.c's sleep(1) before the kernel starts
    assert wakes[:2] == [PHYSICS_STEP_US, PHYSICS_STEP_US + 1_000_000]
    assert pressed_at is not None, "asp never configured the force sensor on D"
    assert wakes[-1] > pressed_at
    assert run_sample(asp, library, tmp_path / "second") == (wakes, pressed_at)


THREADS_PROBE = Path(__file__).parent.parent / "programs" / "asp_threads_probe" / "probe.c"


def run_threads_probe(library: Path, exe: Path, run_dir: Path) -> tuple[list[str], list[int]]:
    physics = FakePhysics(run_dir)
    proc = start(exe, library, physics.run_dir)
    try:
        wakes = physics.wakes(proc, until_us=100_000)  # its last sleep(1000), once the threads are joined
    finally:
        proc.kill()
        out, err = proc.communicate(timeout=30)
        physics.close()
    return out.splitlines(), wakes


def test_threads_a_task_starts_run_one_at_a_time_on_the_bench_clock(probe: tuple[Path, Path],
                                                                    tmp_path: Path) -> None:
    """The baton (asp_threads.c): a team's threads sleep on the simulated clock, counted from the tick in whole
    steps as the native runtime's (posix_time.c), a condition variable wakes its waiter, and at one instant they
    run in a fixed order: at 21 ms A and B both wake; A's sleep moved the bench there, and the baton goes from
    A on in the order they were started: B, then C (which B's signal woke), then A. The same twice."""
    _, library = probe
    exe = tmp_path / "threads"
    subprocess.run([CROSS_GCC, "-O2", "-o", str(exe), str(THREADS_PROBE)], check=True, timeout=120)
    lines, wakes = run_threads_probe(library, exe, tmp_path / "first")
    assert lines == ["A 3000", "A 6000", "B 7000", "A 9000", "A 12000", "B 14000", "A 15000", "A 18000", "B 21000",
                     "C 21000", "A 21000", "joined 21000"]
    # while C waits for a signal nothing has given yet the bench moves a step at a time: with no hub on a port
    # (asp_serial.c), asp's receiving thread might give it at any step; once B, a player, has signalled it
    # (7 ms), only a player can wake C, and the bench goes straight to the next sleep's end; once C is joined,
    # the main thread's sleep goes straight to its end
    assert wakes == [*range(1000, 8000, 1000), 9000, 12_000, 14_000, 15_000, 18_000, 21_000, 1_000_021_000]
    assert run_threads_probe(library, exe, tmp_path / "second") == (lines, wakes)
