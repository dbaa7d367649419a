"""The native runtime on its own: its lockstep, guest windows, scheduler and EV3RT API, against files played
by a stand-in for the physics process (no MuJoCo), and the API checked call for call against the Python mock."""

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from athrill_sim.mock.bus import MemoryBus
from athrill_sim.mock.ev3api import (
    COLOR_SENSOR,
    ENTER_BUTTON,
    EV3_FONT_MEDIUM,
    EV3_FONT_SMALL,
    EV3_LCD_BLACK,
    EV3_LCD_WHITE,
    EV3_PORT_1,
    EV3_PORT_2,
    EV3_PORT_3,
    EV3_PORT_4,
    EV3_PORT_A,
    EV3_PORT_B,
    EV3_PORT_C,
    EV3_PORT_D,
    EV3_SERIAL_BT,
    GYRO_SENSOR,
    LARGE_MOTOR,
    LED_ORANGE,
    LEFT_BUTTON,
    MEDIUM_MOTOR,
    TOUCH_SENSOR,
    ULTRASONIC_SENSOR,
    Ev3Api,
    FileInfo,
    MemFile,
    RgbRaw,
)
from athrill_sim.mock.kernel import Kernel
from hakoniwa.wire.exits import EXIT_BENCH_FAULT
from hakoniwa.wire.protocol import ATHRILL_FILE, NEVER_WAKES, UNITY_FILE, Rx, Tx
from hakoniwa.wire.rundir import LCD_LOG, SDCARD_DIR, SERIAL_INPUT, SERIAL_LOG
from tests.helpers.native_fixtures import FakePhysics, build, finish
from tests.helpers.waiting import wait_until

