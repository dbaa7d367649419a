"""Building native apps: the generated headers, app.cfg and Makefile.inc, the cache, and build errors."""

import os
import subprocess
from pathlib import Path

import pytest

from athrill_sim.mock import kernel as mock_kernel
from athrill_sim.native import NativeBuildError
from athrill_sim.native.appcfg import kernel_config
from athrill_sim.native.build import build_app, first_error
from athrill_sim.native.headers import generated_headers
from athrill_sim.native.workspace import find_app
from athrill_sim.programs.program import ProgramError
from athrill_sim.programs.resolve import resolve_program
from hakoniwa.wire import protocol, waiting
from hakoniwa.wire.timebase import PHYSICS_STEP_US
from tests.helpers.commands import hako
from tests.helpers.native_fixtures import build, need_cc


def protocol_values() -> dict[str, int | str]:
    """What hako_layout.h must say, taken from protocol.py itself rather than from c_header()."""
    p = protocol
    values: dict[str, int | str] = {
        name: getattr(p, name) for name in ("FILE_SIZE", "HEADER_SIZE", "PACKET_SIZE", "WINDOW_SIZE",
                                            "LAYOUT_VERSION", "EXT_OFF", "EXT_SIZE", "RX_GUEST_BASE", "TX_GUEST_BASE",
                                            "MOTOR_PORTS", "TOUCH_PRESSED", "EXIT_BENCH_FAULT",
                                            "NEVER_WAKES")}
    values |= {"UNITY_FILE": p.UNITY_FILE, "ATHRILL_FILE": p.ATHRILL_FILE, "UNITY_MAGIC": p.UNITY_MAGIC.decode(),
               "ATHRILL_MAGIC": p.ATHRILL_MAGIC.decode()}
    for prefix, cls in (("HDR", p.Header), ("RX", p.Rx), ("TX", p.Tx)):
        values |= {f"{prefix}_{k}": v for k, v in vars(cls).items() if isinstance(v, int)}
    for prefix, enum in (("EVENT", p.Event), ("CRASH", p.CrashKind), ("SYNC", p.SyncMode), ("COLOR", p.ColorId),
                         ("LED", p.LedBit)):
        values |= {f"{prefix}_{m.name}": m.value for m in enum}
    return values


def test_the_generated_layout_header_says_what_protocol_py_says(tmp_path):
    need_cc()
    expected = protocol_values()
    for name, text in generated_headers().items():
        (tmp_path / name).write_text(text)
    prints = "\n".join(f'    printf("{k} %s\\n", {f"HAKO_{k}" if isinstance(v, str) else f"str(HAKO_{k})"});'
                       for k, v in expected.items())
    (tmp_path / "dump.c").write_text(
        '#include <stdio.h>\n#include "hako_layout.h"\n'
        'static char buf[64][32]; static int n;\n'
        'static const char *str(long long v) { snprintf(buf[n % 64], 32, "%lld", v); return buf[n++ % 64]; }\n'
        f"int main(void)\n{{\n{prints}\n    return 0;\n}}\n")
    from athrill_sim.native.build import find_compiler

    subprocess.run([str(find_compiler()), "-o", str(tmp_path / "dump"), str(tmp_path / "dump.c")], check=True)
    out = subprocess.run([str(tmp_path / "dump")], capture_output=True, text=True, check=True).stdout
    got = dict(line.split(" ", 1) for line in out.splitlines())
    assert got == {k: str(v) for k, v in expected.items()}


def test_the_generated_timing_header_is_the_mock_kernels_timing():
    text = generated_headers()["hako_timing.h"]
    assert f"#define HAKO_PHYSICS_STEP_US {PHYSICS_STEP_US}\n" in text
    assert f"#define HAKO_TEST_WAIT_NAP_S {mock_kernel.TEST_WAIT_NAP_S!r}\n" in text
    assert f"#define HAKO_CHECK_EVERY_S {waiting.CHECK_EVERY_S!r}\n" in text


def same(cfg: Path) -> str:
    """A stand-in for the C preprocessor where the .cfg needs none."""
    return cfg.read_text()


