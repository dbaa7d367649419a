"""Native runs mean what the real emulator means: a small subset of scripts/benchmark_fidelity.py (the built-in C
tracer at two of its random gain sets, and the SDK's base_practice_1), natively and in the real athrill2's
repeatable mode, must give the same event and laps and distances within 2%."""

import re
import subprocess
import sys

import pytest

from tests.helpers.athrill_fixtures import REPO


@pytest.mark.slow
def test_native_and_real_runs_agree_on_a_subset(base_practice_image, repeatable_athrill2):
    out = subprocess.run([sys.executable, str(REPO / "scripts" / "benchmark_fidelity.py"), "--sets", "2",
                          "--time-limit", "40", "--only", "line_trace_c", "--only", "base_practice_1",
                          "--athrill2", str(repeatable_athrill2)], capture_output=True, text=True, timeout=1200)
    assert "skipped" not in out.stdout, out.stdout
    assert out.stdout.count(" yes\n") == 3, out.stdout
    assert out.returncode == 0 and out.stdout.rstrip().endswith(": none"), out.stdout + out.stderr


@pytest.mark.slow
def test_the_team_style_c_and_cpp_programs_agree_natively_and_in_the_real_emulator(repeatable_athrill2):
    from tests.helpers.realemu_fixtures import need_v850_tools

    need_v850_tools()
    teams = ("etrobo_cpp_tracer", "cpp_features", "etrobo_hackev", "etrobo_spike_cpp")
    out = subprocess.run([sys.executable, str(REPO / "scripts" / "benchmark_fidelity.py"), "--no-corpus",
                          *(arg for name in teams for arg in ("--only", name)),
                          "--athrill2", str(repeatable_athrill2)], capture_output=True, text=True, timeout=1800)
    assert "skipped" not in out.stdout, out.stdout
    assert out.stdout.count(" yes\n") == len(teams), out.stdout
    assert out.returncode == 0 and out.stdout.rstrip().endswith(": none"), out.stdout + out.stderr


@pytest.mark.slow
def test_raspike_arts_official_samples_agree_natively_and_in_the_real_emulator(repeatable_athrill2):
    """sample_c5_spike unchanged (both copies) on HackSPi after a force-sensor press, and sample_c5 (the EV3
    API on RasPike) on HackEV."""
    from tests.helpers.raspike_sdk import ART_SAMPLES, NEEDS_RASPIKE
    from tests.helpers.realemu_fixtures import need_v850_tools

    if not ART_SAMPLES.is_dir():
        pytest.skip(NEEDS_RASPIKE)
    need_v850_tools()
    samples = ("sample_c5_spike", "sdk sample_c5_spike", "sample_c5")
    out = subprocess.run([sys.executable, str(REPO / "scripts" / "benchmark_fidelity.py"), "--no-teams", "--sets", "1",
                          *(arg for name in samples for arg in ("--only", name)),
                          "--athrill2", str(repeatable_athrill2)], capture_output=True, text=True, timeout=1800)
    assert "skipped" not in out.stdout and "not run" not in out.stdout, out.stdout
    assert out.stdout.count(" yes\n") == len(samples), out.stdout
    assert re.search(r"^sample_c5_spike +GOAL ", out.stdout, re.M), out.stdout  # it laps HackSPi