# (C expression, the same call on the Python mock): run in this order by both, every result logged.
API_CALLS = [
    ("ev3_color_sensor_get_reflect(EV3_PORT_1)", lambda a: a.ev3_color_sensor_get_reflect(EV3_PORT_1)),
    ("ev3_sensor_config(EV3_PORT_1, COLOR_SENSOR)", lambda a: a.ev3_sensor_config(EV3_PORT_1, COLOR_SENSOR)),
    ("ev3_sensor_config(9, COLOR_SENSOR)", lambda a: a.ev3_sensor_config(9, COLOR_SENSOR)),
    ("ev3_color_sensor_get_reflect(EV3_PORT_1)", lambda a: a.ev3_color_sensor_get_reflect(EV3_PORT_1)),
    ("ev3_color_sensor_get_ambient(EV3_PORT_1)", lambda a: a.ev3_color_sensor_get_ambient(EV3_PORT_1)),
    ("ev3_color_sensor_get_color(EV3_PORT_1)", lambda a: a.ev3_color_sensor_get_color(EV3_PORT_1)),
    ("({ rgb_raw_t v; ev3_color_sensor_get_rgb_raw(EV3_PORT_1, &v); v.r; })", lambda a: rgb(a, EV3_PORT_1).r),
    ("({ rgb_raw_t v; ev3_color_sensor_get_rgb_raw(EV3_PORT_1, &v); v.g; })", lambda a: rgb(a, EV3_PORT_1).g),
    # Left alone on an error (ev3api_sensor.c returns before uart_sensor_fetch_data).
    ("({ rgb_raw_t v = {7, 8, 9}; ev3_color_sensor_get_rgb_raw(EV3_PORT_2, &v); v.r * 100 + v.b; })",
     lambda a: (v := rgb(a, EV3_PORT_2, RgbRaw(7, 8, 9))).r * 100 + v.b),
    ("ev3_ultrasonic_sensor_get_distance(EV3_PORT_2)", lambda a: a.ev3_ultrasonic_sensor_get_distance(EV3_PORT_2)),
    ("ev3_sensor_config(EV3_PORT_2, ULTRASONIC_SENSOR)", lambda a: a.ev3_sensor_config(EV3_PORT_2, ULTRASONIC_SENSOR)),
    ("ev3_ultrasonic_sensor_get_distance(EV3_PORT_2)", lambda a: a.ev3_ultrasonic_sensor_get_distance(EV3_PORT_2)),
    ("ev3_sensor_config(EV3_PORT_3, GYRO_SENSOR)", lambda a: a.ev3_sensor_config(EV3_PORT_3, GYRO_SENSOR)),
    ("ev3_gyro_sensor_get_angle(EV3_PORT_3)", lambda a: a.ev3_gyro_sensor_get_angle(EV3_PORT_3)),
    ("ev3_gyro_sensor_get_rate(EV3_PORT_3)", lambda a: a.ev3_gyro_sensor_get_rate(EV3_PORT_3)),
    ("ev3_gyro_sensor_reset(EV3_PORT_3)", lambda a: a.ev3_gyro_sensor_reset(EV3_PORT_3)),
    ("ev3_gyro_sensor_get_angle(EV3_PORT_3)", lambda a: a.ev3_gyro_sensor_get_angle(EV3_PORT_3)),
    ("ev3_gyro_sensor_reset(EV3_PORT_2)", lambda a: a.ev3_gyro_sensor_reset(EV3_PORT_2)),
    # A second colour sensor reads slot 1, a third slot 0 again (ev3_vdev.h's switch on the index).
    ("ev3_sensor_config(EV3_PORT_2, COLOR_SENSOR)", lambda a: a.ev3_sensor_config(EV3_PORT_2, COLOR_SENSOR)),
    ("ev3_color_sensor_get_reflect(EV3_PORT_2)", lambda a: a.ev3_color_sensor_get_reflect(EV3_PORT_2)),
    ("({ rgb_raw_t v; ev3_color_sensor_get_rgb_raw(EV3_PORT_2, &v); v.b; })", lambda a: rgb(a, EV3_PORT_2).b),
    ("ev3_sensor_config(EV3_PORT_3, COLOR_SENSOR)", lambda a: a.ev3_sensor_config(EV3_PORT_3, COLOR_SENSOR)),
    ("ev3_color_sensor_get_reflect(EV3_PORT_3)", lambda a: a.ev3_color_sensor_get_reflect(EV3_PORT_3)),
    ("ev3_sensor_config(EV3_PORT_2, ULTRASONIC_SENSOR)", lambda a: a.ev3_sensor_config(EV3_PORT_2, ULTRASONIC_SENSOR)),
    ("ev3_sensor_config(EV3_PORT_3, GYRO_SENSOR)", lambda a: a.ev3_sensor_config(EV3_PORT_3, GYRO_SENSOR)),
    ("ev3_sensor_config(EV3_PORT_4, TOUCH_SENSOR)", lambda a: a.ev3_sensor_config(EV3_PORT_4, TOUCH_SENSOR)),
    ("ev3_touch_sensor_is_pressed(EV3_PORT_4)", lambda a: a.ev3_touch_sensor_is_pressed(EV3_PORT_4)),
    ("ev3_touch_sensor_is_pressed(EV3_PORT_3)", lambda a: a.ev3_touch_sensor_is_pressed(EV3_PORT_3)),
    ("ev3_sensor_get_type(EV3_PORT_2)", lambda a: a.ev3_sensor_get_type(EV3_PORT_2)),
    ("ev3_sensor_get_type(7)", lambda a: a.ev3_sensor_get_type(7)),
    ("ev3_button_is_pressed(ENTER_BUTTON)", lambda a: a.ev3_button_is_pressed(ENTER_BUTTON)),
    ("ev3_button_is_pressed(LEFT_BUTTON)", lambda a: a.ev3_button_is_pressed(LEFT_BUTTON)),
    ("ev3_button_is_pressed(9)", lambda a: a.ev3_button_is_pressed(9)),
    ("ev3_motor_get_counts(EV3_PORT_B)", lambda a: a.ev3_motor_get_counts(EV3_PORT_B)),
    ("ev3_motor_config(EV3_PORT_A, LARGE_MOTOR)", lambda a: a.ev3_motor_config(EV3_PORT_A, LARGE_MOTOR)),
    ("ev3_motor_config(EV3_PORT_B, LARGE_MOTOR)", lambda a: a.ev3_motor_config(EV3_PORT_B, LARGE_MOTOR)),
    ("ev3_motor_config(EV3_PORT_C, 7)", lambda a: a.ev3_motor_config(EV3_PORT_C, 7)),
    ("ev3_motor_config(5, LARGE_MOTOR)", lambda a: a.ev3_motor_config(5, LARGE_MOTOR)),
    ("ev3_motor_get_type(EV3_PORT_B)", lambda a: a.ev3_motor_get_type(EV3_PORT_B)),
    ("ev3_motor_get_counts(EV3_PORT_B)", lambda a: a.ev3_motor_get_counts(EV3_PORT_B)),
    ("ev3_motor_reset_counts(EV3_PORT_B)", lambda a: a.ev3_motor_reset_counts(EV3_PORT_B)),
    ("ev3_motor_reset_counts(EV3_PORT_D)", lambda a: a.ev3_motor_reset_counts(EV3_PORT_D)),
    ("ev3_motor_set_power(EV3_PORT_B, 250)", lambda a: a.ev3_motor_set_power(EV3_PORT_B, 250)),
    ("ev3_motor_get_power(EV3_PORT_B)", lambda a: a.ev3_motor_get_power(EV3_PORT_B)),
    ("ev3_motor_set_power(EV3_PORT_D, 10)", lambda a: a.ev3_motor_set_power(EV3_PORT_D, 10)),
    ("ev3_motor_set_power(EV3_PORT_A, -101)", lambda a: a.ev3_motor_set_power(EV3_PORT_A, -101)),
    ("ev3_motor_get_power(EV3_PORT_D)", lambda a: a.ev3_motor_get_power(EV3_PORT_D)),
    ("ev3_motor_rotate(EV3_PORT_A, 90, 30, true)", lambda a: a.ev3_motor_rotate(EV3_PORT_A, 90, 30, True)),
    ("ev3_motor_steer(EV3_PORT_A, EV3_PORT_B, 15, -33)", lambda a: a.ev3_motor_steer(EV3_PORT_A, EV3_PORT_B, 15, -33)),
    ("ev3_motor_steer(EV3_PORT_A, EV3_PORT_B, 20, 101)", lambda a: a.ev3_motor_steer(EV3_PORT_A, EV3_PORT_B, 20, 101)),
    ("ev3_motor_steer(EV3_PORT_A, EV3_PORT_B, -150, 77)",
     lambda a: a.ev3_motor_steer(EV3_PORT_A, EV3_PORT_B, -150, 77)),
    ("ev3_motor_steer(EV3_PORT_A, EV3_PORT_B, 15, 0)", lambda a: a.ev3_motor_steer(EV3_PORT_A, EV3_PORT_B, 15, 0)),
    ("ev3_motor_steer(EV3_PORT_A, EV3_PORT_D, 20, 0)", lambda a: a.ev3_motor_steer(EV3_PORT_A, EV3_PORT_D, 20, 0)),
    ("ev3_motor_stop(EV3_PORT_B, true)", lambda a: a.ev3_motor_stop(EV3_PORT_B, True)),
    ("ev3_motor_reset_counts(EV3_PORT_D)", lambda a: a.ev3_motor_reset_counts(EV3_PORT_D)),
    ("ev3_motor_config(EV3_PORT_D, MEDIUM_MOTOR)", lambda a: a.ev3_motor_config(EV3_PORT_D, MEDIUM_MOTOR)),
    ("ev3_motor_reset_counts(EV3_PORT_D)", lambda a: a.ev3_motor_reset_counts(EV3_PORT_D)),
    ("ev3_motor_set_power(EV3_PORT_D, 55)", lambda a: a.ev3_motor_set_power(EV3_PORT_D, 55)),
    ("ev3_motor_config(EV3_PORT_D, MEDIUM_MOTOR)", lambda a: a.ev3_motor_config(EV3_PORT_D, MEDIUM_MOTOR)),
    ("ev3_motor_get_power(EV3_PORT_D)", lambda a: a.ev3_motor_get_power(EV3_PORT_D)),
    ("ev3_motor_stop(EV3_PORT_A, 258)", lambda a: a.ev3_motor_stop(EV3_PORT_A, 258)),
    ("ev3_led_set_color(LED_ORANGE)", lambda a: a.ev3_led_set_color(LED_ORANGE)),
    ("ev3_led_set_color(9)", lambda a: a.ev3_led_set_color(9)),
    ("ev3_battery_voltage_mV()", lambda a: a.ev3_battery_voltage_mV()),
    ("ev3_battery_current_mA()", lambda a: a.ev3_battery_current_mA()),
    ("ev3_speaker_set_volume(300)", lambda a: a.ev3_speaker_set_volume(300)),
    ("ev3_speaker_play_tone(NOTE_C4, 250)", lambda a: a.ev3_speaker_play_tone(261.63, 250)),
    ("ev3_speaker_play_file(NULL, 10)", lambda a: a.ev3_speaker_play_file(None, 10)),
    ("ev3_speaker_stop()", lambda a: a.ev3_speaker_stop()),
    ("ev3_button_set_on_clicked(9, NULL, 0)", lambda a: a.ev3_button_set_on_clicked(9, None, 0)),
    ("ev3_lcd_set_font(EV3_FONT_MEDIUM)", lambda a: a.ev3_lcd_set_font(EV3_FONT_MEDIUM)),
    ("ev3_lcd_set_font(5)", lambda a: a.ev3_lcd_set_font(5)),
    ("({ int32_t w = 0, h = 0; ev3_font_get_size(EV3_FONT_SMALL, &w, &h); w * 100 + h; })",
     lambda a: (s := a.ev3_font_get_size(EV3_FONT_SMALL))[1] * 100 + s[2]),
    ("ev3_font_get_size(3, NULL, NULL)", lambda a: a.ev3_font_get_size(3)[0]),
    ('ev3_lcd_draw_string("Kp\\nready", 4, 20)', lambda a: a.ev3_lcd_draw_string("Kp\nready", 4, 20)),
    ("ev3_lcd_draw_line(0, 127, 177, 0)", lambda a: a.ev3_lcd_draw_line(0, 127, 177, 0)),
    ("ev3_lcd_fill_rect(1, 2, 30, 40, EV3_LCD_BLACK)", lambda a: a.ev3_lcd_fill_rect(1, 2, 30, 40, EV3_LCD_BLACK)),
    ("ev3_lcd_fill_rect(1, 2, 3, 4, EV3_LCD_WHITE)", lambda a: a.ev3_lcd_fill_rect(1, 2, 3, 4, EV3_LCD_WHITE)),
    ("({ memfile_t m; ER e = ev3_memfile_load(\"data.bin\", &m); e * 1000 + (int)m.filesz; })",
     lambda a: a.ev3_memfile_load("data.bin", m := MemFile()) * 1000 + m.filesz),
    ('({ memfile_t m; ev3_memfile_load("missing.bin", &m); })', lambda a: a.ev3_memfile_load("missing.bin", MemFile())),
    ("ev3_memfile_load(NULL, NULL)", lambda a: a.ev3_memfile_load(None, None)),
    ("ev3_memfile_free(NULL)", lambda a: a.ev3_memfile_free(None)),
    ('({ memfile_t m; ev3_memfile_load("data.bin", &m); ev3_memfile_free(&m); ev3_memfile_free(&m); })',
     lambda a: (a.ev3_memfile_load("data.bin", m := MemFile()), a.ev3_memfile_free(m), a.ev3_memfile_free(m))[2]),
    ('ev3_sdcard_opendir("logs")', lambda a: a.ev3_sdcard_opendir("logs")),
    ('({ fileinfo_t f; ev3_sdcard_readdir(1, &f); f.size * 10 + f.is_dir; })',
     lambda a: (a.ev3_sdcard_readdir(1, f := FileInfo()), f.size * 10 + f.is_dir)[1]),
    ("({ fileinfo_t f; ev3_sdcard_readdir(1, &f); })", lambda a: a.ev3_sdcard_readdir(1, FileInfo())),
    ("ev3_sdcard_closedir(1)", lambda a: a.ev3_sdcard_closedir(1)),
    ("ev3_sdcard_closedir(1)", lambda a: a.ev3_sdcard_closedir(1)),
    ('ev3_sdcard_opendir("nowhere")', lambda a: a.ev3_sdcard_opendir("nowhere")),
    ("ev3_serial_open_file(5) == NULL", lambda a: a.ev3_serial_open_file(5) is None),
    ('({ fputs("hello bt\\n", ev3_serial_open_file(EV3_SERIAL_BT)); 9; })',
     lambda a: a.ev3_serial_open_file(EV3_SERIAL_BT).write("hello bt\n")),
    ("fgetc(ev3_serial_open_file(EV3_SERIAL_BT))", lambda a: a.ev3_serial_open_file(EV3_SERIAL_BT).read(1)[0]),
    ("fgetc(ev3_serial_open_file(EV3_SERIAL_BT))", lambda a: a.ev3_serial_open_file(EV3_SERIAL_BT).read(1)[0]),
    ("ev3_bluetooth_is_connected()", lambda a: a.ev3_bluetooth_is_connected()),
]


