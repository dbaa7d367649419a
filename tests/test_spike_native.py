"""SPIKE programs natively: ET Robocon's SPIKE SDK for Athrill (raspike-athrill-v850e2m) as the reference for
what each SPIKE-RT call reads and writes, its headers as the reference for what ours declare, and RasPike-ART's
official samples, unmodified. Expected values come from the SDK's C (sdk/common/spikeapi/src), never from what
our runtime printed."""

import re

import pytest

from native_fixtures import build
from raspike_sdk import NEEDS_RASPIKE, SDK


def typedef_names(text: str) -> set[str]:
    """The names a TOPPERS header typedefs (`typedef ... NAME;`, struct typedefs included)."""
    text = re.sub(r"/\*.*?\*/|//[^\n]*", "", text, flags=re.S)
    return set(re.findall(r"\btypedef\b[^;{]*(?:\{[^}]*\})?[^;]*?\b(\w+)\s*;", text))


def test_every_toppers_type_of_the_sdk_is_declared(tmp_path):
    """RasPike's sample_c5 uses float32_t (tool_stddef.h), which our headers once lacked."""
    headers = (SDK / "include" / "t_stddef.h", SDK / "arch" / "gcc" / "tool_stddef.h")
    if not all(h.is_file() for h in headers):
        pytest.skip(NEEDS_RASPIKE)
    names = set().union(*(typedef_names(h.read_text(errors="replace")) for h in headers))
    names = {n for n in names if not n.startswith("TOPPERS_")}  # the headers' own helpers
    assert {"float32_t", "double64_t", "ACVCT", "SYSTIM", "bool_t"} <= names
    uses = "\n".join(f"{n} use_{n};" for n in sorted(names))
    build(tmp_path / "types", f'#include "ev3api.h"\n{uses}\nvoid main_task(intptr_t unused) {{ }}\n')
