"""The Basic class: programs built in SPIKE-RT's own SDK for the hub (spike-rt-hub/sdk), natively and unmodified:
an `app.cdl`, an `app.cfg` that includes `tecsgen.cfg`, `kernel_cfg.h`, `sil.h`, `syssvc/syslog.h`, SPIKE-RT's
C++ classes (`libcpp/spike/*.h`) and cyclic handlers that activate a task (TNFY_ACTTSK). SPIKE-RT's own
`sample_c5` and `sample_cpp5` (tests/programs/spike_rt, copied unchanged) and our look-alike of a team's program
(tests/programs/basic_team_tracer) run on the Basic class's robot, `--robot basic`."""

from __future__ import annotations

import csv
import json
import math
import shutil
from pathlib import Path

import pytest

from athrill_sim.native import spike
from athrill_sim.native.workspace import find_app
from hakoniwa.physics.course import load_course
from hakoniwa.physics.robots import BUILT_IN
from tests.athrill.test_ev3rt_corpus import declarations
from tests.helpers.commands import hako
from tests.helpers.native_fixtures import FakePhysics, build, finish, need_cc
from tests.helpers.paths import DOCS, PROGRAMS
from tests.helpers.raspike_sdk import NEEDS_SPIKE_RT, SPIKE_RT

SAMPLES = PROGRAMS / "spike_rt"
SAMPLE_NAMES = ("sample_c5", "sample_cpp5")
TEAM = PROGRAMS / "basic_team_tracer"
LANES = ("etrobocon-l", "etrobocon-r")
PRESS_FORCE = DOCS / "examples" / "press-force.toml"

# A Basic-class program's files as SPIKE-RT's SDK lays them out (sdk/workspace/sample_c5: app.cfg, app.h), its
# first include the one a team's 2026 program failed at (syssvc/syslog.h).
HUB_CFG = """INCLUDE("tecsgen.cfg");
#include "app.h"
CRE_TSK(MAIN_TASK, { TA_ACT, 0, main_task, 5, 4096, NULL });
CRE_TSK(TRACER_TASK, { TA_NULL, 0, tracer_task, 6, 4096, NULL });
CRE_CYC(TRACER_CYC, { TA_NULL, { TNFY_ACTTSK, TRACER_TASK }, 10 * 1000, 0 });
"""
HUB_H = """#include <kernel.h>
#ifndef TOPPERS_MACRO_ONLY
void main_task(intptr_t exinf);
void tracer_task(intptr_t exinf);
#endif
"""
HUB_APP = r"""
#include <syssvc/syslog.h>
#include "kernel_cfg.h"
#include "app.h"
#include <sil.h>
#include <spike/pup/motor.h>
#ifdef USE_RASPIKE_ART
#error "the hub's SDK does not define USE_RASPIKE_ART"
#endif
static int runs;
void tracer_task(intptr_t exinf)
{
    SYSTIM now;
    get_tim(&now);
    syslog(LOG_NOTICE, "run %d at %d us", ++runs, (int)now);
    ext_tsk();
}
void main_task(intptr_t exinf)
{
    syslog(LOG_DEBUG, "debug before the mask");
    syslog_msk_log(LOG_UPTO(LOG_INFO), LOG_UPTO(LOG_EMERG));
    syslog(LOG_DEBUG, "debug after the mask");
    syslog(LOG_INFO, "info after the mask");
    dly_tsk(20 * 1000);
    sta_cyc(TRACER_CYC);
    ext_tsk();
}
"""


def hub_program(folder: Path, source: str = HUB_APP) -> Path:
    folder.mkdir(parents=True)
    (folder / "app.h").write_text(HUB_H)
    (folder / "app.cdl").write_text('import(<kernel.cdl>);\nimport("syssvc/tSysLog.cdl");\n')
    return build(folder, source, HUB_CFG)


def test_a_basic_class_program_builds_and_its_cyclic_handler_activates_its_task(tmp_path):
    """sta_cyc at 20 ms: ASP3's cyclic handler (phase 0) activates the task at once and every period after; the
    log mask is ASP3's tSysLog's (syssvc/tSysLog.c, tSysLog_eSysLog_write: a line is kept if its priority is
    in the log mask, printed if in the low mask)."""
    exe = hub_program(tmp_path / "app")
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    bench.wakes(proc, 60_000)
    log = finish(proc)
    runs = [line.split("] ", 1)[1] for line in log.splitlines() if "] run " in line]
    assert runs == [f"run {i + 1} at {20_000 + 10_000 * i} us" for i in range(5)]
    assert "debug before the mask" in log and "info after the mask" in log
    assert "debug after the mask" not in log