def rgb(api: Ev3Api, port: int, val: RgbRaw | None = None) -> RgbRaw:
    val = val or RgbRaw()
    api.ev3_color_sensor_get_rgb_raw(port, val)
    return val



SENSORS = {Rx.COLOR1_REFLECT: 0x0111, Rx.COLOR1_RGB + 8: 0x0002_0304, Rx.BATTERY_VOLTAGE: 7900,
           Rx.BATTERY_CURRENT: 140, Rx.COLOR0_REFLECT: 0x1234_0049, Rx.COLOR0_AMBIENT: 0x0105, Rx.COLOR0_COLOR: 6,
           Rx.COLOR0_RGB: 0x0001_0203, Rx.COLOR0_RGB + 4: 0x0001_FFFF, Rx.GYRO_ANGLE: -90, Rx.GYRO_RATE: 0x0001_FFFF,
           Rx.ULTRASONIC_MM: 427, Rx.TOUCH0: 4095, Rx.BUTTONS: 1 << ENTER_BUTTON,
           Rx.MOTOR_ANGLE + 4 * EV3_PORT_B: 530}
ACTUATORS = (0, Tx.GYRO_RESET + 4)
LED_OTHER_BITS = 0b1100_0100  # YELLOW and bits above: EV3RT's read-modify-write of RED and GREEN keeps them
SERIAL_INPUT_LINES = "0 bt 6f6b\n0 uart 7a\n"  # as Scenario.serial_lines writes it: "ok" on bt, "z" on the UART


