"""Real v850 EV3RT images for the real TOPPERS athrill2, built from a user's program (`hako build`).

The EV3RT SDK (toppers/ev3rt-athrill-v850e2m), a v850-elf cross toolchain and Ruby (the SDK's cfg and tecsgen
generators) turn an `app.c` or an EV3RT workspace folder into `asp`, the ELF athrill2 runs. `toolchain.py`
finds the three, `build.py` drives the SDK's own make in a scratch copy and caches the image, `elf.py` checks an
image before any test is charged to it.
"""

from __future__ import annotations

from hakoniwa.wire.errors import HakoError


class ImageError(HakoError, ValueError):
    """No image can be built or run from what was given; the message is one line that says what to do."""
