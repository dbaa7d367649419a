"""Each test's noise seed, derived from where the test sits in a campaign.

A campaign runs every parameter set several times; each repetition must see a different noise draw, and the
whole campaign must still be reproducible from its seed, whatever order tests run or finish in. So the seed
of a test is a pure function of (campaign seed, set index, repetition), never of a counter or the clock.

The function is a keyed hash (BLAKE2b from the standard library) rather than a numpy generator: its value is
fixed by the hash's definition and cannot change with a numpy release, so a journal written today replays
the same draws later. Distinct inputs give independent-looking seeds; two of the 2**32 values can still
collide, which only means two tests share a draw.
"""

from __future__ import annotations

import hashlib
import operator

SEED_BITS = 32  # Rx.NOISE_SEED is a u32
_PERSON = b"hako-noise-seed"  # the hash's personalisation: these seeds differ from any other BLAKE2b use


def noise_seed(campaign_seed: int, set_index: int, repetition: int) -> int:
    """The noise seed (0 .. 2**32 - 1) of repetition `repetition` of parameter set `set_index` in the campaign
    seeded `campaign_seed`; the same three integers always give the same seed."""
    parts = [operator.index(v) for v in (campaign_seed, set_index, repetition)]  # ints only: no 1.0 vs 1
    digest = hashlib.blake2b(":".join(map(str, parts)).encode(), digest_size=SEED_BITS // 8, person=_PERSON)
    return int.from_bytes(digest.digest(), "little")
