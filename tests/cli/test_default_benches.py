"""`hako run`'s default bench count: the cores this process may use (taskset and cpusets included, which
os.cpu_count() ignores), and one where a device config fixes athrill2's UDP ports."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from hakoniwa.cli.main import campaign_benches, usable_cores
from hakoniwa.physics.options import BenchOptions


def test_the_default_follows_the_cores_this_process_may_use(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1})  # `taskset -c 0,1` on a larger machine
    assert usable_cores() == 2
    assert campaign_benches(BenchOptions()) == 2
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {3})
    assert campaign_benches(BenchOptions()) == 1


def test_fixed_udp_ports_make_the_default_one_bench(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1, 2, 3})
    config = tmp_path / "device_config.txt"
    config.write_text("DEBUG_FUNC_ENABLE_VDEV 1\nDEBUG_FUNC_VDEV_SIMSYNC_TYPE UDP\n"
                      "DEBUG_FUNC_VDEV_TX_IPADDR 127.0.0.1\nDEBUG_FUNC_VDEV_TX_PORTNO 54101\n"
                      "DEBUG_FUNC_VDEV_RX_IPADDR 127.0.0.1\nDEBUG_FUNC_VDEV_RX_PORTNO 54102\n")
    assert campaign_benches(BenchOptions(device_config=str(config))) == 1
    config.write_text("DEBUG_FUNC_ENABLE_VDEV 1\nDEBUG_FUNC_VDEV_SIMSYNC_TYPE UDP\n"
                      "DEBUG_FUNC_VDEV_TX_IPADDR 127.0.0.1\nDEBUG_FUNC_VDEV_RX_IPADDR 127.0.0.1\n")
    assert campaign_benches(BenchOptions(device_config=str(config))) == 4  # the bench picks ports per bench
