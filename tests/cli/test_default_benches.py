"""`hako run`'s default bench count: the cores this process may use (taskset and cpusets included, which
os.cpu_count() ignores), on two cores or more at least a set's first wave of tests where results do not depend
on timing, and one where a device config fixes athrill2's UDP ports."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from testctl.bench_options import BenchOptions
from testctl.campaign.benches import campaign_benches, usable_cores
from testctl.campaign.repetition import RepetitionRule

WAVE = RepetitionRule().still_needed([])  # 3 of the default 5: the tests of a set that run at once


def test_the_default_follows_the_cores_this_process_may_use(monkeypatch: pytest.MonkeyPatch) -> None:
    assert WAVE == 3
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1})  # `taskset -c 0,1` on a larger machine
    assert usable_cores() == 2
    assert campaign_benches(BenchOptions(), WAVE) == 3  # a set's three tests at once
    assert campaign_benches(BenchOptions(), 1) == 2  # --repeats 1
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set(range(8)))
    assert campaign_benches(BenchOptions(), WAVE) == 8
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {3})
    assert campaign_benches(BenchOptions(), WAVE) == 1  # on one core a second bench costs more than it gives


def test_the_unsynchronised_emulator_keeps_one_bench_per_core(monkeypatch: pytest.MonkeyPatch) -> None:
    """Its results depend on the CPU each emulator gets: more benches than cores would change them. The
    repeatable mode's do not."""
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1})
    real = {"app": "line_trace_c", "emulator": "athrill2"}  # only read, never built or run here
    assert campaign_benches(BenchOptions(**real, sync="hakoniwa"), WAVE) == 2
    assert campaign_benches(BenchOptions(**real), WAVE) == 3


def test_fixed_udp_ports_make_the_default_one_bench(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1, 2, 3})
    config = tmp_path / "device_config.txt"
    config.write_text("DEBUG_FUNC_ENABLE_VDEV 1\nDEBUG_FUNC_VDEV_SIMSYNC_TYPE UDP\n"
                      "DEBUG_FUNC_VDEV_TX_IPADDR 127.0.0.1\nDEBUG_FUNC_VDEV_TX_PORTNO 54101\n"
                      "DEBUG_FUNC_VDEV_RX_IPADDR 127.0.0.1\nDEBUG_FUNC_VDEV_RX_PORTNO 54102\n")
    assert campaign_benches(BenchOptions(device_config=str(config)), WAVE) == 1
    config.write_text("DEBUG_FUNC_ENABLE_VDEV 1\nDEBUG_FUNC_VDEV_SIMSYNC_TYPE UDP\n"
                      "DEBUG_FUNC_VDEV_TX_IPADDR 127.0.0.1\nDEBUG_FUNC_VDEV_RX_IPADDR 127.0.0.1\n")
    udp = BenchOptions(app="line_trace_c", emulator="athrill2", device_config=str(config))  # TOPPERS' protocol
    assert campaign_benches(udp, WAVE) == 4  # the bench picks ports per bench
