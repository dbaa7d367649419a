"""A team's RasPike-ART program as the robot runs it: `asp`, TOPPERS/ASP3's Linux port with the team's app and
libraspike-art, built by RasPike-ART's own make (`build.py`), for aarch64, run under qemu-user.

docs/DESIGN-NOTES.md ("RasPike-ART's asp, unmodified") says why aarch64 and qemu-user, not x86_64.
"""

from __future__ import annotations

from athrill_sim.v850 import ImageError


class AspError(ImageError):
    """No `asp` can be built or run from what was given; the message is one line that says what to do."""
