"""SPIKE programs natively: ET Robocon's SPIKE SDK for Athrill (raspike-athrill-v850e2m) as the reference for
what each SPIKE-RT call reads and writes, its headers as the reference for what ours declare, and RasPike-ART's
official samples, unmodified. Expected values come from the SDK's C (sdk/common/spikeapi/src), never from what
our runtime printed."""

import json
import re
import shutil
import signal
import subprocess

import numpy
import pytest

from athrill_sim.native import NativeBuildError
from athrill_sim.native.build import RUNTIME_INCLUDE, build_app
from athrill_sim.native.spike import INCLUDE_DIRS
from hakoniwa.physics import spike_hub
from hakoniwa.wire.protocol import TOUCH_PRESSED, Rx, Tx
from tests.athrill.test_ev3rt_corpus import declarations
from tests.helpers.commands import hako
from tests.helpers.native_fixtures import FakePhysics, build, finish
from tests.helpers.raspike_sdk import (
    ART_SAMPLES,
    LIBCPP_SPIKE,
    NEEDS_RASPIKE,
    PBIO_HEADERS,
    SDK,
    SDK_SAMPLES,
    SPIKE_HEADERS,
)
from tests.helpers.realemu_fixtures import need_v850_tools

OURS = INCLUDE_DIRS[0]
# Declared with SPIKE-RT's (or pbio's) signatures, but not provided: a call is a link error naming it.
NOT_PROVIDED = {"hub_imu_get_temperature", "hub_imu_is_stationary", "hub_imu_set_tilt", "hub_imu_get_heading",
                "hub_imu_reset_heading", "pup_force_sensor_distance", "pbio_error_str", "pbdrv_button_is_pressed",
                *(f"pbio_color_{f}" for f in ("rgb_to_hsv", "hsv_to_rgb", "to_hsv", "to_rgb", "hsv_compress",
                                              "hsv_expand")),
                *(f"pbio_light_matrix_{f}" for f in ("get_size", "set_orientation", "clear", "set_rows",
                                                     "set_pixel", "set_image", "start_animation",
                                                     "stop_animation"))}


def typedef_names(text: str) -> set[str]:
    """The names a TOPPERS header typedefs (`typedef ... NAME;`, struct typedefs included)."""
    text = re.sub(r"/\*.*?\*/|//[^\n]*", "", text, flags=re.S)
    return set(re.findall(r"\btypedef\b[^;{]*(?:\{[^}]*\})?[^;]*?\b(\w+)\s*;", text))


def test_every_toppers_type_of_the_sdk_is_declared(tmp_path):
    """RasPike's sample_c5 uses float32_t (tool_stddef.h), which our headers once lacked."""
    headers = (SDK / "include" / "t_stddef.h", SDK / "arch" / "gcc" / "tool_stddef.h")
    if not all(h.is_file() for h in headers):
        pytest.skip(NEEDS_RASPIKE)
    names = set().union(*(typedef_names(h.read_text(errors="replace")) for h in headers))
    names = {n for n in names if not n.startswith("TOPPERS_")}  # the headers' own helpers
    assert {"float32_t", "double64_t", "ACVCT", "SYSTIM", "bool_t"} <= names
    uses = "\n".join(f"{n} use_{n};" for n in sorted(names))
    build(tmp_path / "types", f'#include "ev3api.h"\n{uses}\nvoid main_task(intptr_t unused) {{ }}\n')


def shipped_headers(root) -> list:
    return sorted([*(root / "pup").glob("*.h"), *(root / "hub").glob("*.h")])


def test_our_headers_declare_every_function_spike_rts_declare_with_its_signature():
    """RasPike-ART's spike/pup/*.h and spike/hub/*.h, and the functions of the pbio headers they include."""
    if not SPIKE_HEADERS.is_dir():
        pytest.skip(NEEDS_RASPIKE)
    theirs, ours = {}, {}
    for header in shipped_headers(SPIKE_HEADERS):
        theirs.update(declarations(header.read_text()))
        ours.update(declarations((OURS / "spike" / header.relative_to(SPIKE_HEADERS)).read_text()))
    assert len(theirs) == 57
    for header in ("color.h", "error.h"):
        theirs.update(declarations((PBIO_HEADERS / header).read_text()))
        ours.update(declarations((OURS / "pbio" / header).read_text()))
    assert {n: s for n, s in theirs.items() if ours.get(n) != s} == {}
    assert {h.relative_to(SPIKE_HEADERS) for h in shipped_headers(SPIKE_HEADERS)} == \
        {h.relative_to(OURS / "spike") for h in shipped_headers(OURS / "spike")}


def test_every_declared_function_is_provided_or_named_as_not_provided(tmp_path):
    """What the runtime defines, read from a SPIKE program's binary: exactly our declarations less
    NOT_PROVIDED, so nothing declared is forgotten and nothing listed as missing is secretly there."""
    declared = {}
    for header in [*shipped_headers(OURS / "spike"), *(OURS / "pbio").glob("*.h")]:
        declared.update({n: s for n, s in declarations(header.read_text()).items() if not s.startswith("typedef")})
    exe = build(tmp_path / "app", '#include "spikeapi.h"\nvoid main_task(intptr_t unused) { }\n')
    nm = subprocess.run(["nm", "--defined-only", str(exe)], capture_output=True, text=True, check=True).stdout
    defined = {line.split()[-1] for line in nm.splitlines() if line.split()[1:2] in (["T"], ["t"])}
    assert set(declared) - defined == NOT_PROVIDED


@pytest.mark.parametrize("call", ["hub_imu_get_temperature()", "pbio_error_str(PBIO_ERROR_IO)[0]",
                                  "pup_force_sensor_distance(NULL)"])
def test_a_call_outside_the_subset_is_a_link_error_that_names_it(tmp_path, call):
    source = ('#include "spikeapi.h"\n#include "spike/hub/imu.h"\n#include "spike/pup/forcesensor.h"\n'
              f"void main_task(intptr_t unused) {{ syslog(LOG_NOTICE, \"%d\", (int){call}); }}\n")
    with pytest.raises(NativeBuildError) as e:
        build(tmp_path / "app", source)
    name = call.split("(")[0]
    assert str(e.value).endswith(f"undefined reference to `{name}' (not in the native mock's SPIKE-RT and EV3RT "
                                 "subsets, see docs/NATIVE.md)")
    assert "\n" not in str(e.value)


