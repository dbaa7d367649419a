"""The Fig. 7 tracer tuned as it is written: each of tests/programs/tracer_* (a #define, globals, a data file
on the SD card, constants in a header, constexpr constants of a C++ header) against the offset version,
campaign for campaign; best.patch applied to a copy; the patched program with no parameters at all; a
global's value exact to the bit, natively and in the real emulator, in C and C++ (qualified names); and the
ET Robocon-style C++ tracer tuned without an edit by hand."""

from __future__ import annotations

import json
import shutil
import struct
import subprocess
from functools import cache
from pathlib import Path

import pytest

from athrill_sim.tuning.forms.values import as_float32
from hakoniwa.wire.protocol import open_athrill
from testctl.bench import Bench
from testctl.bench_options import BenchOptions
from testctl.campaign.journal import JOURNAL_FILE, read_journal
from testctl.executor import TestSpec
from testctl.search.space import ParameterSpace
from tests.helpers.commands import hako
from tests.helpers.native_fixtures import need_cc
from tests.helpers.paths import PROGRAMS
from tests.helpers.realemu_fixtures import need_v850_tools

KINDS = ("define", "symbol", "file", "source", "constexpr")  # constexpr: a C++ header's, by source parameters
CAMPAIGN = ("--noise", "0", "--repeats", "1", "--seed", "0", "--init-points", "5", "--trials", "15",
            "--validate", "0")


def campaign(out: Path, *args: str) -> list[tuple]:
    r = hako("run", *args, *CAMPAIGN, "--out", str(out), timeout=1800)
    assert r.returncode == 0, r.stderr
    _, records = read_journal(out / JOURNAL_FILE)
    return sorted((t.set_index, sorted(t.params.items()), t.result.event, t.result.goal_time_us) for t in records)


@cache
def offset_version(tmp: Path) -> list[tuple]:
    return campaign(tmp / "offset", "--app", "line_trace_c")


