"""The real TOPPERS athrill2 in the repeatable mode (built with scripts/athrill-patches): the same image,
parameters and noise draw give the same result to the microsecond on every run, loaded machine or not; and the
images and emulators that cannot run are one line before any test."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from athrill_sim.programs.athrill2 import SYNC_WAIT_KEY
from athrill_sim.programs.third_party import EV3RT_SAMPLE_IMAGE
from hakoniwa.wire.timebase import ALLOWED_TIME_DIFF_US
from testctl.campaign.journal import JOURNAL_FILE, read_journal
from tests.helpers.athrill_fixtures import ASP_IMAGE
from tests.helpers.commands import hako, one_line_error
from tests.helpers.paths import needs_shared
from tests.helpers.realemu_fixtures import BASE_PRACTICE, need_v850_tools

BUSY = "while True: pass"
TRIAL = ("--kp", "2.5", "--ki", "0.5", "--kd", "3", "--seed", "11", "--noise", "1", "--time-limit", "6", "--json")


def trial(run_dir: Path, *args: str) -> tuple[str, bytes]:
    out = hako("try", *args, *TRIAL, "--run-dir", str(run_dir), timeout=600)
    assert out.returncode == 0, out.stderr
    return out.stdout, (run_dir / "trajectory.csv").read_bytes()


@pytest.mark.slow
def test_the_same_image_and_noise_draw_repeat_exactly_under_load(base_practice_image, repeatable_athrill2, tmp_path):
    athrill2 = ("--athrill2", str(repeatable_athrill2))
    runs = [trial(tmp_path / "folder", "--app", str(BASE_PRACTICE), "--emulator", "athrill2", *athrill2),
            trial(tmp_path / "image", "--app", str(base_practice_image), *athrill2)]
    burners = [subprocess.Popen([sys.executable, "-c", BUSY]) for _ in range(2)]
    try:
        runs.append(trial(tmp_path / "loaded", "--app", str(base_practice_image), *athrill2))
    finally:
        for b in burners:
            b.kill()
            b.wait()
    assert all(r == runs[0] for r in runs), [r[0] for r in runs]
    result = json.loads(runs[0][0])
    assert result["sync"] == "repeatable" and result["event"] != "CRASH", result
    assert 0 < result["max_time_diff_us"] <= ALLOWED_TIME_DIFF_US and result["distance_m"] > 0.1, result


@pytest.mark.slow
def test_a_campaign_without_noise_tests_each_set_once_on_several_emulators(repeatable_athrill2, tmp_path):
    need_v850_tools()
    out = tmp_path / "campaign"
    r = hako("run", "--app", "line_trace_c", "--emulator", "athrill2", "--athrill2", str(repeatable_athrill2),
             "--noise", "0", "--optimizer", "random", "--init-points", "2", "--trials", "2", "--benches", "2",
             "--time-limit", "45", "--validate", "0", "--out", str(out), timeout=900)
    assert r.returncode == 0, r.stderr
    header, records = read_journal(out / JOURNAL_FILE)
    assert header["options"]["repeats"] == 1 and header["bench"]["sync"] is None
    assert sorted(rec.set_index for rec in records) == [0, 1, 2, 3]
    assert {rec.result.sync.name for rec in records} == {"REPEATABLE"}


def test_an_athrill2_that_exits_at_once_is_one_line(tmp_path):
    if not ASP_IMAGE.is_file():
        pytest.skip(needs_shared("the real EV3RT image", ASP_IMAGE, EV3RT_SAMPLE_IMAGE))
    fake = tmp_path / "athrill2"
    fake.write_text(f"#!/bin/sh\n# claims {SYNC_WAIT_KEY}\necho 'cannot map athrill_mmap.bin'\nexit 3\n")
    fake.chmod(0o755)
    one_line_error(hako("try", "--app", str(ASP_IMAGE), "--athrill2", str(fake), "--json", timeout=120),
                   "exited at once", "status 3", "cannot map")


def test_an_unpatched_athrill2_is_refused_for_the_repeatable_mode(tmp_path):
    if not ASP_IMAGE.is_file():
        pytest.skip(needs_shared("the real EV3RT image", ASP_IMAGE, EV3RT_SAMPLE_IMAGE))
    plain = tmp_path / "athrill2"
    plain.write_text("#!/bin/sh\nexit 0\n")
    plain.chmod(0o755)
    one_line_error(hako("try", "--app", str(ASP_IMAGE), "--athrill2", str(plain), "--json", timeout=120),
                   "repeatable-sync patch", "build_athrill2.sh --repeatable", "--sync hakoniwa")


@pytest.mark.slow
def test_an_image_that_never_touches_the_mapped_files_is_one_line(repeatable_athrill2, tmp_path):
    from athrill_sim.v850.toolchain import find_tools

    need_v850_tools()
    (tmp_path / "spin.c").write_text("void _start(void) { volatile int x = 0; for (;;) x++; }\n")
    image = tmp_path / "spin.elf"
    subprocess.run([str(find_tools().gcc), "-mv850e2v3", "-nostdlib", "-Wl,-Ttext=0,-e,0", "-O1", "-gdwarf-2", "-o",
                    str(image), str(tmp_path / "spin.c")], check=True, capture_output=True)
    one_line_error(hako("try", "--app", str(image), "--athrill2", str(repeatable_athrill2), "--json", timeout=300),
                   "wrote nothing to the mapped files")


@pytest.mark.slow
def test_a_gyro_reset_does_not_kill_the_patched_athrill2(repeatable_athrill2, tmp_path):
    """EV3RT's ev3_gyro_sensor_reset stores into the RX body; athrill2 without patch 02 dies of SIGSEGV."""
    need_v850_tools()
    (tmp_path / "app.c").write_text(
        '#include "ev3api.h"\n'
        "void main_task(intptr_t unused) {\n"
        "    ev3_motor_config(EV3_PORT_A, LARGE_MOTOR); ev3_motor_config(EV3_PORT_B, LARGE_MOTOR);\n"
        "    ev3_sensor_config(EV3_PORT_4, GYRO_SENSOR);\n"
        "    while (1) {\n"
        "        ev3_gyro_sensor_reset(EV3_PORT_4);\n"
        "        ev3_motor_set_power(EV3_PORT_A, 10);\n"
        "        ev3_motor_set_power(EV3_PORT_B, 10 + ev3_gyro_sensor_get_angle(EV3_PORT_4));\n"
        "        tslp_tsk(10000);\n"
        "    }\n"
        "}\n")
    out = hako("try", "--app", str(tmp_path), "--emulator", "athrill2", "--athrill2", str(repeatable_athrill2),
               "--time-limit", "2", "--noise", "0", "--json", timeout=900)
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout)
    assert result["event"] == "TIME_OVER" and result["distance_m"] > 0.05, result