@pytest.mark.parametrize("name", ["app.c", "app.cpp"])
def test_a_device_used_without_its_header_names_the_header(tmp_path, name):
    """RasPike-ART's spikeapi.h declares no device (sdk/common/spikeapi/include/spikeapi.h includes only the
    kernel's headers, stdio.h and kernel_cfg.h): `pup_motor_t` without `spike/pup/motor.h` fails on the robot
    too, and the error said nothing of the header."""
    source = ('#include "spikeapi.h"\n' + ('extern "C" ' if name.endswith("cpp") else "")
              + "void main_task(intptr_t unused) { pup_motor_t *m = 0; (void)m; }\n")
    with pytest.raises(NativeBuildError) as e:
        build(tmp_path / "app", source, name=name)
    assert "pup_motor_t is declared in spike/pup/motor.h, which the program does not include" in str(e.value)
    assert "\n" not in str(e.value)


# One call through each libcpp-spike header (the C++ classes call our C headers inline).
LIBCPP_USES = """
#include "Battery.h"
#include "ColorSensor.h"
#include "Display.h"
#include "ForceSensor.h"
#include "Motor.h"
#include "Speaker.h"
#include "UltrasonicSensor.h"
#include "spikeapi.h"  // ours, included by a team's own C++ without an extern "C" of its own
#include "spike/hub/imu.h"
int use_every_header()
{
    SYSTIM now;
    get_tim(&now);
    syslog(LOG_NOTICE, "at %d", (int)now);
    dly_tsk(1000);
    float angv[3];
    hub_imu_get_angular_velocity(angv);
    spikeapi::Motor motor(EPort::PORT_A, spikeapi::Motor::EDirection::COUNTERCLOCKWISE);
    spikeapi::ColorSensor color(EPort::PORT_E);
    spikeapi::ForceSensor force(EPort::PORT_D);
    spikeapi::UltrasonicSensor sonar(EPort::PORT_F);
    spikeapi::Display().off();
    spikeapi::Speaker().stop();
    return motor.getCount() + color.getReflection() + force.isTouched() + sonar.getDistance()
           + spikeapi::Battery().getVoltage();
}
"""


def test_libcpp_spikes_classes_compile_against_our_headers_with_c_linkage(tmp_path):
    """ET Robocon's C++ classes (sdk/common/library/libcpp-spike) include our headers from C++: each must
    compile there, and every SPIKE-RT or kernel call they make must be a C symbol (extern "C"), not a
    mangled C++ one that no C runtime defines."""
    if not LIBCPP_SPIKE.is_dir():
        pytest.skip(NEEDS_RASPIKE)
    if shutil.which("g++") is None:
        pytest.skip("needs a C++ compiler (g++)")
    (tmp_path / "uses.cpp").write_text(LIBCPP_USES)
    (tmp_path / "kernel_cfg.h").write_text("")  # what appcfg.py generates: no C declarations to guard
    flags = [f"-I{d}" for d in (tmp_path, RUNTIME_INCLUDE, *INCLUDE_DIRS, LIBCPP_SPIKE / "include")]
    undefined = set()
    for source in [*sorted((LIBCPP_SPIKE / "src").glob("*.cpp")), tmp_path / "uses.cpp"]:
        obj = tmp_path / f"{source.stem}.o"
        subprocess.run(["g++", "-std=gnu++17", "-Wall", "-c", *flags, str(source), "-o", str(obj)], check=True)
        nm = subprocess.run(["nm", "-u", str(obj)], capture_output=True, text=True, check=True).stdout
        undefined |= {line.split()[-1] for line in nm.splitlines()}
    ours = {n for n in undefined if re.match(r"(pup|hub|pbio)_|get_tim$|syslog$|dly_tsk$", n)}
    assert {"get_tim", "syslog", "dly_tsk", "hub_imu_get_angular_velocity", "hub_imu_get_acceleration",
            "hub_light_on_hsv", "pup_motor_get_count",
            "pup_color_sensor_reflection", "hub_display_off", "hub_speaker_stop", "hub_battery_get_voltage",
            "pup_ultrasonic_sensor_distance", "pup_force_sensor_touched"} <= ours
    assert not [n for n in undefined if n.startswith("_Z") and re.search(r"(pup|hub|pbio)_|get_tim|syslog|dly_tsk", n)]