@pytest.mark.slow
@pytest.mark.parametrize("kind", KINDS)
def test_each_kind_tunes_the_tracer_as_the_offset_version_and_patches_it(kind, tmp_path_factory):
    """The same proposals give the same laps, set for set; best.patch applied to a copy gives a program
    that, run with no parameters at all, laps exactly as the best set did."""
    need_cc()
    tmp = tmp_path_factory.getbasetemp()
    out = tmp_path_factory.mktemp(kind) / "campaign"
    tuned = campaign(out, "--app", str(PROGRAMS / f"tracer_{kind}"), "--space", str(PROGRAMS / f"{kind}.toml"))
    assert tuned == offset_version(tmp)
    assert len({lap for *_, lap in tuned}) >= 5  # the sets drive differently
    best = json.loads((out / "best.json").read_text())
    assert best["patch"]["apply_in"] == str(PROGRAMS / f"tracer_{kind}")
    copy = out.parent / "programs"
    shutil.copytree(PROGRAMS, copy)
    r = subprocess.run(["git", "apply", str(out / "best.patch")], cwd=copy / f"tracer_{kind}", capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
    trial = hako("try", "--app", str(copy / f"tracer_{kind}"), "--noise", "0", "--json", "--run-dir",
                 str(out.parent / "patched"), timeout=300)
    assert trial.returncode == 0, trial.stderr
    assert json.loads(trial.stdout)["lap_time_s"] == best["lap_time_s"]


@pytest.mark.slow
def test_hako_test_takes_a_campaign_either_way(tmp_path):
    """A case `from` a campaign gives each value its kind; a case on the patched program gives none."""
    need_cc()
    out = tmp_path / "campaign"
    r = hako("run", "--app", str(PROGRAMS / "tracer_symbol"), "--space", str(PROGRAMS / "symbol.toml"), "--smoke",
             "--noise", "0", "--validate", "0", "--out", str(out), timeout=600)
    assert r.returncode == 0, r.stderr
    copy = tmp_path / "programs"
    shutil.copytree(PROGRAMS, copy)
    assert subprocess.run(["git", "apply", str(out / "best.patch")], cwd=copy / "tracer_symbol").returncode == 0
    (tmp_path / "hako-tests.toml").write_text(
        f'[defaults]\nseeds = 1\nnoise = 0\nexpect = ["GOAL"]\n'
        f'[case.tuned]\napp = "{PROGRAMS / "tracer_symbol"}"\nfrom = "campaign"\n'
        f'[case.patched]\napp = "{copy / "tracer_symbol"}"\nparams = {{}}\n')
    r = hako("test", str(tmp_path / "hako-tests.toml"), "--out", str(tmp_path / "test"), "--json",
             str(tmp_path / "test" / "results.json"), timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    cases = json.loads((tmp_path / "test" / "results.json").read_text())["cases"]
    best = json.loads((out / "best.json").read_text())["lap_time_s"]
    assert [c["runs"][0]["lap_time_s"] for c in cases] == [best, best]


REPORTER = r"""
/* Reports what it reads: each global's bytes into the TX body from 600 on, where no driver writes. */
#include "ev3api.h"

float g_f = 1.0f;
double g_d = 1.0;
int g_i = 1;
short g_s = 1;
#ifndef D_F
#define D_F 1.0f
#endif
#ifndef D_D
#define D_D 1.0
#endif

#define TX(offset, type) (*(volatile type *)(0x090F1000 + (offset)))

void main_task(intptr_t unused)
{
    TX(600, float) = g_f;
    TX(604, unsigned) = sizeof(double);
    TX(608, double) = g_d;
    TX(616, int) = g_i;
    TX(620, int) = g_s;
    TX(624, float) = D_F;
    TX(632, double) = D_D;
    for (;;)
        tslp_tsk(100000);
}
"""
REPORTER_SPACE = """
[[param]]
name = "f"
symbol = "g_f"
low = 0.0
high = 5.0
[[param]]
name = "d"
symbol = "g_d"
low = 0.0
high = 5.0
[[param]]
name = "i"
symbol = "g_i"
type = "int"
low = -100
high = 100
[[fixed]]
name = "s"
symbol = "g_s"
type = "int"
value = -7
"""
DEFINES = """
[[param]]
name = "df"
define = "D_F"
low = 0.0
high = 5.0
[[param]]
name = "dd"
define = "D_D"
type = "f64"
low = 0.0
high = 5.0
"""
F, D, I = 1.2345678901234567, 3.0000000000000004, 41.6  # noqa: E741 (I: the int); what no float32 holds, what only a double does


def report(tmp_path: Path, space_text: str, x: tuple[float, ...], **bench) -> bytes:
    """The TX bytes from 600 on after one test of the reporter with the values `x`."""
    (tmp_path / "app").mkdir()
    (tmp_path / "app" / "app.c").write_text(REPORTER)
    space = ParameterSpace.from_dict(__import__("tomllib").loads(space_text))
    options = BenchOptions(app=str(tmp_path / "app" / "app.c"), bindings=space.bindings(), time_limit_s=0.5, **bench)
    with Bench(options, tmp_path / "run") as b:
        result = b.run(TestSpec(0, 1, space.to_offsets(x), 0, 0.0, space.slot_types))
        assert result.event.name == "TIME_OVER", result
        with open_athrill(tmp_path / "run") as tx:
            return bytes(tx.read("B", 600 + i) for i in range(40))


def test_a_global_holds_exactly_the_float32_float64_or_integer_of_the_proposal(tmp_path):
    need_cc()
    f, _, d, i, s = struct.unpack_from("<fIdii", report(tmp_path, REPORTER_SPACE + DEFINES, (F, D, I, F, D)))
    assert (f, d, i, s) == (as_float32(F), D, 42, -7)


def test_a_define_gives_exactly_the_float32_or_float64_of_the_proposal(tmp_path):
    need_cc()
    df, dd = struct.unpack_from("<f4xd", report(tmp_path, DEFINES, (F, D)), 24)
    assert (df, dd) == (as_float32(F), D)


@pytest.mark.slow
def test_a_global_of_a_v850_image_is_set_exactly_in_the_real_emulator(repeatable_athrill2, tmp_path):
    need_v850_tools()
    raw = report(tmp_path, REPORTER_SPACE, (F, D, I), emulator="athrill2", athrill2=str(repeatable_athrill2))
    f, double_size, i, s = struct.unpack_from("<fI8xii", raw)
    assert (f, i, s) == (as_float32(F), 42, -7)
    d = struct.unpack_from("<d" if double_size == 8 else "<f", raw, 8)[0]  # an EV3RT double may be 32 bits
    assert d == (D if double_size == 8 else as_float32(D))


CPP_REPORTER = r"""
// Reports what it reads, as REPORTER does, of globals a C++ program keeps in a namespace and a class.
#include "ev3api.h"

namespace tuning {
float kp = 1.0f;
}
struct Gains {
    static double kd;
    static int power;
};
double Gains::kd = 1.0;
int Gains::power = 1;

#define TX(offset, type) (*(volatile type *)(0x090F1000 + (offset)))

extern "C" void main_task(intptr_t unused)
{
    TX(600, float) = tuning::kp;
    TX(604, unsigned) = sizeof(double);
    TX(608, double) = Gains::kd;
    TX(616, int) = Gains::power;
    for (;;)
        tslp_tsk(100000);
}
"""
CPP_SPACE = """
[[param]]
name = "kp"
symbol = "tuning::kp"
low = 0.0
high = 5.0
[[param]]
name = "kd"
symbol = "Gains::kd"
low = 0.0
high = 5.0
[[fixed]]
name = "power"
symbol = "Gains::power"
type = "int"
value = 23
"""


def cpp_report(tmp_path: Path, **bench) -> tuple:
    (tmp_path / "app").mkdir()
    (tmp_path / "app" / "app.cpp").write_text(CPP_REPORTER)
    space = ParameterSpace.from_dict(__import__("tomllib").loads(CPP_SPACE))
    options = BenchOptions(app=str(tmp_path / "app" / "app.cpp"), bindings=space.bindings(), time_limit_s=0.5,
                           **bench)
    with Bench(options, tmp_path / "run") as b:
        result = b.run(TestSpec(0, 1, space.to_offsets((F, D)), 0, 0.0, space.slot_types))
        assert result.event.name == "TIME_OVER", result
        with open_athrill(tmp_path / "run") as tx:
            raw = bytes(tx.read("B", 600 + i) for i in range(20))
    f, double_size = struct.unpack_from("<fI", raw)
    d = struct.unpack_from("<d" if double_size == 8 else "<f", raw, 8)[0]
    return f, d if double_size == 8 else None, struct.unpack_from("<i", raw, 16)[0]


def test_a_cpp_programs_qualified_globals_hold_exactly_the_proposal(tmp_path):
    need_cc()
    assert cpp_report(tmp_path) == (as_float32(F), D, 23)


@pytest.mark.slow
def test_a_cpp_images_qualified_globals_are_set_exactly_in_the_real_emulator(repeatable_athrill2, tmp_path):
    """hako build strips a C++ image's debug information; the types come from its asp.debug."""
    need_v850_tools()
    f, d, power = cpp_report(tmp_path, emulator="athrill2", athrill2=str(repeatable_athrill2))
    assert (f, power) == (as_float32(F), 23) and d in (D, None)


@pytest.mark.slow
def test_the_et_robocon_style_cpp_tracer_is_tuned_as_its_team_wrote_it(tmp_path):
    """Its constexpr gains in unit/Pid.h, reached by source parameters: the campaign, best.patch applied to a
    copy with git apply, and the patched copy lapping as the best set did."""
    need_cc()
    team = PROGRAMS / "etrobo_cpp_tracer"
    press = tmp_path / "press.toml"
    press.write_text('[[press]]\nsensor = "touch"\nport = 4\nat_s = 1.0\nfor_s = 0.2\n')
    out = tmp_path / "campaign"
    r = hako("run", "--app", str(team), "--space", str(PROGRAMS / "etrobo_cpp.toml"), "--scenario", str(press),
             "--smoke", "--noise", "0", "--validate", "0", "--out", str(out), timeout=1200)
    assert r.returncode == 0, r.stderr
    assert "unit/Pid.h" in r.stdout and (out / "best.patch").is_file()
    copy = tmp_path / "team"
    shutil.copytree(team, copy)
    applied = subprocess.run(["git", "apply", str(out / "best.patch")], cwd=copy, capture_output=True, text=True)
    assert applied.returncode == 0, applied.stderr
    assert (copy / "unit" / "Pid.h").read_text() != (team / "unit" / "Pid.h").read_text()
    trial = hako("try", "--app", str(copy), "--scenario", str(press), "--noise", "0", "--json", "--run-dir",
                 str(tmp_path / "patched"), timeout=300)
    assert trial.returncode == 0, trial.stderr
    assert json.loads(trial.stdout)["lap_time_s"] == json.loads((out / "best.json").read_text())["lap_time_s"]