def test_a_hub_program_is_told_by_its_app_cdl_or_its_libcpp_include(tmp_path):
    """SPIKE-RT's samples hold an app.cdl; its sample00 has none, but includes <libcpp/spike/Motor.h>. A hub
    program is a SPIKE program without USE_RASPIKE_ART; a RasPike-ART program keeps it."""
    need_cc()
    for name in SAMPLE_NAMES:
        app = find_app(SAMPLES / name)
        assert (app.hub, app.spike, app.defines) == (True, True, ())
    team = find_app(TEAM)
    assert (team.hub, team.cxx) == (True, True)
    (tmp_path / "lone").mkdir()
    lone = tmp_path / "lone" / "app.cpp"
    lone.write_text("#include <libcpp/spike/Motor.h>\n")
    assert find_app(lone).hub
    art = find_app(PROGRAMS / "etrobo_spike_cpp")
    assert (art.hub, art.spike, art.defines[:1]) == (False, True, spike.DEFINES)


LIBCPP_APP = r"""
#include "app.h"
#include <libcpp/libcpp.h>
#include <libcpp/spike/Button.h>
#include <libcpp/spike/Clock.h>
#include <libcpp/spike/ColorSensor.h>
#include <libcpp/spike/Display.h>
#include <libcpp/spike/ForceSensor.h>
#include <libcpp/spike/IMU.h>
#include <libcpp/spike/Light.h>
#include <libcpp/spike/UltrasonicSensor.h>
#include "Motor.h"  // app.mk's -I$(DRIVERS_DIR)/include/libcpp/spike, for a C++ program
#include <syssvc/syslog.h>
using namespace spikeapi;
static Motor left(EPort::PORT_B, Motor::EDirection::COUNTERCLOCKWISE);  // built before the first task
void main_task(intptr_t exinf)
{
    libcpp_sync();
    Clock clock;
    IMU imu;
    IMU::AngularVelocity w;
    imu.getAngularVelocity(w);
    ColorSensor color(EPort::PORT_E);
    ForceSensor force(EPort::PORT_D);
    UltrasonicSensor sonar(EPort::PORT_F);
    Light().turnOnColor(Light::EColor::GREEN);
    Display().showNumber(7);
    clock.sleep(30 * 1000);
    syslog(LOG_NOTICE, "ready %d error %d button %d at %d ms", (int)imu.isReady(), (int)left.hasError(),
           (int)Button().isCenterPressed(), (int)(clock.now() / 1000));
    ext_tsk();
}
void tracer_task(intptr_t exinf) {}
"""


def test_spike_rts_cpp_classes_build_and_run(tmp_path):
    """Every libcpp/spike class of the Basic class's list (the hub SDK's app.mk puts its folders on the include
    path of a C++ program), a global object among them, and libcpp_sync() (libcpp/libcpp.h), which returns at
    once natively."""
    if shutil.which("g++") is None:
        pytest.skip("needs a C++ compiler (g++)")
    folder = tmp_path / "app"
    (folder).mkdir()
    (folder / "Makefile.inc").write_text("SRCLANG := c++\n")
    (folder / "app.h").write_text('#ifdef __cplusplus\nextern "C" {\n#endif\n' + HUB_H
                                  + '#ifdef __cplusplus\n}\n#endif\n')
    exe = build(folder, LIBCPP_APP, HUB_CFG, name="app.cpp")
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    bench.wakes(proc, 50_000)
    log = finish(proc)
    assert "ready 1 error 0 button 0 at 30 ms" in log, log


@pytest.mark.parametrize("copy, original", [
    (Path("athrill_sim/native/sdk/spike-rt/include/libcpp"), Path("drivers/include/libcpp")),
    (Path("athrill_sim/native/sdk/spike-rt/libcpp/spike"), Path("drivers/libcpp/spike")),
    (Path("athrill_sim/native/sdk/spike-rt/LICENSE"), Path("LICENSE")),
    (SAMPLES.relative_to(PROGRAMS.parents[1]) / "sample_c5", Path("sdk/workspace/sample_c5")),
    (SAMPLES.relative_to(PROGRAMS.parents[1]) / "sample_cpp5", Path("sdk/workspace/sample_cpp5")),
    (SAMPLES.relative_to(PROGRAMS.parents[1]) / "LICENSE", Path("LICENSE")),
])
def test_the_copies_are_spike_rts_byte_for_byte(copy, original):
    if not SPIKE_RT.is_dir():
        pytest.skip(NEEDS_SPIKE_RT)
    copy = PROGRAMS.parents[1] / copy
    theirs = SPIKE_RT / original
    files = sorted(f.relative_to(theirs) for f in theirs.rglob("*") if f.is_file()) if theirs.is_dir() else [Path()]
    assert files == (sorted(f.relative_to(copy) for f in copy.rglob("*") if f.is_file()) if copy.is_dir()
                     else [Path()])
    assert all((copy / f).read_bytes() == (theirs / f).read_bytes() for f in files)