# (C expression, expected result, where the value comes from). Run in this order, each result logged. Unless
# said otherwise the reference is the SDK's sdk/common/spikeapi/src (raspike_*.c); "SPIKE-RT" marks the calls
# the SDK leaves incomplete, whose values come from SPIKE-RT's drivers/spike sources instead; "ART" marks
# RasPike-ART's libraspike-art (../shared/third_party/raspike-art/RasPike-ART/libraspike-art/src/raspike_*.c),
# whose getters return the hub's last status. The values of the hub's status are the physics process's
# (hakoniwa/physics/spike_hub.py, tested in tests/physics/test_spike_hub.py); here they are the slots'.
SPIKE_CALLS = [
    ("(color = pup_color_sensor_get_device(PBIO_PORT_ID_E)) != NULL", 1, "create_device_by_portid"),
    ("pup_color_sensor_reflection(color)", 0x1234_0049, "the whole word of EV3_SENSOR_ADDR_REFLECT(0)"),
    ("pup_color_sensor_ambient(color)", 7, "EV3_SENSOR_ADDR_AMBIENT(0)"),
    ("pup_color_sensor_rgb(color).r", 0x0203, "EV3_SENSOR_ADDR_RGB_R(0) into uint16_t"),
    ("pup_color_sensor_rgb(color).g", 300, "RGB_G"),
    ("pup_color_sensor_rgb(color).b", 0x0304, "RGB_B"),
    ("pup_color_sensor_hsv(color, true).h", 200, "SPIKE_SENSOR_HSV_ADDR_H"),
    ("pup_color_sensor_hsv(color, false).s", 5, "ART raspike_color.c 30: surface false asks for the SHSV reading"),
    ("pup_color_sensor_hsv(color, true).v", 60, "HSV_V"),
    ("HSV3(pup_color_sensor_color(color, true))", 120_100_100, "ART raspike_color.c 16-19: the hub's colour"),
    ("HSV3(pup_color_sensor_color(color, false))", 120_100_100, "ART raspike_color.c 18: surface ignored"),
    ("pup_color_sensor_detectable_colors(0, NULL) != NULL", 0, "ART raspike_color.c 82: returns 0"),
    ("({ pup_color_hsv_t two[] = {{0, 0, 100}, {0, 0, 0}}; pup_color_sensor_detectable_colors(2, two) == NULL; })",
     1, "ART raspike_color.c 76-82: not passed on"),
    ("HSV3(pup_color_sensor_color(NULL, true))", 120_100_100, "the hub's default set stays"),
    ("pup_color_sensor_reflection(NULL)", 0x1234_0049, "the device is never looked at"),
    ("pup_color_sensor_get_device(PBIO_PORT_ID_E) == NULL", 1, "already taken"),
    ("(force = pup_force_sensor_get_device(PBIO_PORT_ID_D)) != NULL", 1, ""),
    ("pup_force_sensor_touched(force)", 1, "EV3_SENSOR_ADDR_TOUCH_0 > 0"),
    ("(int)pup_force_sensor_force(force)", 4095, "(float) of the slot"),
    ("pup_force_sensor_pressed(force, 5.0f)", 1, "SPIKE-RT: at least 5 N"),
    ("pup_force_sensor_pressed(force, 5000.0f)", 0, "SPIKE-RT"),
    ("(sonar = pup_ultrasonic_sensor_get_device(PBIO_PORT_ID_F)) != NULL", 1, ""),
    ("pup_ultrasonic_sensor_distance(sonar)", 427, "EV3_SENSOR_ADDR_ULTRASONIC, mm"),
    ("pup_ultrasonic_sensor_presence(sonar)", 0, "nothing emits ultrasound"),
    ("pup_ultrasonic_sensor_light_on(sonar)", 0, "PBIO_SUCCESS"),
    ("pup_ultrasonic_sensor_get_device('G') == NULL", 1, "PORT_TO_RASPIKE out of range"),
    ("pup_motor_get_device(0) == NULL", 1, "out of range"),
    ("({ hub_button_t b; hub_button_is_pressed(&b); (int)b; })", 16 | 32, "LEFT and ENTER as CENTER; DOWN has none"),
    ("hub_battery_get_voltage()", 7900, "SPIKE-RT mV (the SDK answers 50)"),
    ("hub_battery_get_current()", 140, "SPIKE-RT mA (the SDK answers 50)"),
    ("hub_imu_init()", 0, "PBIO_SUCCESS"),
    ("({ float a[3]; hub_imu_get_acceleration(a); (int)(a[0] * 100); })", 150, "f32 of IMU word 0"),
    ("({ float a[3]; hub_imu_get_acceleration(a); (int)(a[2] * 100); })", 980650, "word 2"),
    ("({ float a[3]; hub_imu_get_angular_velocity(a); (int)(a[1] * 100); })", -9025, "word 4"),
    ("({ float a[3]; hub_imu_get_angular_velocity(a); (int)(a[2] * 100); })", 300, "word 5"),
    ("(mb = pup_motor_get_device(PBIO_PORT_ID_B)) != NULL", 1, ""),
    ("pup_motor_get_device(PBIO_PORT_ID_B) == NULL", 1, "already taken"),
    ("pup_motor_setup(mb, PUP_DIRECTION_COUNTERCLOCKWISE, true)", 0, "and reset_count"),
    ("TXW(HAKO_TX_SPIKE_DIRECTION + 4)", 1, "ART raspike_motor.c 23: the direction goes to the hub"),
    ("pup_motor_get_count(mb)", 0, "ART raspike_motor.c 42-46: a reset clears the status's count"),
    ("pup_motor_set_power(mb, 40)", 0, ""),
    ("TXW(HAKO_TX_MOTOR_POWER + 4)", 40, "ART raspike_motor.c 107: the power as set; the hub applies the direction"),
    ("pup_motor_get_power(mb)", 40, "ART raspike_motor.c 80-82: pdev->power in power mode"),
    ("(ma = pup_motor_get_device(PBIO_PORT_ID_A)) != NULL", 1, ""),
    ("pup_motor_setup(ma, PUP_DIRECTION_CLOCKWISE, false)", 0, ""),
    ("pup_motor_set_power(ma, 0)", 0, "power 0 raises the stop flag"),
    ("pup_motor_get_device(PBIO_PORT_ID_A) == ma", 1, "port A's port_id 0 reads as free"),
    ("pup_motor_get_count(ma)", 100, "ART raspike_motor.c 54: the status's count"),
    ("(mc = pup_motor_get_device(PBIO_PORT_ID_C)) != NULL", 1, ""),
    ("pup_motor_setup(mc, PUP_DIRECTION_CLOCKWISE, false)", 0, ""),
    ("pup_motor_set_power(mc, 150)", 0, "not clamped"),
    ("pup_motor_get_power(mc)", 150, ""),
    ("pup_motor_set_duty_limit(mc, 30)", 100, "SPIKE-RT: the old limit"),
    ("(pup_motor_set_power(mc, 80), TXW(HAKO_TX_MOTOR_POWER + 8))", 30, "SPIKE-RT: within the limit"),
    ("(pup_motor_restore_duty_limit(mc, 100), pup_motor_set_power(mc, -120), TXW(HAKO_TX_MOTOR_POWER + 8))", -120,
     ""),
    ("pup_motor_stop(mb)", 0, "power 0, STOP flag"),
    ("pup_motor_get_power(mb)", 40, "ART raspike_motor.c 119-123: stop changes neither pdev->cmd nor power"),
    ("(pup_motor_set_speed(mb, 100), pup_motor_get_power(mb))", -37, "ART raspike_motor.c 85: the status's power"),
    ("pup_motor_stop(mb)", 0, ""),
    ("pup_motor_get_power(mb)", -37, "ART: still not power mode"),
    ("pup_motor_is_stalled(mb)", 0, "ART raspike_motor.c 141: the status's (SPIKE-RT: not driven)"),
    ("pup_motor_get_speed(mb)", 0, "ART raspike_motor.c 60: the status's (SPIKE-RT: not moving)"),
    ("(hub_light_on_color(PBIO_COLOR_YELLOW), TXB(HAKO_TX_LED))", 4, "EV3_GPIO_LED_YELLOW, the byte written whole"),
    ("(hub_light_on_color(PBIO_COLOR_ORANGE), TXB(HAKO_TX_LED))", 0, "no LED for orange"),
    ("({ pbio_color_hsv_t c = {250, 80, 50}; hub_light_on_hsv(&c); TXB(HAKO_TX_LED); })", 8, "nearest hue: blue"),
    ("({ pbio_color_hsv_t c = {350, 90, 90}; hub_light_on_hsv(&c); TXB(HAKO_TX_LED); })", 1, "red, across 360"),
    ("({ pbio_color_hsv_t c = {120, 0, 90}; hub_light_on_hsv(&c); TXB(HAKO_TX_LED); })", 0, "grey"),
    ("hub_light_on_color(PBIO_COLOR_GREEN)", 0, ""),
    ("hub_display_char(7)", 2, "SPIKE-RT: PBIO_ERROR_INVALID_ARG, no glyph"),
    ("hub_display_pixel(5, 0, 100)", 2, "SPIKE-RT: off the 5x5 matrix"),
    ("hub_display_pixel(4, 4, 100)", 0, ""),
    ("hub_display_number(-42)", 0, ""),
    ('hub_display_text("A\\001", 1, 1)', 2, "SPIKE-RT"),
    ('ELAPSED_MS(hub_display_text("AB", 100, 50))', 300, "SPIKE-RT: 100 on and 50 off per character"),
    ('ELAPSED_MS(hub_display_text("AB", 100, 0))', 200, "SPIKE-RT"),
    ('ELAPSED_MS(hub_display_text_scroll("A", 10))', 120, "SPIKE-RT: (1 + 1) characters x 6 columns x 10 ms"),
    ("ELAPSED_MS(hub_speaker_play_tone(NOTE_A4, 200))", 200, "SPIKE-RT: dly_tsk(duration)"),
    ("ELAPSED_MS(hub_speaker_play_tone(10, SOUND_MANUAL_STOP))", 0, "SPIKE-RT: returns at once"),
]
SPIKE_SNAPSHOT = {Rx.BUTTONS: 0b11001, Rx.COLOR0_AMBIENT: 7, Rx.COLOR0_REFLECT: 0x1234_0049,
                  Rx.COLOR0_RGB: 0x0001_0203, Rx.COLOR0_RGB + 4: 300, Rx.COLOR0_RGB + 8: 0x0002_0304,
                  Rx.ULTRASONIC_MM: 427, Rx.TOUCH0: 4095, Rx.BATTERY_CURRENT: 140, Rx.BATTERY_VOLTAGE: 7900,
                  Rx.MOTOR_ANGLE: 100, Rx.MOTOR_ANGLE + 4: -530, Rx.MOTOR_ANGLE + 8: 7,
                  Rx.SPIKE_HSV_H: 200, Rx.SPIKE_HSV_S: 80, Rx.SPIKE_HSV_V: 60,
                  Rx.SPIKE_SHSV: 30, Rx.SPIKE_SHSV + 4: 5, Rx.SPIKE_SHSV + 8: 1,
                  Rx.SPIKE_COLOR: 120, Rx.SPIKE_COLOR + 4: 100, Rx.SPIKE_COLOR + 8: 100,
                  Rx.SPIKE_MOTOR_POWER + 4: -37}
