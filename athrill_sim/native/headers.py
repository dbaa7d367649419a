"""The C headers generated from the Python side, so that the native runtime cannot disagree with it: the wire
layout (`hakoniwa.wire.protocol.c_header`, the only place that knows a byte offset), the lockstep's timing (the
physics step, and how long the mock kernel sleeps between its checks that the physics process lives) and the
names of the files a program leaves in the run directory (`hakoniwa.wire.rundir`)."""

from __future__ import annotations

from athrill_sim.mock import kernel as mock_kernel
from hakoniwa.wire import rundir, waiting
from hakoniwa.wire.protocol import RASPIKE_STATUS_PERIOD_US, c_header
from hakoniwa.wire.timebase import BUTTON_POLL_US, CALL_COST_US, CLOCK_EPOCH_S, PHYSICS_STEP_US

LAYOUT_HEADER = "hako_layout.h"
TIMING_HEADER = "hako_timing.h"


def timing_header() -> str:
    values = {
        "PHYSICS_STEP_US": PHYSICS_STEP_US,
        "BUTTON_POLL_US": BUTTON_POLL_US,
        "CALL_COST_US": CALL_COST_US,
        "CLOCK_EPOCH_S": f"{CLOCK_EPOCH_S}LL",
        "TEST_WAIT_NAP_S": mock_kernel.TEST_WAIT_NAP_S,
        "CHECK_EVERY_S": waiting.CHECK_EVERY_S,
        "RASPIKE_HUB_SENT": rundir.RASPIKE_HUB_SENT,
        "RASPIKE_PROGRAM_SENT": rundir.RASPIKE_PROGRAM_SENT,
        "RASPIKE_HUB_NEXT_STATUS": rundir.RASPIKE_HUB_NEXT_STATUS,
        "RASPIKE_SERIAL_SIZE": rundir.RASPIKE_SERIAL_SIZE,
        "RASPIKE_STATUS_PERIOD_US": RASPIKE_STATUS_PERIOD_US,
    }
    files = {"LCD_LOG": rundir.LCD_LOG, "SERIAL_LOG": rundir.SERIAL_LOG.replace("{port}", "%s"),
             "SERIAL_INPUT": rundir.SERIAL_INPUT, "SDCARD_DIR": rundir.SDCARD_DIR,
             "RASPIKE_SERIAL": rundir.RASPIKE_SERIAL}
    lines = ["/* Generated from hakoniwa.wire.timebase, hakoniwa.wire.waiting and athrill_sim.mock.kernel; "
             "do not edit. */",
             "#ifndef HAKO_TIMING_H", "#define HAKO_TIMING_H"]
    lines += [f"#define HAKO_{name} {value}" for name, value in values.items()]
    lines += [f'#define HAKO_{name} "{value}"' for name, value in files.items()]
    # serial_port_t order: EV3_SERIAL_DEFAULT, _UART, _BT, as the scenario names them
    lines.append("#define HAKO_SERIAL_PORT_NAMES " + ", ".join(f'"{port}"' for port in rundir.SERIAL_PORTS))
    lines.append("#endif")
    return "\n".join(lines) + "\n"


def generated_headers() -> dict[str, str]:
    """{file name: text} of every generated header."""
    return {LAYOUT_HEADER: c_header(), TIMING_HEADER: timing_header()}
