"""ET Robocon's official SPIKE sample in the real emulator on `--robot hackspi`: the unmodified
`sample_c5_spike` (RasPike-ART, built against ../shared's raspike-athrill-v850e2m) starts on a force-sensor
press and laps the oval, because the SPIKE colour sensor reads the course as the sample is calibrated (white
40, black 10) and HackSPi's left motor is mounted mirror-wise, as the sample's PUP_DIRECTION_COUNTERCLOCKWISE
says. The SDK's own copy of the sample (sdk/workspace/sample_c5_spike) is the same source."""

import json
from pathlib import Path

import pytest

from athrill_sim.programs.third_party import RASPIKE_SAMPLES, RASPIKE_SDK
from athrill_sim.v850.toolchain import SHARED, find_tools
from tests.helpers.commands import hako
from tests.helpers.paths import needs_shared
from tests.helpers.realemu_fixtures import need_v850_tools

RASPIKE = SHARED / "raspike"
SPIKE_SDK = RASPIKE / "raspike-athrill-v850e2m"
SAMPLE = RASPIKE / "raspike-art-samples" / "sample_c5_spike"


@pytest.fixture(scope="module")
def sample_image() -> Path:
    if not (SPIKE_SDK / "sdk" / "common" / "spikeapi").is_dir():
        pytest.skip(needs_shared("ET Robocon's SPIKE SDK", SPIKE_SDK, RASPIKE_SDK))
    if not SAMPLE.is_dir():
        pytest.skip(needs_shared("RasPike-ART's SPIKE sample", SAMPLE, RASPIKE_SAMPLES))
    need_v850_tools()  # the EV3RT toolchain: the SPIKE SDK has none beside it
    out = hako("build", str(SAMPLE), "--sdk", str(SPIKE_SDK), "--toolchain", str(find_tools().gcc.parent),
               timeout=900)
    assert out.returncode == 0, out.stderr
    return Path(out.stdout.strip())


@pytest.mark.slow
def test_the_official_spike_sample_laps_the_oval_on_hackspi(sample_image, repeatable_athrill2, tmp_path):
    scenario = tmp_path / "start.toml"
    scenario.write_text('[[press]]\nsensor = "force"\nat_s = 1.0\nfor_s = 0.5\n')
    out = hako("try", "--app", str(sample_image), "--robot", "hackspi", "--scenario", str(scenario),
               "--athrill2", str(repeatable_athrill2), "--noise", "0", "--json", timeout=600)
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout)
    assert result["event"] == "GOAL" and result["checkpoints"] == 4, result
    assert 1.0 < result["lap_time_s"] < 60 and result["sync"] == "repeatable", result
    # Without the press the sample waits for the force sensor: no start, no metre driven.
    waiting = hako("try", "--app", str(sample_image), "--robot", "hackspi", "--athrill2", str(repeatable_athrill2),
                   "--noise", "0", "--time-limit", "3", "--json", timeout=600)
    assert waiting.returncode == 0, waiting.stderr
    assert json.loads(waiting.stdout)["distance_m"] < 0.01