def test_our_headers_declare_every_function_of_spike_rts_on_the_hub():
    """The hub's own spike/pup/*.h and spike/hub/*.h (drivers/include/spike), which are libraspike-art's and
    more (the IMU's readiness, rest, tilt and heading): each with the hub's signature. Its hub/bluetooth.h, the
    hub's advertising, has no counterpart on the bench."""
    if not SPIKE_RT.is_dir():
        pytest.skip(NEEDS_SPIKE_RT)
    hub = SPIKE_RT / "drivers" / "include" / "spike"
    ours = spike.INCLUDE_DIRS[0] / "spike"
    headers = sorted([*hub.glob("pup/*.h"), *hub.glob("hub/*.h")])
    assert [h.relative_to(hub) for h in headers if not (ours / h.relative_to(hub)).is_file()] == \
        [Path("hub/bluetooth.h")]
    theirs, mine = {}, {}
    for header in headers:
        if (ours / header.relative_to(hub)).is_file():
            theirs.update(declarations(header.read_text()))
            mine.update(declarations((ours / header.relative_to(hub)).read_text()))
    assert "hub_imu_get_heading" in theirs
    assert {n: s for n, s in theirs.items() if mine.get(n) != s} == {}


def trial(run_dir: Path, app: Path, lane: str) -> dict:
    need_cc()
    r = hako("try", "--noise", "0", "--json", "--run-dir", str(run_dir), "--course", lane, "--app", str(app),
             "--robot", "basic", "--scenario", str(PRESS_FORCE), timeout=600)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def followed_m(run_dir: Path, lane: str) -> float:
    """How far the robot drove before its colour sensor first saw nothing but white for a second (the noise-free
    floor under the sensor, on the trajectory the run recorded): the length of line it traced."""
    course = load_course(lane)
    forward = BUILT_IN["basic"].body.color_sensor_forward
    with open(run_dir / "trajectory.csv") as f:
        rows = [(int(r["time_us"]), float(r["x"]), float(r["y"]), float(r["yaw"])) for r in csv.DictReader(f)]
    driven, white_since = 0.0, None
    for (_, x0, y0, _), (t, x, y, yaw) in zip(rows, rows[1:]):
        driven += math.hypot(x - x0, y - y0)
        white = course.reading_at(x + forward * math.cos(yaw), y + forward * math.sin(yaw)).reflect >= course.ev3.white
        white_since = (white_since or (t, driven)) if white else None
        if white_since and t - white_since[0] >= 1_000_000:
            return white_since[1]
    return driven


@pytest.mark.slow
@pytest.mark.parametrize("lane", LANES)
def test_spike_rts_samples_trace_the_line_on_the_basic_robot(tmp_path, lane):
    """SPIKE-RT's sample_c5 and sample_cpp5, as they are (LineTracer.h: white 80, black 10, power 60, steering
    0.4 per unit every 100 ms), start on the force sensor and trace the line's right edge up the first
    straight, round the first curve and along the blue section, through the first checkpoint, the C and the
    C++ sample along the same path; at the tight reverse curve into the loop their gentle steering loses it
    (LineTracer.h's other figures, 0.8 and 30, lap)."""
    runs = {name: tmp_path / name for name in SAMPLE_NAMES}
    results = {name: trial(run, SAMPLES / name, lane) for name, run in runs.items()}
    c5 = results["sample_c5"]
    assert c5["event"] != "CRASH" and c5["checkpoints"] >= 1
    assert followed_m(runs["sample_c5"], lane) > 3.0
    assert (runs["sample_c5"] / "trajectory.csv").read_bytes() == (runs["sample_cpp5"] / "trajectory.csv").read_bytes()
    for run in runs.values():
        log = (run / "athrill.log").read_text()
        assert "Press force sensor to start" in log and "Start Line Trace!!" in log


@pytest.mark.slow
@pytest.mark.parametrize("lane", LANES)
def test_a_basic_class_team_program_laps_on_the_basic_robot(tmp_path, lane):
    """Our look-alike: libcpp/spike objects built before the first task, a 10 ms cyclic handler activating its
    tracing task, syslog with the mask a team sets (its LOG_DEBUG lines kept out)."""
    result = trial(tmp_path / "run", TEAM, lane)
    assert (result["event"], result["checkpoints"]) == ("GOAL", 4)
    # Its base power 45 (LineTracer.h) drives the axle centre at most 45% of the body's top speed, over the lane's
    # 9.7 m of line: no lap is shorter.
    body = BUILT_IN["basic"].body
    assert 9.7 / (0.45 * body.max_wheel_speed * body.wheel_radius) < result["lap_time_s"] < 80
    log = (tmp_path / "run" / "athrill.log").read_text()
    assert "basic_team_tracer: press the force sensor" in log and "start at 700 ms" in log
    assert " mm at 10 s" in log and "ref error" not in log
