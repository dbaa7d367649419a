"""Where ET Robocon's SPIKE SDK for Athrill and RasPike-ART's samples live in ../shared (see its
third_party/raspike/README.md), for the tests that read them; each skips with NEEDS_RASPIKE without them. SPIKE-RT
for the hub (third_party/raspike-art/README.md) likewise, with NEEDS_SPIKE_RT."""

from __future__ import annotations

from athrill_sim.programs.third_party import RASPIKE_SDK, SPIKE_RT_HUB
from tests.helpers.paths import SHARED, needs_shared

RASPIKE = SHARED / "third_party" / "raspike"
SDK = RASPIKE / "raspike-athrill-v850e2m"
SPIKEAPI_SRC = SDK / "sdk" / "common" / "spikeapi" / "src"
SPIKE_HEADERS = SDK / "libraspike-art" / "drivers" / "include" / "spike"
PBIO_HEADERS = SDK / "libraspike-art" / "external" / "libpybricks" / "lib" / "pbio" / "include" / "pbio"
VDEV_HEADER = SDK / "target" / "v850_gcc" / "pil" / "include" / "ev3_vdev_common.h"
SDK_SAMPLES = SDK / "sdk" / "workspace"
ART_SAMPLES = RASPIKE / "raspike-art-samples"
NEEDS_RASPIKE = needs_shared("ET Robocon's SPIKE SDK", RASPIKE, RASPIKE_SDK)
LIBCPP_SPIKE = SDK / "sdk" / "common" / "library" / "libcpp-spike"
SPIKE_RT = SHARED / "third_party" / "raspike-art" / "spike-rt-hub"
NEEDS_SPIKE_RT = needs_shared("SPIKE-RT for the hub", SPIKE_RT, SPIKE_RT_HUB)
