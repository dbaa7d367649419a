"""C++ EV3RT programs as ET Robocon teams write them, built natively: `Makefile.inc` evaluated by GNU make,
EV3RT's `libcpp-ev3`, static objects constructed before the first task, the C++ standard library, and the
one-line errors of a build that cannot be made.

The programs are in tests/programs/: `etrobo_cpp_tracer` (classes in app/ and unit/, the teams' Makefile.inc
with Shift-JIS comments, global libcpp-ev3 objects, a touch start and a cyclic tracer), `cpp_features` (the
language and library a program relies on), `cpp_exception`, and `etrobo_hackev` (ET Robocon's HackEV
sample layout, in C).
"""

from __future__ import annotations

import filecmp
import json
import os
import shutil
from pathlib import Path

import pytest

from athrill_sim.native import NativeBuildError
from athrill_sim.native.build import build_app, find_compiler, find_cxx_compiler
from athrill_sim.native.makefile import ETROBOC_COMMON, LIBRARY_DIR, evaluate
from athrill_sim.native.workspace import find_app
from athrill_sim.programs.program import ProgramError
from athrill_sim.programs.resolve import resolve_program
from athrill_sim.programs.third_party import EV3RT_SDK, RASPIKE_SDK
from tests.helpers.commands import hako, one_line_error
from tests.helpers.ev3rt_corpus import EV3RT
from tests.helpers.native_fixtures import need_cc
from tests.helpers.paths import PROGRAMS, needs_shared
from tests.helpers.raspike_sdk import SDK as RASPIKE

TRACER = PROGRAMS / "etrobo_cpp_tracer"
FEATURES = PROGRAMS / "cpp_features"
HACKEV = PROGRAMS / "etrobo_hackev"
SPIKE_TRACER = PROGRAMS / "etrobo_spike_cpp"
NO_CXX = "needs a C++ compiler (c++) to build C++ apps"


def need_cxx() -> None:
    need_cc()
    try:
        find_cxx_compiler()
    except NativeBuildError:
        pytest.skip(NO_CXX)


def press(tmp_path: Path, port: int | str) -> Path:
    """A scenario pressing the touch sensor on `port` (or the force sensor, "force") at 0.5 s."""
    scenario = tmp_path / f"press-{port}.toml"
    sensor = 'sensor = "force"' if port == "force" else f'sensor = "touch"\nport = {port}'
    scenario.write_text(f"[[press]]\n{sensor}\nat_s = 0.5\nfor_s = 0.2\n")
    return scenario


def workspace(tmp_path: Path, makefile: bytes | str, files: dict[str, str] | None = None) -> Path:
    app = tmp_path / "ws" / "app"
    app.mkdir(parents=True)
    (app / "Makefile.inc").write_bytes(makefile.encode() if isinstance(makefile, str) else makefile)
    for name, text in (files or {}).items():
        (app / name).parent.mkdir(parents=True, exist_ok=True)
        (app / name).write_text(text)
    return app


@pytest.mark.parametrize("sdk, library", [(EV3RT, "libcpp-ev3"), (RASPIKE, "libcpp-spike")])
def test_the_shipped_libraries_are_the_sdks_own_byte_for_byte(sdk, library):
    shared = sdk / "sdk" / "common" / "library" / library
    if not shared.is_dir():
        pytest.skip(needs_shared("the SDK", sdk, EV3RT_SDK if sdk == EV3RT else RASPIKE_SDK))
    ours = LIBRARY_DIR / library
    for sub in ("include", "src"):
        compare = filecmp.dircmp(shared / sub, ours / sub)
        assert not (compare.left_only or compare.right_only or compare.diff_files), sub
        assert all(filecmp.cmp(shared / sub / f, ours / sub / f, shallow=False) for f in compare.common_files)
    assert (shared / "Makefile").read_bytes() == (ours / "Makefile").read_bytes()
    assert (ours / "LICENSE.md").read_bytes() == (sdk / "LICENSE.md").read_bytes()


def test_a_teams_makefile_inc_is_read_by_gnu_make_with_its_shell_calls_and_the_library():
    app = find_app(TRACER)
    names = {s.relative_to(TRACER).as_posix() for s in app.sources}
    assert names == {"app.cpp", "app/Tracer.cpp", "unit/Pid.cpp"}  # found by $(shell ls ...) and vpath
    assert {s.name for s in app.library_sources} == {"Clock.cpp", "ColorSensor.cpp", "GyroSensor.cpp",
                                                    "Motor.cpp", "SonarSensor.cpp", "Steering.cpp",
                                                    "TouchSensor.cpp"}
    assert app.include_dirs[:1] == (LIBRARY_DIR / "libcpp-ev3" / "include",)
    assert {TRACER / "app", TRACER / "unit"} <= set(app.include_dirs) and app.cxx
    assert b"\x83" in (TRACER / "Makefile.inc").read_bytes()  # its comments are Shift-JIS
    assert {TRACER / "Makefile.inc", LIBRARY_DIR / "libcpp-ev3" / "Makefile"} <= set(app.hashed)


