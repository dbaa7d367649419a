"""Where each third-party piece that `../shared` holds comes from, for a user who has no `../shared`.

This project's CI has a `../shared` folder beside the clone with the real Athrill, EV3RT's and ET Robocon's
SDKs, a v850 toolchain and a large maze set; a fresh clone has none of it. What needs a piece says where it
looked and where a user gets it: the public repository and commit it was taken from, and our patch or script
that makes it build here. This table is the one place those are written: the tests' skip reasons
(`tests/helpers/paths.py`) and the build's errors read it, and `tests/project/test_skip_reasons.py` checks
that README.md and docs/REAL-ATHRILL.md give the same repositories and commits.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Piece:
    """One piece of `../shared`: its public origin and what turns that into what `../shared` holds; without a
    repository (a toolchain we build, documents not published), `then` alone says how to do without it."""

    shared: str  # where `../shared` holds it
    repository: str | None  # owner/name on GitHub
    commit: str | None  # the commit `../shared`'s copy is of
    then: str = ""  # our patch or script that makes it usable here, or what to take of the repository

    def source(self) -> str:
        """Where a user gets it, as one phrase for a skip reason or an error."""
        if self.repository is None:
            return self.then
        then = f", then {self.then}" if self.then else ""
        return f"get https://github.com/{self.repository} at {self.commit}{then}"


ATHRILL = Piece("third_party/athrill/src/athrill-target-v850e2m", "toppers/athrill-target-v850e2m", "d7123b6",
                "clone toppers/athrill at 8bf811e as its athrill/ and build athrill2 with scripts/build_athrill2.sh "
                "(ATHRILL_SRC names the folder)")
ATHRILL_CORE = Piece("third_party/athrill/src/athrill-target-v850e2m/athrill", "toppers/athrill", "8bf811e")
EV3RT_SDK = Piece("third_party/ev3rt/ev3rt-athrill-v850e2m", "toppers/ev3rt-athrill-v850e2m", "eaa870b",
                  "apply scripts/ev3rt-patches/01-ev3rt-gcc12-ruby3.diff and 02-ev3rt-cxx.diff (EV3RT_SDK or --sdk "
                  "names the folder)")
EV3RT_SAMPLE_IMAGE = Piece("third_party/athrill/ev3rt-ble_sample", "toppers/ev3rt-athrill-v850e2m", "b1740b6",
                           "hako build its sdk/workspace/ble_sample, beside that folder's memory_mmap.txt and "
                           "device_config_mmap.txt")
V850_TOOLCHAIN = Piece("third_party/ev3rt/toolchain", None, None,
                       "build it with scripts/build_v850_toolchain.sh from Debian 12's gcc-12-source, "
                       "binutils-source and newlib-source (--toolchain names it)")
RASPIKE_SDK = Piece("third_party/raspike/raspike-athrill-v850e2m", "ETrobocon/raspike-athrill-v850e2m", "a57b9ca",
                    "check out its libraspike-art submodule at 28f3f38 and apply "
                    "scripts/ev3rt-patches/raspike-gcc12-ruby3.diff (RASPIKE_SDK or --sdk names the folder)")
RASPIKE_SAMPLES = Piece("third_party/raspike/raspike-art-samples", "ETrobocon/RasPike-ART", "46d328e",
                        "take its sdk/workspace")
RASPIKE_ART = Piece("third_party/raspike-art/RasPike-ART", "ETrobocon/RasPike-ART", "e1d218c",
                    "check out its libraspike-art submodule at 28f3f38 (RASPIKE_ART or --sdk names the folder)")
SPIKE_RT_HUB = Piece("third_party/raspike-art/spike-rt-hub", "ETrobocon/spike-rt-RasPike-ART", "38ed091",
                     "take its sdk/ and drivers/")
MAZES = Piece("mazes", "micromouseonline/mazefiles", "a71f846897fdd2193e726a1276c6774c9ce9ac67",
              "take its classic/, halfsize/ and training/ folders")
SEEDS = Piece("seeds", None, None, "the project's source documents, not published; the tests that read them "
              "check our code against their worked examples, which the rest of the tests also cover")
PIECES = (ATHRILL, ATHRILL_CORE, EV3RT_SDK, EV3RT_SAMPLE_IMAGE, V850_TOOLCHAIN, RASPIKE_SDK, RASPIKE_SAMPLES,
          RASPIKE_ART, SPIKE_RT_HUB, MAZES, SEEDS)