SPIKE_IMU = {Rx.SPIKE_IMU_ACCEL_X: (1.5, -2.25, 9806.5), Rx.SPIKE_IMU_ANGVEL_X: (0.5, -90.25, 3.0)}
PROBE_HEAD = r"""
#include "spikeapi.h"
#include "hako_layout.h"
#include "spike/pup/motor.h"
#include "spike/pup/colorsensor.h"
#include "spike/pup/forcesensor.h"
#include "spike/pup/ultrasonicsensor.h"
#include "spike/hub/battery.h"
#include "spike/hub/button.h"
#include "spike/hub/display.h"
#include "spike/hub/imu.h"
#include "spike/hub/light.h"
#include "spike/hub/speaker.h"
#define TXW(offset) (*(volatile int32_t *)(HAKO_TX_GUEST_BASE + (offset)))
#define TXB(offset) (*(volatile uint8_t *)(HAKO_TX_GUEST_BASE + (offset)))
#define HSV3(c) ({ pup_color_hsv_t c_ = (c); c_.h * 1000000 + c_.s * 1000 + c_.v; })
/* to the nearest ms: the reads around the call take their microseconds (a wait counts from its step) */
#define ELAPSED_MS(call) ({ SYSTIM a_, b_; get_tim(&a_); call; get_tim(&b_); (int)((b_ - a_ + 500) / 1000); })
static pup_device_t *color, *force, *sonar;
static pup_motor_t *ma, *mb, *mc;
"""


def spike_probe(calls: list[str]) -> str:
    lines = "\n".join(f'    syslog(LOG_NOTICE, "= %d", (int)({c}));' for c in calls)
    end = '    syslog(LOG_NOTICE, "done");\n    slp_tsk();\n'
    return f"{PROBE_HEAD}\nvoid main_task(intptr_t unused)\n{{\n{lines}\n{end}}}\n"


def results(log: str) -> list[int]:
    return [int(line.rsplit("= ", 1)[1]) for line in log.splitlines() if "] = " in line]


