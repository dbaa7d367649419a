"""Where ET Robocon's SPIKE SDK for Athrill and RasPike-ART's samples live in ../shared (see its
third_party/raspike/README.md), for the tests that read them; each skips with NEEDS_RASPIKE without them."""

from __future__ import annotations

from tests.helpers.paths import SHARED

RASPIKE = SHARED / "third_party" / "raspike"
SDK = RASPIKE / "raspike-athrill-v850e2m"
SPIKEAPI_SRC = SDK / "sdk" / "common" / "spikeapi" / "src"
SPIKE_HEADERS = SDK / "libraspike-art" / "drivers" / "include" / "spike"
PBIO_HEADERS = SDK / "libraspike-art" / "external" / "libpybricks" / "lib" / "pbio" / "include" / "pbio"
VDEV_HEADER = SDK / "target" / "v850_gcc" / "pil" / "include" / "ev3_vdev_common.h"
SDK_SAMPLES = SDK / "sdk" / "workspace"
ART_SAMPLES = RASPIKE / "raspike-art-samples"
NEEDS_RASPIKE = f"needs ET Robocon's SPIKE SDK at {RASPIKE} (../shared)"
LIBCPP_SPIKE = SDK / "sdk" / "common" / "library" / "libcpp-spike"
