"""A parameter's value as the program holds it: every form's value comes from its slot in the parameter area
(an f64: `hakoniwa.wire.params.CARRIER`) and reaches the program as exactly what the program's type makes of the
proposal: the float32 or float64 of it, or the integer. A value written as text (a define, a source match, a
data file) is the shortest decimal that C reads back as that very number, whether it reads it as a double and
converts it (`float kp = KP;`, `atof`) or as a float directly (`1.5f`, `strtof`).
"""

from __future__ import annotations

import re
import struct
from fractions import Fraction

from hakoniwa.conventions import FLOAT32_MAX
from hakoniwa.wire.params import INT_TYPES

_SUFFIX = {"float": re.compile(r"[0-9.]([fFlL])$"), "int": re.compile(r"[0-9]([uUlL]+)$")}


def as_float32(value: float) -> float:
    return struct.unpack("<f", struct.pack("<f", value))[0]


def typed_value(value: float, storage: str) -> float | int:
    """What a program whose variable has type `storage` holds of the proposal `value`."""
    if storage in INT_TYPES:
        return int(value)
    return as_float32(value) if storage == "f32" else float(value)


def value_text(value: float, storage: str) -> str:
    """The value as C source or a data file holds it: for a float32, the shortest decimal that a double
    literal (then converted) and a float literal both give back exactly; for a double, the shortest that
    gives it back; an integer as an integer."""
    if storage in INT_TYPES:
        return str(int(value))
    if storage == "f64":
        return _floating(repr(float(value)))
    f = as_float32(value)
    for digits in range(1, 18):
        text = f"{f:.{digits}g}"
        if abs(float(text)) <= FLOAT32_MAX and as_float32(float(text)) == f and _nearest_float32(Fraction(text), f):
            return _floating(text)
    raise AssertionError(f"no decimal for float32 {f!r}")  # 17 significant digits always read back


def literal(old: str, text: str, integer: bool) -> str:
    """The value as a literal in place of `old`, keeping `old`'s C suffix (1.0f stays a float literal)."""
    m = _SUFFIX["int" if integer else "float"].search(old.strip())
    return text + m.group(1) if m is not None else text


def _floating(text: str) -> str:
    """A C floating literal, never an integer one: `KP / 2` must not become an integer division."""
    return text if any(c in text for c in ".en") else text + ".0"


def _nearest_float32(x: Fraction, f: float) -> bool:
    """Whether `x` rounds to the float32 `f` (round to nearest, ties to even), as strtof rounds."""
    exact = Fraction(f)
    if x == exact:
        return True
    bits = struct.unpack("<I", struct.pack("<f", f))[0]
    toward_zero, away = bits - 1, bits + 1  # the float32 bit patterns either side of f (f is not zero here)
    for b in (toward_zero, away):
        n = struct.unpack("<f", struct.pack("<I", b))[0]
        # past the largest float32 lies infinity; values round there from the midpoint with 2**128
        neighbour = Fraction(2**128 if n > 0 else -2**128) if abs(n) == float("inf") else Fraction(n)
        if (neighbour - exact) * (x - exact) > 0:  # x lies on this neighbour's side of f
            mid = (exact + neighbour) / 2
            return abs(x - exact) < abs(mid - exact) or (abs(x - exact) == abs(mid - exact) and not bits & 1)
    return False