def test_the_spike_api_reads_and_writes_what_the_sdk_and_libraspike_art_do(tmp_path):
    exe = build(tmp_path / "probe", spike_probe([c for c, _, _ in SPIKE_CALLS]))
    bench = FakePhysics(tmp_path / "run")
    for offset, value in SPIKE_SNAPSHOT.items():
        bench.unity.write_i32(offset, value)
    for offset, values in SPIKE_IMU.items():
        for axis, value in enumerate(values):
            bench.unity.write_f32(offset + 4 * axis, value)
    bench.athrill.write("B", Tx.LED, 0b1100_0000)
    proc = bench.start(exe)
    bench.wakes(proc, 1_500_000)
    log = finish(proc)
    assert "] done" in log
    assert list(zip((c for c, _, _ in SPIKE_CALLS), results(log))) == [(c, want) for c, want, _ in SPIKE_CALLS]
    a = bench.athrill
    assert a.read_i32s(Tx.MOTOR_POWER, 3) == (0, 0, -120)  # A set 0, B stopped, C as last set
    assert a.read_i32s(Tx.MOTOR_BRAKE, 3) == (1, 1, 0)  # EV3_MOTOR_INX_STOP_*: raised on a power of 0
    assert a.read_i32s(Tx.MOTOR_RESET_ANGLE, 3) == (0, 1, 0)  # B's setup reset its count
    assert a.read_i32s(Tx.SPIKE_DIRECTION, 3) == (0, 1, 0)  # B counter-clockwise, for the hub
    assert a.read("B", Tx.LED) == 2  # EV3_GPIO_LED_GREEN
    for line in ("pup_motor_get_device(): port B already has a device",
                 "pup_ultrasonic_sensor_get_device(): port G is not one of the hub's ports A..F",
                 "pup_motor_get_device(): port 0 is not one of the hub's ports A..F",
                 "display: text \"AB\" (100 ms each, 50 ms dark between)", "speaker: tone 440 Hz for 200 ms",
                 "speaker: tone 64 Hz for -1 ms"):
        assert line in log


SPEED_APP = r"""
#include "spikeapi.h"
#include "spike/pup/motor.h"
static void report(pup_motor_t *m)
{
    syslog(LOG_NOTICE, "count %d speed %d power %d stalled %d", (int)pup_motor_get_count(m),
           (int)pup_motor_get_speed(m), (int)pup_motor_get_power(m), (int)pup_motor_is_stalled(m));
}
void main_task(intptr_t unused)
{
    pup_motor_t *m = pup_motor_get_device(PBIO_PORT_ID_A);
    pup_motor_setup(m, DIRECTION, true);
    for (int i = 0; i < 10; i++) {
        pup_motor_set_speed(m, 300); /* every period, as programs do: the reference runs on */
        tslp_tsk(100 * 1000);
        report(m);
    }
    pup_motor_hold(m);
    tslp_tsk(300 * 1000);
    report(m);
    pup_motor_set_power(m, 50);
    for (int i = 0; i < 4; i++) {
        tslp_tsk(100 * 1000);
        report(m);
    }
    slp_tsk();
}
"""
DEG_PER_S_PER_POWER = 16.6  # the default robot's wheels: power 100 is 29 rad/s


def run_motor(bench: FakePhysics, proc: subprocess.Popen, until_us: int, blocked=lambda t_us: False) -> None:
    """Play a motor on port A, as the physics process plays the hub: it turns at DEG_PER_S_PER_POWER x its
    power (none while `blocked`) in the direction the program set it up with, its count is reported in that
    direction, its power as the hub reports it (spike_hub.py), and the encoder reset the SDK asks for is
    done."""
    raw, now = 0.0, 0
    while (wake := bench.next_wake(proc)) <= until_us:
        if bench.athrill.read_i32(Tx.MOTOR_RESET_ANGLE):
            raw = 0.0
            bench.athrill.write_i32(Tx.MOTOR_RESET_ANGLE, 0)
        power = max(-100, min(100, bench.athrill.read_i32(Tx.MOTOR_POWER)))
        direction = bench.athrill.read_i32(Tx.SPIKE_DIRECTION)
        sign = spike_hub.direction_sign(direction)
        if not blocked(now):
            raw += sign * power * DEG_PER_S_PER_POWER * (wake - now) / 1e6
        now = wake
        bench.unity.write_i32(Rx.MOTOR_ANGLE, int(sign * raw))
        bench.unity.write_i32(Rx.SPIKE_MOTOR_POWER, spike_hub.power_report(power, direction))
        bench.answer(wake)


def reports(log: str) -> list[dict[str, int]]:
    return [dict(zip(*[iter(line.split("] ", 1)[1].split())] * 2)) for line in log.splitlines() if "] count " in line]


@pytest.mark.parametrize("direction,sign", [("PUP_DIRECTION_CLOCKWISE", 1), ("PUP_DIRECTION_COUNTERCLOCKWISE", -1)])
def test_set_speed_holds_the_speed_in_degrees_per_second(tmp_path, direction, sign):
    """SPIKE-RT's set_speed (the SDK takes it as a power): 300 deg/s, whatever the power that takes. Count and
    speed are in the program's direction whichever it is (pbio applies the direction to the count: the hub's
    raspike.c process_motor_cmd passes it to pup_motor_setup, motor.c 57-59); get_power, not in power mode, is
    the hub's report (libraspike-art raspike_motor.c 79-85), which SPIKE-RT negates for a counter-clockwise
    motor (spike-rt-hub/drivers/spike/pup/motor.c 120-122); after set_power it is the power set (80-82)."""
    exe = build(tmp_path / "app", SPEED_APP.replace("DIRECTION", direction))
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    run_motor(bench, proc, 2_000_000)
    got = [{k: int(v) for k, v in r.items()} for r in reports(finish(proc))]
    speeds = [r["speed"] for r in got[:10]]
    assert all(abs(s - 300) <= 15 for s in speeds[3:]), speeds  # settled within 0.3 s, within 5%
    assert abs((got[9]["count"] - got[4]["count"]) - 300 * 0.5) <= 3  # 0.5 s at 300 deg/s, to 1%
    # the power that holds 300 deg/s (18), give or take the regulator's last step before the status
    assert all(abs(r["power"] - sign * round(300 / DEG_PER_S_PER_POWER)) <= 1 for r in got[5:10]), got
    held = got[10]
    assert abs(held["count"] - got[9]["count"]) <= 10 and abs(held["speed"]) <= 20  # hold: it stopped
    assert [r["power"] for r in got[11:]] == [50] * 4 and got[14]["speed"] > 0  # set_power: as set, forward
    assert [r["stalled"] for r in got] == [0] * 15