def prepare(side: FakePhysics) -> None:
    """The same snapshot, LED byte, SD card and serial input for both runtimes."""
    for offset, value in SENSORS.items():
        side.unity.write_i32(offset, value)
    side.athrill.write("B", Tx.LED, LED_OTHER_BITS)
    (side.run_dir / SDCARD_DIR / "logs").mkdir(parents=True)
    (side.run_dir / SDCARD_DIR / "data.bin").write_bytes(bytes(range(37)))
    (side.run_dir / SDCARD_DIR / "logs" / "run1.txt").write_text("12345")
    (side.run_dir / SERIAL_INPUT).write_text(SERIAL_INPUT_LINES)


def api_probe_source() -> str:
    calls = "\n".join(f'    syslog(LOG_NOTICE, "= %d", (int)({c}));' for c, _ in API_CALLS)
    return f'#include "ev3api.h"\n\nvoid main_task(intptr_t unused)\n{{\n{calls}\n    tslp_tsk(1000);\n}}\n'


def test_the_api_answers_and_writes_exactly_as_the_python_mock(tmp_path, capsys):
    exe = build(tmp_path / "probe", api_probe_source())
    native, mock = FakePhysics(tmp_path / "native"), FakePhysics(tmp_path / "mock")
    for side in (native, mock):
        prepare(side)
    proc = native.start(exe)
    assert native.next_wake(proc) == 1000
    native_log = finish(proc)

    bus = MemoryBus(mock.run_dir)
    api = Ev3Api(bus, Kernel(bus.unity, bus.athrill))
    for _, call in API_CALLS:
        api.syslog(f"= {int(call(api))}")
    assert native_log.splitlines() == capsys.readouterr().err.splitlines()
    assert native.athrill.read_i32s(*ACTUATORS) == mock.athrill.read_i32s(*ACTUATORS)
    for name in (LCD_LOG, SERIAL_LOG.format(port="bt")):
        assert (native.run_dir / name).read_bytes() == (mock.run_dir / name).read_bytes(), name
    bus.close()
    # Values from EV3RT's source, not from either runtime:
    a = native.athrill
    assert a.read("B", Tx.LED) == LED_OTHER_BITS | 0b01  # 9 = 0b1001: RED set, GREEN cleared (gpio_set_value)
    assert a.read_i32(Tx.MOTOR_BRAKE + 4 * EV3_PORT_B) == 1
    assert a.read_i32(Tx.MOTOR_BRAKE + 4 * EV3_PORT_A) == 2  # (char)258: opOUTPUT_STOP's buf[2] = brake
    assert a.read_i32(Tx.MOTOR_RESET_ANGLE + 4 * EV3_PORT_D) == 1  # TX 48, motor_clr_angle's port + 8
    assert a.read_i32(Tx.MOTOR_POWER + 4 * EV3_PORT_D) == 0  # motor_config's opOUTPUT_STOP zeroes it
    results = [int(line.rsplit("= ", 1)[1]) for line in native_log.splitlines() if "] = " in line]
    said = dict(zip((c for c, _ in API_CALLS), results))  # the last result of each expression
    assert said["ev3_motor_get_power(EV3_PORT_D)"] == 55  # motor_power[], which config leaves alone
    assert said["ev3_led_set_color(9)"] == 0  # never E_PAR: only the RED and GREEN bits are looked at
    assert said["ev3_color_sensor_get_reflect(EV3_PORT_2)"] == 0x11  # colour slot 1 (RX 136), low byte
    assert said["ev3_color_sensor_get_reflect(EV3_PORT_3)"] == 0x49  # a third one: slot 0 again
    assert said["ev3_battery_voltage_mV()"] == 7900  # RX 120, EV3_BATTERY_INX_VOLTAGE
    assert "API ev3_memfile_load() warning: Path 'missing.bin' is invalid." in native_log  # API_WARN


