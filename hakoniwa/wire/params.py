"""The parameter area of `unity_mmap.bin` (RX body 540..PARAM_END): typed slots the controller writes
before each test.

The paper's programs read a float32 at `0x090F0000 + offset`, so an `offset` parameter's slot is the
program's own storage, of the type the program reads there (f32 unless the space says otherwise). Every other
form of parameter (a `#define`, a global, a data file, a source match: `athrill_sim.tuning.forms`) is handed to the
physics process through a slot too, as an f64 holding the proposal exactly, and the physics side turns it
into what the program reads (the float32 or float64 of the proposal, or the integer). So the wire stays the
one contract between controller and bench, whatever the form.
"""

from __future__ import annotations

import struct

from hakoniwa.wire.protocol import PARAM_END, Rx

# struct format of each storage type a parameter can have, by the names the space file uses.
SLOT_FORMATS = {"f32": "f", "f64": "d", "i8": "b", "u8": "B", "i16": "h", "u16": "H", "i32": "i", "u32": "I",
                "i64": "q", "u64": "Q"}
FLOAT_TYPES = ("f32", "f64")
INT_TYPES = tuple(t for t in SLOT_FORMATS if t not in FLOAT_TYPES)
CARRIER = "f64"  # the slot type of every parameter that is not an `offset`: a double holds any proposal exactly
SLOT_ALIGN = 4  # every slot starts on a 4-byte boundary, as the paper's float32 slots do
FIRST_SLOT = Rx.PARAMS


def slot_size(slot_type: str) -> int:
    return struct.calcsize(SLOT_FORMATS[slot_type])


def int_range(storage: str) -> tuple[int, int]:
    """The values an integer storage type holds."""
    bits = 8 * slot_size(storage)
    return (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if storage.startswith("i") else (0, (1 << bits) - 1)


def fits_area(offset: int, slot_type: str) -> bool:
    return FIRST_SLOT <= offset and offset + slot_size(slot_type) <= PARAM_END and offset % SLOT_ALIGN == 0


def encode(slot_type: str, value: float) -> int | float:
    """The value as the slot stores it: an integer type takes the (already integral) value as an int."""
    return value if slot_type in FLOAT_TYPES else int(value)