RESET_APP = r"""
#include "spikeapi.h"
#include "spike/pup/motor.h"
void main_task(intptr_t unused)
{
    pup_motor_t *m = pup_motor_get_device(PBIO_PORT_ID_A);
    pup_motor_setup(m, PUP_DIRECTION_CLOCKWISE, false);
    pup_motor_set_power(m, 50);
    tslp_tsk(300 * 1000);
    syslog(LOG_NOTICE, "count %d speed %d", (int)pup_motor_get_count(m), (int)pup_motor_get_speed(m));
    pup_motor_reset_count(m); /* which writes power 0, as the SDK's */
    pup_motor_set_power(m, 50);
    for (int i = 0; i < 3; i++) {
        tslp_tsk(20 * 1000);
        syslog(LOG_NOTICE, "count %d speed %d", (int)pup_motor_get_count(m), (int)pup_motor_get_speed(m));
    }
    pup_motor_reset_count(m); /* stopped by it, so not stalled, though the power set is still 50 */
    tslp_tsk(400 * 1000);
    syslog(LOG_NOTICE, "stalled %d power %d", (int)pup_motor_is_stalled(m), (int)pup_motor_get_power(m));
    slp_tsk();
}
"""


def test_a_count_reset_moves_the_count_but_not_the_speed(tmp_path):
    exe = build(tmp_path / "app", RESET_APP)
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    run_motor(bench, proc, 800_000)
    log = finish(proc)
    got = [{k: int(v) for k, v in r.items()} for r in reports(log)]
    assert "stalled 0 power 50" in log
    full = 50 * DEG_PER_S_PER_POWER
    assert abs(got[0]["count"] - 0.3 * full) <= 2 and all(abs(r["speed"] - full) <= 0.02 * full for r in got)
    assert [abs(r["count"] - k * 0.02 * full) <= 2 for k, r in enumerate(got[1:], 1)] == [True] * 3


BLOCKED_APP = r"""
#include "spikeapi.h"
#include "spike/pup/motor.h"
void main_task(intptr_t unused)
{
    pup_motor_t *m = pup_motor_get_device(PBIO_PORT_ID_A);
    pup_motor_setup(m, PUP_DIRECTION_CLOCKWISE, true);
    DRIVE;
    for (int i = 0; i < 8; i++) {
        tslp_tsk(50 * 1000);
        syslog(LOG_NOTICE, "count %d stalled %d power %d", (int)pup_motor_get_count(m), (int)pup_motor_is_stalled(m),
               (int)pup_motor_get_power(m));
    }
    slp_tsk();
}
"""


@pytest.mark.parametrize("drive,first_stalled_ms", [
    ("pup_motor_set_power(m, 50)", 300),  # driven from 0 ms, blocked from 100 ms: 200 ms still at 300 ms
    ("pup_motor_set_speed(m, 500)", 400),  # the regulator reaches its limit at 170 ms, 50 degrees behind
])
def test_a_blocked_motor_is_stalled_after_200_ms(tmp_path, drive, first_stalled_ms):
    """SPIKE-RT's is_stalled (the SDK's is always false), with Pybricks' tolerances: driven (a power, or a
    regulated motor at its limit) for 200 ms and slower than 20 deg/s over them. The motor is blocked from
    100 ms; the program asks every 50 ms."""
    exe = build(tmp_path / "app", BLOCKED_APP.replace("DRIVE", drive))
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    run_motor(bench, proc, 500_000, blocked=lambda t_us: t_us >= 100_000)
    got = [{k: int(v) for k, v in r.items()} for r in reports(finish(proc))]
    stalled = [r["stalled"] for r in got]  # at 50, 100, .. 400 ms
    assert stalled == [int(ms >= first_stalled_ms) for ms in range(50, 401, 50)], stalled
    if "speed" in drive:
        assert got[-1]["power"] == 100  # at the limit: the reference waits for the motor


STATUS_APP = r"""
#include "spikeapi.h"
#include "spike/pup/colorsensor.h"
#include "spike/pup/motor.h"
void main_task(intptr_t unused)
{
    pup_device_t *color = pup_color_sensor_get_device(PBIO_PORT_ID_E);
    pup_motor_t *m = pup_motor_get_device(PBIO_PORT_ID_A);
    pup_motor_setup(m, PUP_DIRECTION_CLOCKWISE, false);
    for (int i = 0; i < 35; i++) {
        syslog(LOG_NOTICE, "= %d", (int)(pup_color_sensor_reflection(color) * 1000 + pup_motor_get_count(m)));
        dly_tsk(1000);
    }
    slp_tsk();
}
"""