WINDOWS_APP = r'''
#include "ev3api.h"
#define REFLECT (*(volatile int32_t *)(0x090F0000 + 12))

void main_task(intptr_t unused)
{
    ev3_motor_config(EV3_PORT_B, LARGE_MOTOR);
    syslog(LOG_NOTICE, "Kp %.3f reflect %d", *(volatile float *)(0x090F0000 + 540), (int)REFLECT);
    ev3_motor_reset_counts(EV3_PORT_B);
    *(volatile int32_t *)(0x090F1000 + 800) = 1234;
    tslp_tsk(2500);
    syslog(LOG_NOTICE, "reflect %d at %d us", (int)REFLECT, (int)({ SYSTIM t; get_tim(&t); t; }));
    ev3_motor_set_power(EV3_PORT_B, 42);
    tslp_tsk(1000);
}
'''


def test_raw_guest_addresses_see_the_files_and_untouched_bytes_are_never_written_back(tmp_path):
    exe = build(tmp_path / "app", WINDOWS_APP)
    bench = FakePhysics(tmp_path / "run")
    bench.unity.write_f32(Rx.KP, 1.539)
    bench.unity.write_i32(Rx.COLOR0_REFLECT, 60)
    proc = bench.start(exe)
    assert bench.next_wake(proc) == 3000  # 2.5 ms, rounded up to whole physics steps
    a = bench.athrill
    assert a.read_u32(Tx.ATHRILL_PID) == proc.pid
    assert a.read_i32(Tx.MOTOR_RESET_ANGLE + 4 * EV3_PORT_B) == 1
    assert a.read_i32(800) == 1234
    a.write_i32(Tx.MOTOR_RESET_ANGLE + 4 * EV3_PORT_B, 0)  # the physics process applies and clears the flag
    a.write_i32(Tx.START, 1)  # the controller, meanwhile
    bench.unity.write_i32(Rx.COLOR0_REFLECT, 77)  # the next snapshot
    bench.unity.unity_time_us = 3000
    assert bench.next_wake(proc) == 4000
    assert a.read_i32(Tx.MOTOR_RESET_ANGLE + 4 * EV3_PORT_B) == 0  # not written back: the program left it
    assert a.read_i32(Tx.START) == 1
    assert a.read_i32(Tx.MOTOR_POWER + 4 * EV3_PORT_B) == 42 and a.read_i32(800) == 1234
    assert a.athrill_time_us == 3000 and a.unity_time_us == 3000
    log = finish(proc)
    assert "Kp 1.539 reflect 60" in log and "reflect 77 at 3000 us" in log


@pytest.mark.parametrize("address", ["0x090F2000", "0x090EFFFC", "0x08000000"])
def test_a_read_outside_the_windows_is_a_segfault(tmp_path, address):
    source = f'#include "ev3api.h"\nvoid main_task(intptr_t u) {{ syslog(LOG_NOTICE, "%d", ' \
             f'*(volatile int *)({address})); }}\n'
    exe = build(tmp_path / "app", source)
    proc = FakePhysics(tmp_path / "run").start(exe)
    assert proc.wait(timeout=10) == -signal.SIGSEGV


def test_unusable_files_are_a_bench_fault(tmp_path):
    exe = build(tmp_path / "app", EMPTY_APP)
    bench = FakePhysics(tmp_path / "run")
    bench.close()
    (tmp_path / "run" / "athrill_mmap.bin").write_bytes(b"ETTX" + bytes(100))
    proc = bench.start(exe)
    assert proc.wait(timeout=10) == EXIT_BENCH_FAULT
    assert "bench fault: " in (err := finish(proc)) and "size 104 bytes, expected 8192" in err