def test_app_cfg_declares_tasks_and_cyclic_handlers_with_ids(tmp_path):
    cfg = tmp_path / "app.cfg"
    cfg.write_text('INCLUDE("app_common.cfg");\nextern void not_an_api(intptr_t exinf);\n'
                   'DOMAIN(TDOM_APP) {\nCRE_TSK(MAIN_TASK, { TA_ACT, 0, main_task, PRI + 1, 4096, NULL });\n'
                   'CRE_TSK(TRACER_TASK, { TA_NULL, 0, tracer_task, PRI + 2, STACK_SIZE, NULL });\n'
                   'EV3_CRE_CYC(TICK, { TA_STA, 3, tick, 4, 1 });\n'
                   'CRE_CYC(KICK, { TA_NULL, { TNFY_ACTTSK, TRACER_TASK }, 4U * 1000U, 1U * 1000U });\n}\n'
                   'ATT_MOD("app.o");\n')
    config = kernel_config(cfg, same)
    header, source = config.header(), config.source()
    # EV3RT numbers its EV3_CRE_CYC handlers apart from ASP3's CRE_CYC ones (ev3cyclic_dri.c): each from 1
    for line in ("#define MAIN_TASK 1", "#define TRACER_TASK 2", "#define TICK 1", "#define KICK 1",
                 "#define TNUM_TSKID 2", "#define TNUM_CYCID 1"):
        assert line + "\n" in header
    assert '{"MAIN_TASK", (TA_ACT), (intptr_t)(0), main_task, (PRI + 1), (4096)},' in source
    assert '{TNFY_HANDLER, (intptr_t)(3), tick}, ((RELTIM)(4) * 1000U), ((RELTIM)(1) * 1000U), true},' in source
    assert '{"KICK", (TA_NULL), {TNFY_ACTTSK, TRACER_TASK}, (4U * 1000U), (1U * 1000U), false},' in source
    assert "void tick(intptr_t exinf);" in source and "not_an_api" not in source


@pytest.mark.parametrize("cfg, message", [
    ("CRE_SEM(SEM1, { TA_NULL, 1, 1 });", "CRE_SEM is not supported by the native mock"),
    ('INCLUDE("mine.cfg");', 'INCLUDE("mine.cfg"): no such file'),
    ("CRE_TSK(A, { TA_ACT, 0, main_task, 10 });", "CRE_TSK(A) takes 6 values in braces, got 4"),
    ("CRE_TSK(A, { TA_ACT, 0, main_task, 10, 4096, NULL });\nCRE_TSK(A, { TA_ACT, 0, t2, 10, 4096, NULL });",
     "A is declared twice"),
])
def test_app_cfg_errors_name_the_problem(tmp_path, cfg, message):
    (tmp_path / "app.cfg").write_text(cfg)
    with pytest.raises(NativeBuildError, match=message.replace("(", r"\(").replace(")", r"\)")):
        kernel_config(tmp_path / "app.cfg", same)


def test_makefile_inc_names_the_sources_as_gnu_make_reads_it(tmp_path):
    app = tmp_path / "ws" / "app"
    (app / "util").mkdir(parents=True)
    (app / "app.c").write_text("")
    (app / "util" / "pid.c").write_text("")
    (app / "Makefile.inc").write_text(
        "mkfile_path := $(dir $(lastword $(MAKEFILE_LIST)))\nAPPL_DIRS += $(mkfile_path)util\n"
        "ifeq ($(SRCLANG),c++)\n\tAPPL_CXXOBJS += tracer.o\nelse\n\tAPPL_COBJS += $(notdir $(wildcard "
        "$(mkfile_path)util/*.c))\nendif\nAPPL_COBJS := $(APPL_COBJS:.c=.o)\n"
        "INCLUDES += -I$(mkfile_path)util\nCOPTS += -DGAIN=2 -O3 -ffast-math -I $(mkfile_path)util -std=c99\n")
    found = find_app(app)
    assert found.sources == (app / "app.c", app / "util" / "pid.c")
    assert found.include_dirs == (app / "util",) and found.defines == ("-DGAIN=2",) and found.c_std == "-std=c99"
    assert app / "Makefile.inc" in found.hashed