def test_readings_are_the_hubs_status_of_the_last_10_ms(tmp_path):
    """The hub sends its status every 10 ms (the hub's raspike.cfg 11: APP_NOTIFY_CYC, 10*1000, activating the
    task that calls notify_status, raspike.c 923), and libraspike-art's getters return the last one received
    (raspike_internal.h: GET_AND_RET_SENSOR_COMMON, DELAYED_SENSOR_COMMON). A program polling every 1 ms, while
    the reflection and the count change at every physics step, reads each status ten times. Its first reading
    waits for the status that carries the reflection: the one at 20 ms (test below)."""
    exe = build(tmp_path / "app", STATUS_APP)
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    while (wake := bench.next_wake(proc)) <= 60_000:
        ms = wake // 1000
        bench.unity.write_i32(Rx.COLOR0_REFLECT, ms)
        bench.unity.write_i32(Rx.MOTOR_ANGLE, ms)
        bench.answer(wake)
    got = results(finish(proc))
    assert got == [(ms // 10 * 10) * 1001 for ms in range(20, 55)], got


MODES_APP = r"""
#include "spikeapi.h"
#include "spike/pup/colorsensor.h"
static void at(const char *what)
{
    SYSTIM now;
    get_tim(&now);
    syslog(LOG_NOTICE, "%s = %d", what, (int)(now / 1000));
}
void main_task(intptr_t unused)
{
    pup_device_t *color = pup_color_sensor_get_device(PBIO_PORT_ID_E);
    pup_color_sensor_reflection(color);
    at("reflection");
    pup_color_sensor_rgb(color);
    at("rgb");
    pup_color_sensor_rgb(color);
    at("rgb again");
    dly_tsk(5000);
    pup_color_sensor_hsv(color, true);
    at("hsv");
    pup_color_sensor_hsv(color, false);
    at("hsv, surface false");
    pup_color_sensor_color(color, false);
    pup_color_sensor_color(color, true);
    at("colour, either surface");
    slp_tsk();
}
"""


def test_a_reading_of_another_kind_waits_for_the_status_that_carries_it(tmp_path):
    """libraspike-art reads the colour sensor from the status, which carries one reading a port at a time
    (raspike_internal.h 47-52); another reading it asks the hub for and waits until a status carries it
    (raspike_protocol.c 401-414). Its commands wait in a buffer from the handshake on (176) until the next status
    comes in (333), and the hub takes the new reading up at its following status (raspike.c 325-330): a switch
    asked for at a status instant is answered 20 ms later, one asked for 5 ms after it 15 ms later. The same
    reading again, or `color` for the other surface (libraspike-art asks RP_CMD_ID_COL_COL for both), does not
    wait; HSV for the other surface does. As under --emulator raspike-art (tests/athrill/test_raspike_art_trial.py)."""
    exe = build(tmp_path / "app", MODES_APP)
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    bench.wakes(proc, until_us=200_000)
    log = finish(proc)
    got = {line.split("] ", 1)[1].rsplit(" = ", 1)[0]: int(line.rsplit(" = ", 1)[1])
           for line in log.splitlines() if " = " in line}
    assert got == {"reflection": 20, "rgb": 40, "rgb again": 40, "hsv": 60, "hsv, surface false": 80,
                   "colour, either surface": 100}, log


SAMPLE = "sample_c5_spike"
SAMPLE_COPIES = {"raspike-art-samples": ART_SAMPLES / SAMPLE, "the SDK's workspace": SDK_SAMPLES / SAMPLE}


def sample_copy(tmp_path, where: str):
    if not SAMPLE_COPIES[where].is_dir():
        pytest.skip(NEEDS_RASPIKE)
    return shutil.copytree(SAMPLE_COPIES[where], tmp_path / SAMPLE)


def sample_powers(reflection: int) -> tuple[int, int]:
    """The TX powers of ports A and B that sample_c5_spike's tracer_task writes for a reflection, computed as
    its C does (LineTracer.c, LineTracer.h): right motor A, left motor B, each as the program sets it
    (libraspike-art raspike_motor.c 107 sends the power as set; the hub applies B's counter-clockwise)."""
    steering = int(numpy.float32((40 + 10) // 2 - reflection) * numpy.float32(1.5))  # (int16_t)(float32 * 1.5F)
    left, right = 30 + steering, 30 - steering
    return right, left


@pytest.mark.parametrize("where", sorted(SAMPLE_COPIES))
def test_sample_c5_spike_waits_for_the_force_sensor_then_traces(tmp_path, where):
    """Unmodified, natively: it polls the force sensor (the SDK's EV3 touch slot 0) every 10 ms and writes no
    motor; after the press it sets its motors up (encoder resets of A and B) and every 100 ms writes the
    powers LineTracer.c computes from the reflection."""
    exe = build_app(sample_copy(tmp_path, where))
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    press_us, reflections = 200_000, {300_000: 12, 400_000: 25, 500_000: 38, 600_000: 0}
    for wake in range(10_000, press_us + 1, 10_000):  # dly_tsk(10 ms) until touched
        assert bench.next_wake(proc) == wake
        assert bench.athrill.read_i32s(Tx.MOTOR_POWER, 4) == (0, 0, 0, 0)
        if wake == press_us:
            bench.unity.write_i32(Rx.TOUCH0, TOUCH_PRESSED)
            bench.unity.write_i32(Rx.COLOR0_REFLECT, 20)
        bench.answer(wake)
    seen = {}
    while (wake := bench.next_wake(proc)) <= 700_000:
        seen[wake] = bench.athrill.read_i32s(Tx.MOTOR_POWER, 4)
        if wake in reflections:
            bench.unity.write_i32(Rx.COLOR0_REFLECT, reflections[wake])
        bench.answer(wake)
    out = finish(proc, stdout=True)
    assert "Press force sensor to start" in out and "Start Line Trace!!" in out
    assert bench.athrill.read_i32s(Tx.MOTOR_RESET_ANGLE, 4) == (1, 1, 0, 0)  # pup_motor_setup(.., true)
    # The tracer runs at the press (200 ms) and every 100 ms after, and the hub's status wakes the program
    # every 10 ms (status.c): what the tracer wrote is what the program has published at the next wake. Its
    # first reading waits for the status that carries the reflection, at 220 ms (status.c, spike_status_await).
    assert sorted(seen) == list(range(210_000, 700_001, 10_000))
    for at, reflection in ((220_000, 20), (300_000, 12), (400_000, 25), (500_000, 38), (600_000, 0)):
        assert seen[at + 10_000][:2] == sample_powers(reflection), at
    assert bench.athrill.read_i32s(Tx.MOTOR_BRAKE, 4) == (0, 0, 0, 0)  # no power was 0


NULL_MOTOR_APP = r"""
#include "spikeapi.h"
#include "spike/pup/motor.h"
void main_task(intptr_t unused)
{
    pup_motor_t *left = pup_motor_get_device(PBIO_PORT_ID_B);
    pup_motor_t *again = pup_motor_get_device(PBIO_PORT_ID_B);
    syslog(LOG_NOTICE, "got %d then %d", left != NULL, again != NULL);
    pup_motor_set_power(again, 30);
}
"""


def test_a_motor_on_a_port_without_one_is_null_and_using_it_is_a_crash(tmp_path):
    """A second get_device of a port gives NULL (the SDK's error value), logged as SPIKE-RT logs it; using
    the NULL motor, which the SDK dereferences, crashes the program with a line saying why."""
    exe = build(tmp_path / "app", NULL_MOTOR_APP)
    proc = FakePhysics(tmp_path / "run").start(exe)
    assert proc.wait(timeout=10) == -signal.SIGABRT
    log = finish(proc)
    assert "pup_motor_get_device(): port B already has a device" in log and "got 1 then 0" in log
    assert "pup_motor_set_power(): the motor is NULL (pup_motor_get_device found no free port)" in log


PRESS_FIRST_TOUCH_SLOT = '[[press]]\nsensor = "touch"\nport = 3\nat_s = 1.0\nfor_s = 0.2\n'  # default robot: slot 0


def trial(tmp_path, app, *args: str) -> tuple[dict, str]:
    out = hako("try", "--app", str(app), "--json", "--noise", "0", "--run-dir", str(tmp_path / "run"), *args)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout), (tmp_path / "run" / "athrill.log").read_text()


@pytest.mark.slow
@pytest.mark.parametrize("where", sorted(SAMPLE_COPIES))
def test_sample_c5_spike_starts_on_a_press_and_drives(tmp_path, where):
    """On the default robot it cannot trace (HackSPi's wiring is not the default robot's), but it must start
    on a scenario press of the touch slot the SDK reads the force sensor from, and drive."""
    app = sample_copy(tmp_path, where)
    (tmp_path / "press.toml").write_text(PRESS_FIRST_TOUCH_SLOT)
    result, log = trial(tmp_path, app, "--scenario", str(tmp_path / "press.toml"), "--time-limit", "5")
    assert result["event"] != "CRASH" and result["distance_m"] > 0.2, log
    assert "Press force sensor to start" in log and "Start Line Trace!!" in log


@pytest.mark.slow
def test_sample_c5_spike_without_a_press_waits(tmp_path):
    result, log = trial(tmp_path, sample_copy(tmp_path, "raspike-art-samples"), "--time-limit", "3")
    assert (result["event"], result["distance_m"]) == ("TIME_OVER", 0.0)
    assert "Press force sensor to start" in log and "Start Line Trace!!" not in log


@pytest.mark.slow
def test_sample_c5_runs_natively(tmp_path):
    """RasPike's EV3RT-API sample (float32_t and all) on HackEV's wiring, which is the sample's."""
    if not (ART_SAMPLES / "sample_c5").is_dir():
        pytest.skip(NEEDS_RASPIKE)
    app = shutil.copytree(ART_SAMPLES / "sample_c5", tmp_path / "sample_c5")
    result, log = trial(tmp_path, app, "--robot", "hackev", "--time-limit", "5")
    assert result["event"] != "CRASH" and result["distance_m"] > 1.0, log
    assert "Start Line Trace!!" in log


@pytest.mark.slow
def test_sample_c5_spike_natively_drives_as_the_sdks_image_in_the_real_emulator(tmp_path, repeatable_athrill2):
    """The same unmodified sample, built natively and built with ET Robocon's SDK into a v850 image for the
    repeatable athrill2, on the same robot and press: the same event and distance (within 2%)."""
    from athrill_sim.v850.toolchain import find_tools

    need_v850_tools()
    app = sample_copy(tmp_path, "raspike-art-samples")
    gcc = find_tools().gcc  # EV3RT's toolchain: the SPIKE SDK has none beside it
    built = hako("build", str(app), "--sdk", str(SDK), "--toolchain", str(gcc.parent), timeout=900)
    assert built.returncode == 0, built.stderr
    (tmp_path / "press.toml").write_text(PRESS_FIRST_TOUCH_SLOT)
    args = ("--scenario", str(tmp_path / "press.toml"), "--time-limit", "5")
    native, _ = trial(tmp_path / "native", app, *args)
    real, log = trial(tmp_path / "real", built.stdout.strip(), "--athrill2", str(repeatable_athrill2), *args)
    assert real["sync"] == "repeatable" and "Start Line Trace!!" in log
    assert native["event"] == real["event"] and native["event"] != "CRASH"
    assert native["distance_m"] == pytest.approx(real["distance_m"], rel=0.02)


@pytest.mark.parametrize("makefile,header,spike", [
    ("USE_RASPIKE_ART=1\n", '#include "ev3api.h"\n', True),
    ("", '#include "spikeapi.h"\n', True),
    ("", "#include <pbio/port.h>\n", True),
    ("", '#include "ev3api.h"\n', False),
    ("ifdef USE_RASPIKE_ART\nAPPL_COBJS += x.o\nendif\n", '#include "ev3api.h"\n', False),
])
def test_a_spike_program_is_one_that_says_so_in_makefile_inc_or_includes_a_spike_header(tmp_path, makefile,
                                                                                      header, spike):
    from athrill_sim.native.workspace import find_app

    (tmp_path / "Makefile.inc").write_text(makefile)
    (tmp_path / "app.h").write_text(header)
    (tmp_path / "app.c").write_text('#include "app.h"\n')
    app = find_app(tmp_path)
    assert app.spike == spike and ("-DUSE_RASPIKE_ART" in app.defines) == spike


def test_motor_c_measures_speed_and_stall_with_spike_hubs_constants():
    """The native runtime computes the speed and the stall in C (motor.c), the hub on a pty with
    spike_hub.speed_over and spike_hub.stalled: the window and the stall tolerances must be the same."""
    from athrill_sim.native.build import RUNTIME

    text = (RUNTIME / "spike" / "src" / "motor.c").read_text()
    defined = {m[1]: int(m[2]) for m in re.finditer(r"^#define (\w+) (\d+)\b", text, re.M)}
    assert {name: defined.get(name) for name in ("SPEED_WINDOW_US", "STALL_SPEED_DPS", "STALL_TIME_US")} == {
        "SPEED_WINDOW_US": spike_hub.SPEED_WINDOW_US, "STALL_SPEED_DPS": spike_hub.STALL_SPEED_DPS,
        "STALL_TIME_US": spike_hub.STALL_TIME_US}