EMPTY_APP = '#include "ev3api.h"\nvoid main_task(intptr_t unused) { }\n'
SLEEPER_APP = '#include "ev3api.h"\nvoid main_task(intptr_t unused) { for (;;) tslp_tsk(100000); }\n'


def test_a_program_whose_tasks_all_end_never_wakes_and_exits(tmp_path):
    exe = build(tmp_path / "app", EMPTY_APP)
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    assert bench.next_wake(proc) == NEVER_WAKES
    assert proc.wait(timeout=10) == 0


def maps_the_bench_files(pid: int, run_dir: Path) -> bool:
    """Whether process `pid` has the run directory's two mapped files mapped."""
    try:
        maps = Path(f"/proc/{pid}/maps").read_text()
    except OSError:
        return False
    return all(str(run_dir.resolve() / name) in maps for name in (UNITY_FILE, ATHRILL_FILE))


def test_a_prelaunched_program_waits_for_its_own_test(tmp_path):
    exe = build(tmp_path / "app", SLEEPER_APP)
    bench = FakePhysics(tmp_path / "run")
    bench.unity.write_u32(Rx.TEST_SEQ, 1)
    proc = bench.start(exe, test=2)
    # Positive evidence that it runs: it has mapped the bench's files (it gets that far before it waits).
    wait_until(lambda: maps_the_bench_files(proc.pid, bench.run_dir), 30, 0.01, alive=lambda: proc.poll() is None,
               what="the program to open the bench's files")
    time.sleep(0.3)  # sixty of its naps: time enough to take the files, which it must not before its test
    assert proc.poll() is None and bench.athrill.read_u32(Tx.ATHRILL_PID) == 0  # waiting, hands off the files
    bench.unity.write_u32(Rx.TEST_SEQ, 2)
    assert bench.wakes(proc, 250_000) == [100_000, 200_000, 300_000]
    finish(proc)


def test_a_prelaunched_program_whose_test_never_comes_exits_quietly(tmp_path):
    exe = build(tmp_path / "app", SLEEPER_APP)
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe, test=2)
    bench.unity.write_u32(Rx.TEST_SEQ, 3)
    assert proc.wait(timeout=10) == 0
    assert "test 2 will not run (physics is at test 3)" in finish(proc)


def test_a_program_whose_physics_process_is_gone_exits_quietly(tmp_path):
    exe = build(tmp_path / "app", SLEEPER_APP)
    bench = FakePhysics(tmp_path / "run")
    physics = subprocess.Popen(["sleep", "60"])
    bench.unity.write_u32(Rx.PHYSICS_PID, physics.pid)
    proc = bench.start(exe)
    assert bench.next_wake(proc) == 100_000
    physics.kill()
    physics.wait()
    assert proc.wait(timeout=10) == 0
    assert "is gone" in finish(proc)


SCHEDULING_CFG = """
INCLUDE("app_common.cfg");
#include "app.h"
CRE_TSK(MAIN_TASK, { TA_ACT, 0, main_task, MAIN_PRIORITY, STACK_SIZE, NULL });
CRE_TSK(HIGH_TASK, { TA_NULL, 7, high_task, MAIN_PRIORITY - 1, STACK_SIZE, NULL });
CRE_TSK(LOW_TASK, { TA_ACT, 0, low_task, MAIN_PRIORITY + 1, STACK_SIZE, NULL });
CRE_TSK(PERIODIC_TASK, { TA_NULL, 0, periodic_task, MAIN_PRIORITY, STACK_SIZE, NULL });
EV3_CRE_CYC(TICK, { TA_STA, 0, tick, 30, 0 });
CRE_CYC(KICK, { TA_NULL, { TNFY_ACTTSK, PERIODIC_TASK }, 40 * 1000, 5 * 1000 });
"""
SCHEDULING_APP = r"""
#include "ev3api.h"
#include "app.h"

static void say(const char *what) { syslog(LOG_NOTICE, "%s", what); }

void tick(intptr_t exinf) { syslog(LOG_NOTICE, "tick (tslp_tsk in a handler: %d)", tslp_tsk(1000)); }
void high_task(intptr_t exinf) { syslog(LOG_NOTICE, "high %d", (int)exinf); }
void periodic_task(intptr_t exinf) { say("periodic"); }
void low_task(intptr_t exinf)
{
    say("low");
    dly_tsk(20000);
    say("low after 20 ms");
    ext_tsk();
    say("never");
}
void main_task(intptr_t exinf)
{
    say("main");
    syslog(LOG_NOTICE, "act_tsk(HIGH_TASK) %d", act_tsk(HIGH_TASK));
    syslog(LOG_NOTICE, "act_tsk(99) %d", act_tsk(99));
    syslog(LOG_NOTICE, "sta_cyc(KICK) %d", sta_cyc(KICK));
    syslog(LOG_NOTICE, "tslp_tsk(50 ms) %d", tslp_tsk(50000));
    syslog(LOG_NOTICE, "wup_tsk(LOW_TASK) %d", wup_tsk(LOW_TASK));
    syslog(LOG_NOTICE, "slp_tsk after a wup_tsk of itself %d", (wup_tsk(TSK_SELF), slp_tsk()));
    ev3_stp_cyc(TICK);
    stp_cyc(KICK);
}
"""
SCHEDULING_H = "#define MAIN_PRIORITY (TMIN_APP_TPRI + 2)\nvoid main_task(intptr_t);\n"


