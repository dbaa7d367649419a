"""Native C programs on the real bench: the C Fig. 7 tracer against the Python one, the unmodified EV3RT sample
against the real emulator, campaigns, and crashes."""

import json
import random
import signal

import pytest

from athrill_sim.apps import C_BUILTIN
from athrill_sim.programs.third_party import EV3RT_SAMPLE_IMAGE
from hakoniwa.wire.protocol import CrashKind, Event
from testctl.campaign.journal import JOURNAL_FILE, PHASE_VALIDATION, read_journal
from testctl.paper import GAIN_RANGE, line_trace_params
from tests.helpers.athrill_fixtures import ASP_IMAGE, SHARED_ATHRILL
from tests.helpers.bench_fixtures import PAPER, physics
from tests.helpers.commands import hako
from tests.helpers.native_fixtures import need_cc
from tests.helpers.paths import needs_shared

BLE_SAMPLE = SHARED_ATHRILL / "ev3rt-ble_sample"


def trials(app: str, gain_sets: list[dict[int, float]], run_dir) -> list[tuple[Event, int]]:
    with physics(run_dir, app=app) as (_, runner):
        return [(r.event, r.goal_time_us) for r in map(runner.run_test, gain_sets)]


def test_the_c_tracer_and_the_python_tracer_finish_the_paper_lap_in_the_same_microsecond(tmp_path):
    need_cc()
    python = trials("line_trace", [PAPER], tmp_path / "python")
    native = trials("line_trace_c", [PAPER], tmp_path / "native")
    assert native == python and native[0][0] == Event.GOAL


@pytest.mark.slow
def test_the_c_tracer_and_the_python_tracer_agree_on_random_gains(tmp_path):
    need_cc()
    rng = random.Random(20240610)
    gain_sets = [line_trace_params(*(rng.uniform(*GAIN_RANGE) for _ in range(3))) for _ in range(20)]
    python = trials("line_trace", gain_sets, tmp_path / "python")
    native = trials("line_trace_c", gain_sets, tmp_path / "native")
    assert python == native, [(g, p, n) for g, p, n in zip(gain_sets, python, native) if p != n]
    assert len(set(python)) >= 10, python  # the sets drive differently (EV3RT's steer laps nearly every one)




def test_the_unmodified_ev3rt_sample_follows_the_line_natively(tmp_path):
    need_cc()
    if not BLE_SAMPLE.is_dir():
        pytest.skip(needs_shared("the EV3RT sample", BLE_SAMPLE, EV3RT_SAMPLE_IMAGE))
    out = hako("try", "--app", str(BLE_SAMPLE / "app.c"), "--json", "--run-dir", str(tmp_path))
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout)
    assert result["sync"] == "lockstep" and result["event"] == "TIME_OVER" and result["distance_m"] >= 0.5
    log = (tmp_path / "athrill.log").read_text()
    assert "#### motor control start 0" in log and "####serial_task UP" in log  # both tasks of app.cfg ran


@pytest.mark.slow
def test_the_ev3rt_sample_runs_natively_as_it_runs_in_the_real_emulator(athrill2, tmp_path):
    need_cc()
    # the unpatched athrill2, so TOPPERS' own protocol (the repeatable mode needs the patched one)
    real = hako("try", "--app", str(ASP_IMAGE), "--athrill2", str(athrill2), "--sync", "hakoniwa", "--json",
                "--run-dir", str(tmp_path / "real"))
    native = hako("try", "--app", str(BLE_SAMPLE), "--json", "--run-dir", str(tmp_path / "native"))
    assert real.returncode == 0 and native.returncode == 0, real.stderr + native.stderr
    real, native = json.loads(real.stdout), json.loads(native.stdout)
    assert native["event"] == real["event"]
    assert native["distance_m"] == pytest.approx(real["distance_m"], rel=0.25)


def campaign(tmp_path, app: str) -> list:
    out = tmp_path / "campaign"
    r = hako("run", "--app", app, "--smoke", "--out", str(out))
    assert r.returncode == 0, r.stderr
    _, records = read_journal(out / JOURNAL_FILE)
    return [r for r in records if r.phase != PHASE_VALIDATION]  # the search's tests


def test_a_campaign_runs_a_c_file(tmp_path):
    need_cc()
    records = campaign(tmp_path, str(C_BUILTIN["line_trace_c"]))
    assert len(records) == 4 and all(r.result.event != Event.CRASH for r in records)


@pytest.mark.slow
def test_a_campaign_runs_the_builtin_c_tracer(tmp_path):
    need_cc()
    records = campaign(tmp_path, "line_trace_c")
    assert len(records) == 4 and any(r.result.event == Event.GOAL for r in records)


CRASHING_APP = r'''
#include <stdlib.h>
#include "ev3api.h"

#define Kp (*(volatile float *)(0x090F0000 + 540))

void main_task(intptr_t unused)
{
    tslp_tsk(100000);
    if (Kp == 1)
        *(volatile int *)8 = 0;
    if (Kp == 2)
        abort();
    if (Kp == 3)
        syslog(LOG_NOTICE, "%d", *(volatile int *)(0x090F1000 + 0x1000));
    for (;;)
        tslp_tsk(100000);
}
'''


def test_a_crashing_program_is_a_crash_named_by_its_signal_and_the_bench_goes_on(tmp_path):
    need_cc()
    (tmp_path / "crash.c").write_text(CRASHING_APP)
    with physics(tmp_path / "run", app=str(tmp_path / "crash.c")) as (_, runner):
        results = [runner.run_test(line_trace_params(kp, 0, 0)) for kp in (1, 2, 3, 0)]
    segv, abort, outside, still = results
    for r, sig in ((segv, "SIGSEGV"), (abort, "SIGABRT"), (outside, "SIGSEGV")):
        assert r.event == Event.CRASH and r.crash_kind == CrashKind.PROGRAM
        assert sig in r.crash_reason()
    assert segv.crash_detail == -signal.SIGSEGV and abort.crash_detail == -signal.SIGABRT
    assert outside.crash_kind == CrashKind.PROGRAM  # a fault (SIGSEGV), not a hang until the Athrill timeout
    assert still.event == Event.TIME_OVER
