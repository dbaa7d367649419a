"""Where simulated time can stall, wall time bounds the wait: the image check and every test end with a word
naming what stalled, never a hang. The emulator is a stand-in for athrill2 (a script that opens the mapped
files as athrill2 does and then never lets its clock move), since a v850 image whose start-up blocks needs
the v850 toolchain; the physics side cannot tell the two apart."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hakoniwa.wire.wallclock import FACTOR, FLOOR_S, WallCeiling
from tests.helpers.commands import one_line_error

# athrill2's command line ends with the image; the image's name says how this stand-in behaves.
FAKE_ATHRILL2 = f'''#!{sys.executable}
import mmap, os, struct, sys
image = os.path.basename(sys.argv[-1])
files = [open(name, "r+b") for name in ("unity_mmap.bin", "athrill_mmap.bin")]
tx = mmap.mmap(files[1].fileno(), 8192)
if image.startswith("frozen"):  # EV3RT boots (its drivers write the TX body), then the clock stops
    struct.pack_into("<i", tx, 32, 0)
    struct.pack_into("<Q", tx, 8, 5000)
while True:  # "blocked": an initialization routine that never returns, before anything is written
    pass
'''


def v850_image(path: Path) -> Path:
    """The smallest file the bench takes for a v850 image: a 32-bit little-endian ELF header for EM_V850."""
    header = b"\x7fELF\x01\x01\x01" + bytes(9) + (2).to_bytes(2, "little") + (87).to_bytes(2, "little")
    path.write_bytes(header + (1).to_bytes(4, "little") + bytes(52 - len(header) - 4))
    return path


def fake_athrill2(tmp_path: Path) -> Path:
    exe = tmp_path / "athrill2"
    exe.write_text(FAKE_ATHRILL2)
    exe.chmod(0o755)
    return exe


def hako_trial(tmp_path: Path, image: str, *extra: str) -> tuple[subprocess.CompletedProcess, float]:
    started = time.monotonic()
    r = subprocess.run([sys.executable, "-m", "testctl.hako", "try", "--app", str(v850_image(tmp_path / image)),
                        "--athrill2", str(fake_athrill2(tmp_path)), "--sync", "hakoniwa", "--run-dir",
                        str(tmp_path / "run"), *extra], capture_output=True, text=True, timeout=120)
    return r, time.monotonic() - started


@pytest.mark.slow
def test_an_image_whose_start_up_blocks_fails_the_check_naming_the_stalled_clock(tmp_path):
    r, wall_s = hako_trial(tmp_path, "blocked.elf")
    one_line_error(r, "the emulator's clock did not move for 10 s", "its start-up blocks?")
    assert wall_s < 60  # not the 300 s it once waited


def test_a_test_whose_emulated_clock_stops_is_a_bench_fault_naming_it(tmp_path):
    r, wall_s = hako_trial(tmp_path, "frozen.elf", "--athrill-timeout", "2", "--json")
    assert r.returncode != 0 and "Traceback" not in r.stderr, r.stderr
    assert "the bench spoiled the test (bench (simulated time stalled))" in r.stderr
    result = json.loads(r.stdout)
    assert (result["event"], result["crash"], result["bench_cause"]) == ("CRASH", "bench", "time_stalled")
    assert "the emulator's clock did not move for 2 s" in (tmp_path / "run" / "physics.log").read_text()
    assert wall_s < 60


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def test_the_ceiling_follows_the_rate_measured_early_and_has_a_floor():
    clock = Clock()
    ceiling = WallCeiling(60_000_000, clock=clock)  # 60 simulated s to go
    clock.now += 2.0
    assert ceiling.exceeded(1_000_000) is None  # 0.5 sim-s per wall-s: 60 s would take 120 s; ceiling 10x that
    assert ceiling.ceiling_s == pytest.approx(FACTOR * 120)
    clock.now += FACTOR * 120 - 2.0 - 1
    assert ceiling.exceeded(30_000_000) is None
    clock.now += 2
    why = ceiling.exceeded(30_000_000)
    assert why is not None and "simulated time reached 30.00 of 60 s" in why and "past its ceiling of 1200 s" in why


def test_a_fast_machine_still_gets_the_floor_and_a_clock_that_never_moved_is_named():
    clock = Clock()
    fast = WallCeiling(60_000_000, clock=clock)
    clock.now += 2.0
    assert fast.exceeded(60_000_000) is None and fast.ceiling_s == FLOOR_S  # 30 sim-s per wall-s
    still = WallCeiling(60_000_000, clock=Clock())
    still._clock.now += FLOOR_S + 1  # type: ignore[attr-defined]
    assert still.exceeded(0) == f"simulated time did not move from 0 s in {FLOOR_S + 1:.0f} s of wall time"


BLOCKING_INIT_CFG = '''INCLUDE("app_common.cfg");
INCLUDE("tecsgen.cfg");

#include "app.h"
#include "ev3.h"

ATT_INI({ TA_NULL, 0, block_init });
CRE_TSK(MAIN_TASK, { TA_ACT, 0, main_task, TMIN_APP_TPRI + 1, STACK_SIZE, NULL });
'''
BLOCKING_INIT_C = '''#include "ev3api.h"
#include "app.h"

void block_init(intptr_t exinf)  /* never returns: the kernel never starts its tasks */
{
    volatile int forever = 1;
    while (forever) {
    }
}

void main_task(intptr_t unused)
{
    ev3_motor_config(EV3_PORT_A, LARGE_MOTOR);
    for (;;) {
        ev3_motor_set_power(EV3_PORT_A, 10);
        tslp_tsk(100 * 1000);
    }
}
'''


@pytest.mark.slow
def test_a_real_image_whose_initialization_blocks_is_refused_before_any_test(tmp_path, athrill2):
    """The real athrill2 on a real image with an ATT_INI routine that never returns: its clock runs (it counts
    the busy loop's cycles) and the program writes nothing, which the image check says in one line."""
    from tests.helpers.commands import hako
    from tests.helpers.realemu_fixtures import BASE_PRACTICE, need_v850_tools

    need_v850_tools()
    app = tmp_path / "blocking_init"
    app.mkdir()
    (app / "app.cfg").write_text(BLOCKING_INIT_CFG)
    (app / "app.c").write_text(BLOCKING_INIT_C)
    (app / "Makefile.inc").write_text((BASE_PRACTICE / "Makefile.inc").read_text())
    header = (BASE_PRACTICE / "app.h").read_text(errors="replace")
    declaration = "extern void\tmain_task(intptr_t exinf);"
    assert declaration in header
    (app / "app.h").write_text(header.replace(declaration, declaration + "\nextern void\tblock_init(intptr_t exinf);"))
    built = hako("build", str(app), timeout=900)
    assert built.returncode == 0, built.stderr
    started = time.monotonic()
    r = hako("try", "--app", built.stdout.strip(), "--athrill2", str(athrill2), "--sync", "hakoniwa",
             "--run-dir", str(tmp_path / "run"), timeout=300)
    one_line_error(r, "the program wrote nothing to the mapped files")
    assert time.monotonic() - started < 60