def test_tasks_and_cyclic_handlers_run_in_priority_and_time_order(tmp_path):
    (tmp_path / "app").mkdir()
    (tmp_path / "app" / "app.h").write_text(SCHEDULING_H)
    exe = build(tmp_path / "app", SCHEDULING_APP, SCHEDULING_CFG)
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    assert bench.wakes(proc, 60_000) == [5_000, 20_000, 30_000, 45_000, 50_000, NEVER_WAKES]
    assert proc.wait(timeout=10) == 0
    log = [line.split("] ", 1) for line in finish(proc).splitlines()]
    assert [(stamp.strip("[ s"), what) for stamp, what in log] == [
        ("0.000", "tick (tslp_tsk in a handler: -25)"),  # E_CTX; handlers run before tasks
        ("0.000", "main"),
        ("0.000", "high 7"),  # a higher priority activated: it runs first
        ("0.000", "act_tsk(HIGH_TASK) 0"),
        ("0.000", "act_tsk(99) -18"),
        ("0.000", "sta_cyc(KICK) 0"),
        ("0.000", "low"),
        ("0.005", "periodic"),  # KICK: phase 5 ms after sta_cyc
        ("0.020", "low after 20 ms"),
        ("0.030", "tick (tslp_tsk in a handler: -25)"),
        ("0.045", "periodic"),
        ("0.050", "tslp_tsk(50 ms) -50"),  # E_TMOUT
        ("0.050", "wup_tsk(LOW_TASK) -41"),  # E_OBJ: it has ended
        ("0.050", "slp_tsk after a wup_tsk of itself 0"),
    ]



EV3_IDS_CFG = """
#include "app.h"
CRE_TSK(MAIN_TASK, { TA_ACT, 0, main_task, MAIN_PRIORITY, STACK_SIZE, NULL });
CRE_TSK(TRACER_TASK, { TA_NULL, 0, tracer_task, MAIN_PRIORITY + 1, STACK_SIZE, NULL });
CRE_CYC(TRACER_CYC, { TA_NULL, { TNFY_ACTTSK, TRACER_TASK }, 10 * 1000, 0 });
"""
EV3_IDS_APP = r"""
#include "ev3api.h"
#include "app.h"
void tracer_task(intptr_t exinf) { syslog(LOG_NOTICE, "traced"); }
void main_task(intptr_t exinf)
{
    syslog(LOG_NOTICE, "ev3_sta_cyc(TRACER_CYC) %d", ev3_sta_cyc(TRACER_CYC));
    tslp_tsk(25 * 1000);
    syslog(LOG_NOTICE, "sta_cyc(TRACER_CYC) %d", sta_cyc(TRACER_CYC));
    tslp_tsk(15 * 1000);
    stp_cyc(TRACER_CYC);
}
"""


def test_ev3_sta_cyc_takes_only_an_ev3_cyclics_id_as_on_ev3rt(tmp_path):
    """ev3cyclic_dri.c's CHECK_EV3CYCID: an ASP3 CRE_CYC handler's ID is E_ID to ev3_sta_cyc, which starts
    nothing (a C++ tracer, run both ways, found the native runtime starting it)."""
    (tmp_path / "app").mkdir()
    (tmp_path / "app" / "app.h").write_text(SCHEDULING_H + "void tracer_task(intptr_t);\n")
    exe = build(tmp_path / "app", EV3_IDS_APP, EV3_IDS_CFG)
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    assert bench.wakes(proc, 60_000) == [25_000, 35_000, 40_000, NEVER_WAKES]
    log = [line.split("] ", 1) for line in finish(proc).splitlines()]
    assert [(stamp.strip("[ s"), what) for stamp, what in log] == [
        ("0.000", "ev3_sta_cyc(TRACER_CYC) -18"),  # E_ID, and no tracing until sta_cyc
        ("0.025", "sta_cyc(TRACER_CYC) 0"),
        ("0.025", "traced"),
        ("0.035", "traced"),
    ]


# Each loop computes for a small fraction of the spin slice (about 0.1 ms here), then sleeps 100 ms.
COMPUTING_APP = r"""
#include "ev3api.h"
void main_task(intptr_t unused)
{
    for (;;) {
        volatile unsigned x = 0;
        for (unsigned i = 0; i < 100000; i++)
            x += i;
        tslp_tsk(100000);
    }
}
"""
SPINNING_APP = '#include "ev3api.h"\nvoid main_task(intptr_t unused) { tslp_tsk(100000); for (;;) {} }\n'


def test_a_task_that_computes_less_than_a_slice_before_it_sleeps_is_never_preempted(tmp_path):
    """The slice counts from each dispatch: a CPU timer that ran on through the kernel's own work and the
    waits once fired inside such a loop now and then, moving the task's outputs 10 ms late by chance (how
    often depended on the machine's speed)."""
    exe = build(tmp_path / "app", COMPUTING_APP)
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    assert bench.wakes(proc, 30_000_000) == [100_000 * k for k in range(1, 302)]
    finish(proc)