def test_a_program_that_includes_libcpp_spike_is_a_spike_program():
    app = find_app(SPIKE_TRACER)
    assert app.spike and app.cxx and "-DUSE_RASPIKE_ART" in app.defines
    assert {s.name for s in app.library_sources} == {"Button.cpp", "Clock.cpp", "IMU.cpp", "Light.cpp"}


@pytest.mark.slow
def test_a_teams_libcpp_spike_tracer_laps_hackspi_after_the_force_press(tmp_path):
    need_cxx()
    result = trial(tmp_path, SPIKE_TRACER, "--robot", "hackspi", "--scenario", str(press(tmp_path, "force")))
    assert result["event"] == "GOAL" and 25 < result["lap_time_s"] < 35
    assert "spike-cpp-tracer started at 500 ms" in (tmp_path / "run" / "athrill.log").read_text()


def test_environment_variables_reach_make_and_et_robocons_default_to_the_benchs_header(tmp_path, monkeypatch):
    app = workspace(tmp_path, "INCLUDES += -I$(ETROBO_HRP3_WORKSPACE)/etroboc_common -I$(MY_INCLUDE)\n")
    (tmp_path / "mine").mkdir()
    monkeypatch.setenv("MY_INCLUDE", str(tmp_path / "mine"))
    monkeypatch.delenv("ETROBO_HRP3_WORKSPACE", raising=False)
    assert evaluate(app / "Makefile.inc").words("INCLUDES") == [f"-I{ETROBOC_COMMON}", f"-I{tmp_path / 'mine'}"]
    assert (ETROBOC_COMMON / "etroboc_ext.h").is_file()
    monkeypatch.setenv("ETROBO_HRP3_WORKSPACE", str(tmp_path / "etrobo"))
    assert evaluate(app / "Makefile.inc").words("INCLUDES")[0] == f"-I{tmp_path / 'etrobo'}/etroboc_common"


@pytest.mark.parametrize("makefile, message", [
    ("A = 1\n  stray words\n", "Makefile.inc:2: missing separator"),
    ("\n$(error this robot needs a gyro)\n", "Makefile.inc:2: this robot needs a gyro"),
    ("APPL_CXXOBJS += $(shell ls $(dir $(lastword $(MAKEFILE_LIST)))nothere/*.cpp)\n",
     "nothere/*.cpp) failed: ls: cannot access"),
    ("APPL_CXXOBJS += $(shell find $(dir $(lastword $(MAKEFILE_LIST))) -name '*.cc')\n", "names no files"),
    ("X := $(shell exit 3)\n", "$(shell exit 3) failed: exit status 3"),
    ("include $(EV3RT_SDK_LIB_DIR)/libcpp-spike2/Makefile\n",
     "Makefile.inc:1: includes libcpp-spike2/Makefile, a library the bench does not have"),
    ("APPL_CXXOBJS += Missing.o\nSRCLANG := c++\n", "APPL_CXXOBJS names Missing.o, but there is no Missing.cpp"),
    ("APPL_LIBS += $(dir $(lastword $(MAKEFILE_LIST)))prebuilt.a\n", "a prebuilt library"),
])
def test_a_makefile_inc_that_cannot_be_built_is_one_line(tmp_path, makefile, message):
    app = workspace(tmp_path, makefile, {"app.c": "", "app.cpp": "", "prebuilt.a": ""})
    with pytest.raises(NativeBuildError) as e:
        find_app(app)
    assert "\n" not in str(e.value) and message in str(e.value)


def test_the_main_file_must_be_the_one_srclang_has_ev3rt_build(tmp_path):
    app = workspace(tmp_path, "", {"app.cpp": ""})
    with pytest.raises(NativeBuildError, match=r"app.cpp, but Makefile.inc says SRCLANG c: .*set SRCLANG := c\+\+"):
        find_app(app)
    (app / "Makefile.inc").write_text("SRCLANG := c++\n")
    (app / "app.cpp").rename(app / "main.cpp")
    with pytest.raises(NativeBuildError, match="no app.cpp; an EV3RT workspace folder holds app.cpp"):
        find_app(app)


def trial(tmp_path: Path, app: Path, *args: str) -> dict:
    out = hako("try", "--app", str(app), "--noise", "0", "--json", "--run-dir", str(tmp_path / "run"), *args,
               timeout=600)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def program_lines(run_dir: Path) -> list[str]:
    """What the program printed: in the real emulator, what follows athrill2's own start-up lines (the last
    of which names its device-call address)."""
    lines = [line for line in (run_dir / "athrill.log").read_text(errors="replace").splitlines() if line.strip()]
    starts = [i for i, line in enumerate(lines) if line.startswith("athrill_device_func_call=")]
    return lines[starts[-1] + 1:] if starts else lines


FEATURE_LINES = ["constructed the first global", "main_task: features, 3 squares",
                 "square 3 and rect 2x5: total area 19", "new int[1000]: 7", "iostream works", "clock: 20 ms"]


def test_static_objects_are_built_before_the_first_task_and_the_standard_library_works(tmp_path):
    need_cxx()
    assert trial(tmp_path, FEATURES, "--time-limit", "0.5")["event"] == "TIME_OVER"
    assert program_lines(tmp_path / "run") == FEATURE_LINES


