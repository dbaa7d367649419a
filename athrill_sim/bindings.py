"""How a parameter reaches a program that was not written for the bench: the kinds beside the paper's
`offset`, as the physics process is told them (`--bindings`, JSON made from the space by the controller).

- `define`: the program is built with `-DNAME=value` (a build per value, cached);
- `symbol`: a global's initial value is set in the program's image (`athrill_sim.elf_symbols`);
- `file`: a data file on the SD card is written from a template for each test;
- `source`: the text a pattern captures in one of the program's files is replaced in a scratch copy, which is
  built (a build per value, cached).

Every kind's value comes from its slot in the parameter area (an f64: `hakoniwa.wire.params.CARRIER`) and
reaches the program as exactly what the program's type makes of the proposal: the float32 or float64 of it,
or the integer. A value written as text (a define, a source match, a data file) is the shortest decimal that
C reads back as that very number, whether it reads it as a double and converts it (`float kp = KP;`,
`atof`) or as a float directly (`1.5f`, `strtof`).
"""

from __future__ import annotations

import json
import string
import struct
from dataclasses import asdict, dataclass
from fractions import Fraction

from athrill_sim.kinds.kind import DATA_FILE, IMAGE, REBUILD
from hakoniwa.conventions import FLOAT32_MAX
from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.params import FLOAT_TYPES, INT_TYPES

KINDS = ("define", "symbol", "file", "source")  # besides `offset`, which needs nothing of the physics side
NEEDS = {"define": REBUILD, "symbol": IMAGE, "file": DATA_FILE, "source": REBUILD}  # of the program's kind
SPACE_TYPES = ("float", "int", *FLOAT_TYPES, *INT_TYPES)  # what a space's `type` may say


class BindingError(HakoError, ValueError):
    """A binding cannot reach the program; the message is one line with the fix."""


@dataclass(frozen=True)
class Binding:
    """One parameter of a kind other than `offset`: where its value goes, and the slot it comes from."""

    name: str
    kind: str
    target: str  # define: the macro; symbol: the global's name; file: the data file; source: the file
    slot: int  # RX body offset of the f64 that carries the value
    low: float  # the values it takes: a searched parameter's range, a fixed one's value twice
    high: float
    type: str = "float"  # the space's type: float, int, or a storage type (f32, f64, i8 .. u64)
    match: str | None = None  # source: the regular expression whose one group is the value
    template: str | None = None  # file: the data file's text with {Name} placeholders
    template_file: str | None = None  # file: a copy of the data file with {Name} placeholders

    @property
    def integer(self) -> bool:
        return self.type == "int" or self.type in INT_TYPES

    @property
    def text_type(self) -> str:
        """The type whose value a text of this parameter stands for: a float parameter's text is read as a
        float32 unless the space says f64."""
        if self.integer:
            return "i64"
        return "f64" if self.type == "f64" else "f32"

    def describe(self) -> str:
        return f"{self.kind} {self.target}" + (f" ({self.match})" if self.match else "")


def to_json(bindings: tuple[Binding, ...]) -> str:
    return json.dumps([{k: v for k, v in asdict(b).items() if v is not None} for b in bindings], sort_keys=True)


def from_json(text: str) -> tuple[Binding, ...]:
    try:
        data = json.loads(text)
        bindings = tuple(Binding(**entry) for entry in data)
    except (ValueError, TypeError) as e:
        raise BindingError(f"--bindings is not a list of parameter bindings: {e}") from None
    for b in bindings:
        if b.kind not in KINDS or b.type not in SPACE_TYPES:
            raise BindingError(f"--bindings: {b.name!r} has kind {b.kind!r} and type {b.type!r}")
    return bindings


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


def template_fields(text: str) -> list[str]:
    """The {Name} placeholders of a template, in order ({{ and }} are literal braces)."""
    fields = []
    try:
        parsed = list(string.Formatter().parse(text))
    except ValueError as e:
        raise BindingError(f"template: {e} (write a literal brace as {{{{ or }}}})") from None
    for _, field, spec, conversion in parsed:
        if field is None:
            continue
        if not field.isidentifier() or spec or conversion:
            raise BindingError(f"template: placeholder {{{field}{'!' + conversion if conversion else ''}"
                               f"{':' + spec if spec else ''}}} is not a parameter's name in braces, as {{Kp}}")
        fields.append(field)
    return fields


def fill_template(text: str, texts: dict[str, str]) -> str:
    return text.format_map(texts)