def test_a_task_that_spins_is_preempted_and_simulated_time_goes_on(tmp_path):
    exe = build(tmp_path / "app", SPINNING_APP)
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    assert bench.wakes(proc, 150_000) == [100_000, 110_000, 120_000, 130_000, 140_000, 150_000, 160_000]
    finish(proc)

CLICK_APP = r'''
#include "ev3api.h"
static void clicked(intptr_t exinf) { syslog(LOG_NOTICE, "clicked %d", (int)exinf); }
void main_task(intptr_t unused)
{
    ev3_button_set_on_clicked(ENTER_BUTTON, clicked, 5);
    for (;;) tslp_tsk(1000);
}
'''


def test_a_click_handler_runs_when_the_button_comes_up(tmp_path):
    """brick_dri.c's brick_button_cyc calls it on a release (down before, up now), never on the press."""
    exe = build(tmp_path / "app", CLICK_APP)
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    for wake, buttons in ((1000, 1 << ENTER_BUTTON), (2000, 1 << ENTER_BUTTON), (3000, 0), (4000, 0)):
        assert bench.next_wake(proc) == wake
        bench.unity.write_i32(Rx.BUTTONS, buttons)
        bench.unity.unity_time_us = wake
    bench.next_wake(proc)
    assert [line.split("] ")[1] for line in finish(proc).splitlines()] == ["clicked 5"]



SHORT_PRESS_C = r"""
#include "ev3api.h"
static void clicked(intptr_t exinf) { syslog(LOG_NOTICE, "clicked %d", (int)exinf); }
void main_task(intptr_t unused)
{
    ev3_button_set_on_clicked(ENTER_BUTTON, clicked, 5);
    for (;;) tslp_tsk(100000);
}
"""
SHORT_PRESS_PY = """
from athrill_sim.mock.ev3api import ENTER_BUTTON

def main_task(api):
    api.ev3_button_set_on_clicked(ENTER_BUTTON, lambda exinf: api.syslog(f"clicked {exinf}"), 5)
    while True:
        api.tslp_tsk(100000)
"""
PRESS_US = (20_000, 50_000)  # shorter than the program's 100 ms sleep


def stamped_lines(log: str) -> list[tuple[str, str]]:
    """(seconds, message) of each syslog line, as both sides stamp them: `[     0.050 s] message`."""
    return [(stamp.strip("[ s"), what.strip()) for stamp, what in
            (line.split("] ", 1) for line in log.splitlines() if line.startswith("[") and "] " in line)]


def run_with_a_short_press(bench: FakePhysics, proc: subprocess.Popen, until_us: int) -> list[int]:
    wakes = []
    while (wake := bench.next_wake(proc)) <= until_us:
        wakes.append(wake)
        bench.unity.write_i32(Rx.BUTTONS, 1 << ENTER_BUTTON if PRESS_US[0] <= wake < PRESS_US[1] else 0)
        bench.unity.unity_time_us = wake
    return wakes


@pytest.mark.parametrize("side", ["native", "python"])
def test_a_press_shorter_than_the_programs_sleep_is_clicked_as_on_ev3rt(tmp_path, side, monkeypatch):
    """EV3RT polls the buttons every 10 ms (brick_dri.cfg's BRICK_BTN_CYC), whatever the tasks do: while a
    click handler is set both kernels wake that often, so a 30 ms press during a 100 ms sleep is clicked, at
    the first poll that sees it up (50 ms)."""
    bench = FakePhysics(tmp_path / "run")
    if side == "native":
        proc = bench.start(build(tmp_path / "app", SHORT_PRESS_C))
    else:
        (tmp_path / "short_press.py").write_text(SHORT_PRESS_PY)
        monkeypatch.setenv("PYTHONPATH", str(tmp_path))
        proc = subprocess.Popen([sys.executable, "-m", "athrill_sim.mock.main", "--app", "short_press:main_task",
                                 "--run-dir", str(bench.run_dir)], stdin=subprocess.DEVNULL,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert run_with_a_short_press(bench, proc, 200_000) == [10_000 * k for k in range(1, 21)]
    assert stamped_lines(finish(proc)) == [("0.050", "clicked 5")]


SLEEPS_UNTIL_CLICKED = r"""
#include "ev3api.h"
static void clicked(intptr_t exinf) { wup_tsk(MAIN_TASK); }
void main_task(intptr_t unused)
{
    ev3_button_set_on_clicked(ENTER_BUTTON, clicked, 0);
    slp_tsk();
    syslog(LOG_NOTICE, "started");
    tslp_tsk(100000);
}
"""


def test_a_task_asleep_until_a_click_wakes_when_the_button_is_released(tmp_path):
    """The press-to-start pattern of EV3RT programs: slp_tsk, and a click handler that wakes the task. With
    nothing timed left the kernel used to leave at once; the button poll keeps it going."""
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(build(tmp_path / "app", SLEEPS_UNTIL_CLICKED))
    wakes = run_with_a_short_press(bench, proc, 150_000)
    assert wakes[:5] == [10_000, 20_000, 30_000, 40_000, 50_000] and 150_000 in wakes
    assert stamped_lines(finish(proc)) == [("0.050", "started")]