@pytest.mark.slow
def test_the_teams_cpp_tracer_waits_for_the_touch_sensor_and_laps(tmp_path):
    need_cxx()
    result = trial(tmp_path, TRACER, "--scenario", str(press(tmp_path, 4)))
    assert result["event"] == "GOAL" and 15 < result["lap_time_s"] < 20
    assert "cpp-tracer (running) started at 500000 us" in (tmp_path / "run" / "athrill.log").read_text()
    still = trial(tmp_path / "unpressed", TRACER, "--time-limit", "2")
    assert still["event"] == "TIME_OVER" and still["distance_m"] == 0


def test_an_exception_escaping_a_task_is_a_program_crash_and_one_caught_is_not(tmp_path):
    need_cxx()
    result = trial(tmp_path, PROGRAMS / "cpp_exception" / "app.cpp")
    assert result["event"] == "CRASH" and result["crash"] == "program" and result["crash_detail"] == -6
    assert "caught: caught in main_task" in result["program_output"]
    assert "terminate called after throwing an instance of 'std::runtime_error'" in result["program_output"]


@pytest.mark.slow
@pytest.mark.parametrize("etrobo", [None, "/nonexistent/etrobo", "etroboc"])
def test_et_robocons_hackev_layout_builds_with_and_without_its_variable_and_drives(tmp_path, etrobo):
    need_cc()
    env = {k: v for k, v in os.environ.items() if not k.startswith("ETROBO_")}
    if etrobo == "etroboc":  # a user's own ET Robocon environment: its etroboc_common holds the real header
        (tmp_path / "etrobo" / "etroboc_common").mkdir(parents=True)
        (tmp_path / "etrobo" / "etroboc_common" / "etroboc_ext.h").write_text("#error not the bench's header\n")
        etrobo = str(tmp_path / "etrobo")
    if etrobo is not None:
        env["ETROBO_HRP3_WORKSPACE"] = etrobo
    out = hako("try", "--app", str(HACKEV), "--robot", "hackev", "--scenario", str(press(tmp_path, 1)),
               "--noise", "0", "--json", "--run-dir", str(tmp_path / "run"), env=env, timeout=600)
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout)
    assert result["event"] == "COMPLETED" and result["distance_m"] > 2.5  # 8 s of tracing, then its own end


def test_a_cpp_compile_error_is_its_first_error_with_file_and_line(tmp_path):
    need_cxx()
    app = workspace(tmp_path, "SRCLANG := c++\nAPPL_CXXOBJS += Broken.o\n",
                    {"app.cpp": '#include "ev3api.h"\nextern "C" void main_task(intptr_t u) {}\n',
                     "Broken.cpp": "class Pid {\n  int x\n};\n"})
    with pytest.raises(ProgramError) as e:
        resolve_program(str(app))
    assert "\n" not in str(e.value) and "app.cpp does not build: Broken.cpp:2:" in str(e.value)
    assert "error:" in str(e.value)


def test_an_undefined_ev3rt_call_in_cpp_is_a_one_line_link_error_naming_it(tmp_path):
    need_cxx()
    (tmp_path / "app.cpp").write_text('#include "ev3api.h"\nextern "C" void main_task(intptr_t u)\n'
                                      "{ ev3_infrared_sensor_get_distance(EV3_PORT_1); }\n")
    with pytest.raises(NativeBuildError, match="undefined reference to `ev3_infrared_sensor_get_distance'"):
        build_app(tmp_path / "app.cpp")


def test_a_task_function_without_c_linkage_is_named_with_the_fix(tmp_path):
    need_cxx()
    (tmp_path / "app.cpp").write_text('#include "ev3api.h"\nvoid main_task(intptr_t u) {}\n')
    with pytest.raises(NativeBuildError, match=r'defines no function main_task.*must be extern "C"'):
        build_app(tmp_path / "app.cpp")


def test_without_a_cpp_compiler_a_cpp_app_names_what_to_install(tmp_path, monkeypatch):
    need_cc()
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    for tool in ("make", "sh", "ls", "sed", "date", "mkdir", "cat"):
        if found := shutil.which(tool):
            (bin_dir / tool).symlink_to(found)
    (bin_dir / "cc").symlink_to(find_compiler())
    monkeypatch.setenv("PATH", str(bin_dir))
    monkeypatch.delenv("CXX", raising=False)
    with pytest.raises(ProgramError, match=r"no C\+\+ compiler .*\(apt-get install g\+\+\)"):
        resolve_program(str(TRACER))


def test_hako_try_with_a_broken_makefile_inc_fails_before_any_test(tmp_path):
    app = workspace(tmp_path, "SRCLANG := c++\nAPPL_CXXOBJS += $(shell ls /nonexistent/*.cpp)\n", {"app.cpp": ""})
    run_dir = tmp_path / "run"
    one_line_error(hako("try", "--app", str(app), "--run-dir", str(run_dir), timeout=120), "Makefile.inc",
                   "$(shell ls /nonexistent/*.cpp) failed")
    assert not (run_dir / "physics.log").exists()
