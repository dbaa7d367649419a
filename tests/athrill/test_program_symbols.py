"""A program's own names win over the native runtime's C library functions, as they win over the C library's on
the robot, where those are in a shared library (docs/DESIGN-NOTES.md, "A program's own names"): ET Robocon's
tutorial declares `Clock clock;` beside main_task, and teams name globals `time` or `open`. The runtime's
simulated clock still serves every other caller: the program's other files, and libstdc++'s chrono and sleeps.
Expected times follow from the documented rules (a relative wait counts from its tick in whole steps, the
first clock read at a tick reads the tick), as in test_posix_runtime.py."""

from __future__ import annotations

import re

import pytest

from athrill_sim.native.build import build_app
from hakoniwa.wire.timebase import PHYSICS_STEP_US
from tests.helpers.native_fixtures import FakePhysics, build, finish, need_cc
from tests.helpers.paths import PROGRAMS

STEP = PHYSICS_STEP_US
NAMES = ("clock", "time", "sleep", "signal", "open", "system")  # each a C library function the runtime defines
# A file of the program that includes no header, as a team's file of globals would, for it to define them.
GLOBALS = "".join(f"int {name} = {i};\n" for i, name in enumerate(NAMES, 1)) + \
    'EXTERN int globals(void) { return ' + " + ".join(f"{name} * {10 ** (5 - i)}" for i, name in enumerate(NAMES)) + \
    "; }\n"
CFG = """#include "app.h"
CRE_TSK(MAIN_TASK, { TA_ACT, 0, main_task, TMIN_APP_TPRI + 1, 4096, NULL });
"""
C_MAIN = r"""#include <stdio.h>
#include <time.h>
#include <unistd.h>
#include "app.h"
int globals(void);
void main_task(intptr_t unused) {
    printf("= %d\n", globals());
    usleep(2500);
    struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t);
    printf("= %lld\n", t.tv_sec * 1000000LL + t.tv_nsec / 1000);
    slp_tsk();
}
"""
CXX_MAIN = r"""#include <chrono>
#include <cstdio>
#include <thread>
#include "app.h"
extern "C" int globals(void);
void main_task(intptr_t unused) {
    std::printf("= %d\n", globals());
    std::this_thread::sleep_for(std::chrono::microseconds(2500));
    auto now = std::chrono::steady_clock::now().time_since_epoch();
    std::printf("= %lld\n", (long long)std::chrono::duration_cast<std::chrono::microseconds>(now).count());
    slp_tsk();
}
"""
APP_H = """#ifdef __cplusplus
extern "C" {
#endif
#include "ev3api.h"
void main_task(intptr_t exinf);
#ifdef __cplusplus
}
#endif
"""


@pytest.mark.parametrize("cxx", [False, True], ids=["C", "C++"])
def test_a_programs_globals_named_as_c_library_functions_win_and_the_clock_serves_the_rest(tmp_path, cxx):
    folder = tmp_path / "app"
    folder.mkdir()
    suffix = ".cpp" if cxx else ".c"
    (folder / "app.h").write_text(APP_H)
    (folder / f"globals{suffix}").write_text(GLOBALS.replace("EXTERN", 'extern "C"' if cxx else ""))
    (folder / "Makefile.inc").write_text("SRCLANG := c++\nAPPL_CXXOBJS += globals.o\n" if cxx
                                         else "APPL_COBJS += globals.o\n")
    exe = build(folder, CXX_MAIN if cxx else C_MAIN, CFG, name=f"app{suffix}")
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    wakes = bench.wakes(proc, 3 * STEP)
    log = finish(proc, stdout=True)
    assert [line[2:] for line in log.splitlines() if line.startswith("= ")] == ["123456", str(3 * STEP)], log
    assert wakes[0] == 3 * STEP  # 2.5 ms from tick 0, in whole steps: the runtime's sleep, on simulated time


def test_the_tutorials_clock_global_builds_and_keeps_simulated_time(tmp_path):
    """tests/programs/etrobo_tutorial: `Tracer tracer; Clock clock;` in app.cpp, libcpp-ev3's Clock, a cyclic
    tracer every 4 ms while main_task sleeps five times 100 ms on it."""
    need_cc()
    exe = build_app(PROGRAMS / "etrobo_tutorial")
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    bench.wakes(proc, 600_000)
    log = finish(proc, stdout=True)
    ends = re.search(r"main_task ends at (\d+) us", log)
    steps = re.search(r"Stopped after (\d+) steps", log)
    assert ends and steps, log
    assert abs(int(ends[1]) - 5 * 100_000) < STEP  # five sleeps of 100 ms; each clock read takes a microsecond
    assert int(steps[1]) == 5 * 100_000 // 4_000  # from sta_cyc (its first at once) to stp_cyc