def test_a_build_is_cached_until_a_source_changes(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    source = '#include "ev3api.h"\nvoid main_task(intptr_t unused) { tslp_tsk(%d); }\n'
    exe = build(tmp_path / "app", source % 1000)
    built_at = exe.stat().st_mtime_ns
    assert build_app(tmp_path / "app" / "app.c") == exe and exe.stat().st_mtime_ns == built_at
    assert build(tmp_path / "copy", source % 1000) == exe  # the same program elsewhere
    assert build(tmp_path / "app", source % 2000) != exe
    assert exe.parent.parent == tmp_path / "cache" / "hakoniwa-py" / "native"


def test_a_compile_error_is_a_one_line_program_error_with_the_compilers_first_message(tmp_path):
    need_cc()
    (tmp_path / "broken.c").write_text('#include "ev3api.h"\nvoid main_task(intptr_t u)\n{\n    int x = 1\n}\n')
    with pytest.raises(ProgramError) as e:
        resolve_program(str(tmp_path / "broken.c"))
    message = str(e.value)
    assert "\n" not in message
    assert "broken.c does not build: broken.c:5:1: error: expected ',' or ';' before '}' token" in message


def test_an_unsupported_ev3rt_call_is_a_link_error_that_names_it(tmp_path):
    need_cc()
    (tmp_path / "app.c").write_text('#include "ev3api.h"\nvoid main_task(intptr_t u) '
                                    '{ ev3_infrared_sensor_get_distance(EV3_PORT_1); }\n')
    with pytest.raises(NativeBuildError,
                       match="undefined reference to `ev3_infrared_sensor_get_distance'.*not in the native"):
        build_app(tmp_path / "app.c")


def test_first_error_skips_warnings_and_linker_noise():
    out = ("app.c: In function 'f':\napp.c:3:5: warning: unused variable 'x'\n"
           "/usr/bin/ld: /tmp/cc1.o: in function `main_task':\napp.c:(.text+0x1d): undefined reference to `wai_sem'\n"
           "collect2: error: ld returned 1 exit status\n")
    assert first_error(out).startswith("undefined reference to `wai_sem' (not in the native")
    twice = ("/usr/bin/ld: /tmp/cc2.o: in function `main':\napp.c:(.text.startup+0x0): multiple definition of "
             "`main'; /tmp/cc3.o:main.c:(.text.startup+0x0): first defined here\n"
             "collect2: error: ld returned 1 exit status\n")
    assert first_error(twice).startswith("multiple definition of `main'")


def test_without_a_c_compiler_a_c_app_is_a_one_line_error(tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))
    monkeypatch.delenv("CC", raising=False)
    (tmp_path / "app.c").write_text("")
    with pytest.raises(ProgramError, match="no C compiler"):
        resolve_program(str(tmp_path / "app.c"))


def test_hako_try_with_a_broken_c_app_fails_before_any_test(tmp_path):
    need_cc()
    (tmp_path / "broken.c").write_text("void main_task(long u) { undeclared(); = }\n")
    run_dir = tmp_path / "run"
    out = hako("try", "--app", str(tmp_path / "broken.c"), "--run-dir", str(run_dir), timeout=120)
    assert out.returncode != 0
    assert "Traceback" not in out.stderr and len(out.stderr.strip().splitlines()) == 1
    assert "broken.c does not build: broken.c:1:" in out.stderr and "error:" in out.stderr
    assert not (run_dir / "physics.log").exists()  # no test started


@pytest.mark.parametrize("variable", ["HOME", "XDG_CACHE_HOME"])
def test_an_unwritable_cache_names_the_variable_that_moves_it(tmp_path, variable):
    """A read-only HOME (here a HOME the cache cannot be made under, as even root cannot write inside a file)."""
    need_cc()
    app = tmp_path / "app.c"
    app.write_text('#include "ev3api.h"\nvoid main_task(intptr_t exinf) { ext_tsk(); }\n')
    blocked = tmp_path / "a-file"
    blocked.write_text("")
    env = {**os.environ, "XDG_CACHE_HOME": "", variable: str(blocked)}
    r = hako("try", "--app", str(app), "--time-limit", "1", env=env, timeout=120)
    assert r.returncode != 0 and "Traceback" not in r.stderr
    (line,) = [line for line in r.stderr.splitlines() if line.startswith("Error:")]
    assert line.startswith(f"Error: cannot write the build cache at {blocked}")
    assert "set XDG_CACHE_HOME to a writable folder" in line


def test_the_cache_error_is_caught_as_either_build_s_error(tmp_path, monkeypatch):
    from athrill_sim.programs.build_cache import cached_build
    from athrill_sim.v850 import ImageError

    (tmp_path / "a-file").write_text("")
    for kind in (ImageError, NativeBuildError):
        with pytest.raises(kind, match="XDG_CACHE_HOME"):
            cached_build(tmp_path / "a-file" / "entry", "product", lambda scratch: None)
