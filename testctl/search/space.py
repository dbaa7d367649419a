"""The search space of a campaign: which control parameters are searched, in what ranges, which are held
fixed, and how each reaches the robot program.

The paper's programs read their parameters from guest memory, so a parameter is by default an `offset` in
`unity_mmap.bin`'s parameter area: what the app reads (`read_f32(0x090F0000 + offset)`). A program written
without the bench keeps its gains elsewhere, and a parameter may say so instead (`athrill_sim.bindings`):
`define = "KP"` (built with -DKP=value), `symbol = "g_kp"` (a global's initial value), `file = "gains.csv"`
(a data file written from a template) or `source = { file, match }` (a constant in the source, rewritten).
Every parameter still travels through a slot of the parameter area (`hakoniwa.wire.params`): an `offset`
one in its own, the others in slots allocated from the top of the area in the space's order, so the wire
stays the one contract and a cluster needs nothing else. `type = "int"` makes a parameter an integer,
rounded before it is used and recorded as used; `type = "f32" | "f64" | "i8" .. "u64"` names the storage.

The paper's experiment (Kp, Ki, Kd in [0, 5], motor power 15) is `ParameterSpace.default()`; any other is a
small TOML file (see docs/space-example.toml), so a user can search a line threshold or the motor power
without touching code. The name is for people, plots, the journal and a template's {placeholders}.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

from athrill_sim.bindings import KINDS, SPACE_TYPES, Binding, to_json
from hakoniwa.conventions import FLOAT32_MAX
from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.params import (
    CARRIER,
    FIRST_SLOT,
    FLOAT_TYPES,
    INT_TYPES,
    SLOT_ALIGN,
    fits_area,
    int_range,
    slot_size,
)
from hakoniwa.wire.protocol import PARAM_END, Rx
from testctl import paper

_LAST_OFFSET = PARAM_END - 4
_KIND_KEYS = ("offset", *KINDS)
_VIA_KEYS = {"template", "template_file"}  # besides the kind's own key


class SpaceError(HakoError, ValueError):
    """A parameter-space description is unusable; the message is one line naming the problem."""


@dataclass(frozen=True)
class Via:
    """How a parameter of a kind other than `offset` reaches the program."""

    kind: str  # define, symbol, file, source
    target: str  # the macro; the global; the data file; the source file
    match: str | None = None  # source: the regular expression whose one group is the value
    template: str | None = None  # file: its text with {Name} placeholders
    template_file: str | None = None  # file: a copy of it with placeholders

    def to_dict(self) -> dict[str, Any]:
        if self.kind == "source":
            return {"source": {"file": self.target, "match": self.match}}
        extra = {k: v for k, v in (("template", self.template), ("template_file", self.template_file)) if v is not None}
        return {self.kind: self.target, **extra}

    def describe(self) -> str:
        return f"{self.kind} {self.target}" + (f" {self.match!r}" if self.match else "")


@dataclass(frozen=True)
class Parameter:
    """A searched parameter: continuous, or an integer (`type = "int"` or an integer storage type)."""

    name: str
    offset: int | None  # None: it reaches the program `via` another kind
    low: float
    high: float
    type: str = "float"
    via: Via | None = None

    @property
    def integer(self) -> bool:
        return self.type == "int" or self.type in INT_TYPES

    @property
    def kind(self) -> str:
        return self.via.kind if self.via is not None else "offset"

    @property
    def storage(self) -> str:
        """What its slot holds: an `offset` parameter's slot is the program's own variable (float32 unless the
        type says otherwise); every other kind's slot carries the value exactly as an f64."""
        if self.via is not None:
            return CARRIER
        return {"float": "f32", "int": "i32"}.get(self.type, self.type)

    @property
    def range_type(self) -> str:
        """The type whose values the parameter must stay within: its storage, and for the other kinds what
        the program reads (a float32 unless it says f64; an int unless it says which)."""
        if self.via is None:
            return self.storage
        return {"float": "f32", "int": "i32"}.get(self.type, self.type)

    def to_dict(self) -> dict[str, Any]:
        where = self.via.to_dict() if self.via is not None else {"offset": self.offset}
        return {"name": self.name, **where, "low": self.low, "high": self.high,
                **({"type": self.type} if self.type != "float" else {})}


@dataclass(frozen=True)
class FixedParameter(Parameter):
    """A parameter written with the same value in every test (e.g. the paper's motor power 15)."""

    def __init__(self, name: str, offset: int | None, value: float, type: str = "float", via: Via | None = None):
        super().__init__(name, offset, value, value, type, via)

    @property
    def value(self) -> float:
        return self.low

    def to_dict(self) -> dict[str, Any]:
        d = super().to_dict()
        del d["low"], d["high"]
        return {**d, "value": self.value}


@dataclass(frozen=True)
class ParameterSpace:
    """Searched and fixed parameters; construction validates kinds, slots, names and ranges."""

    params: tuple[Parameter, ...]
    fixed: tuple[FixedParameter, ...] = ()

    def __post_init__(self) -> None:
        if not self.params:
            raise SpaceError("the space has no searched parameter")
        seen_names: set[str] = set()
        targets: dict[tuple, str] = {}
        for p in self.every:
            if not p.name:
                raise SpaceError("a parameter has an empty name")
            if p.name in seen_names:
                raise SpaceError(f"parameter name {p.name!r} is used twice")
            seen_names.add(p.name)
            if p.type not in SPACE_TYPES:
                raise SpaceError(f"{p.name!r}: type {p.type!r} is none of {', '.join(SPACE_TYPES)}")
            if (p.offset is None) == (p.via is None):
                raise SpaceError(f"{p.name!r}: give exactly one of offset, {', '.join(KINDS)}")
            if p.offset is not None:
                _check_offset(p.name, p.offset, p.storage)
            key = _target(p)
            if key in targets:
                if p.via is None:
                    raise SpaceError(f"{p.name!r} and {targets[key]!r} share offset {p.offset}")
                raise SpaceError(f"{targets[key]!r} and {p.name!r} are two parameters on one target "
                                 f"({p.via.describe()})")
            targets[key] = p.name
            if p.via is not None and p.via.kind == "file" and not p.name.isidentifier():
                raise SpaceError(f"{p.name!r}: a file parameter's name is its {{placeholder}}: use letters, digits "
                                 "and _")
        for p in self.params:
            _check_value(p, "low", p.low)
            _check_value(p, "high", p.high)
            if p.low >= p.high:
                raise SpaceError(f"{p.name!r}: low {p.low} must be below high {p.high}")
        for f in self.fixed:
            _check_value(f, "value", f.value)
        self.slots  # noqa: B018 (allocates, or says the area is full)

    @property
    def every(self) -> tuple[Parameter, ...]:
        return (*self.params, *self.fixed)

    @cached_property
    def slots(self) -> dict[str, int]:
        """{name: slot offset}: an `offset` parameter's own; the others', 8 bytes each from the top of the
        parameter area down, in the space's order, around the `offset` ones."""
        own = [(p, p.offset) for p in self.every if p.offset is not None]  # the others come `via` a kind
        taken = [(offset, offset + slot_size(p.storage)) for p, offset in own]
        for i, (p, _) in enumerate(own):
            for (q, _), (start, end) in zip(own[:i], taken):
                if start < taken[i][1] and taken[i][0] < end:
                    raise SpaceError(f"{p.name!r} ({p.storage} at {p.offset}) and {q.name!r} ({q.storage} at "
                                     f"{q.offset}) overlap")
        out = {p.name: offset for p, offset in own}
        at = PARAM_END
        for p in (q for q in self.every if q.via is not None):
            at -= slot_size(CARRIER)
            while any(start < at + slot_size(CARRIER) and at < end for start, end in taken):
                at -= SLOT_ALIGN
            if at < FIRST_SLOT:
                raise SpaceError(f"{p.name!r}: the parameter area {FIRST_SLOT}..{PARAM_END} has no room left for it")
            taken.append((at, at + slot_size(CARRIER)))
            out[p.name] = at
        return out

    @classmethod
    def default(cls) -> ParameterSpace:
        """The paper's experiment (section 4.1, Table 4)."""
        return cls(
            params=(
                Parameter("Kp", Rx.KP, *paper.GAIN_RANGE),
                Parameter("Ki", Rx.KI, *paper.GAIN_RANGE),
                Parameter("Kd", Rx.KD, *paper.GAIN_RANGE),
            ),
            fixed=(FixedParameter("motor_power", Rx.MOTOR_POWER, paper.MOTOR_POWER),),
        )

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.params)

    @property
    def dim(self) -> int:
        return len(self.params)

    def snap(self, x: Sequence[float]) -> tuple[float, ...]:
        """`x` with every integer parameter rounded: the point as it is used and recorded."""
        return tuple(float(round(v)) if p.integer else float(v) for p, v in zip(self.params, x, strict=True))

    def to_offsets(self, x: Sequence[float]) -> dict[int, float]:
        """What the trial runner writes: {slot offset: value} for a point `x` (in `names` order) plus the fixed
        parameters; the slots' types are `slot_types`."""
        if len(x) != self.dim:
            raise ValueError(f"point has {len(x)} coordinates, the space has {self.dim}")
        values = {self.slots[p.name]: v for p, v in zip(self.params, self.snap(x))}
        values.update((self.slots[f.name], f.value) for f in self.fixed)
        return values

    @property
    def slot_types(self) -> dict[int, str]:
        """{slot offset: type} of every slot that is not a float32 (the paper's type, the runner's default)."""
        return {self.slots[p.name]: p.storage for p in self.every if p.storage != "f32"}

    def bindings(self) -> str | None:
        """How the parameters of other kinds than `offset` reach the program, for the bench
        (`BenchOptions.bindings`); None when every parameter is an `offset`."""
        bound = tuple(Binding(p.name, p.via.kind, p.via.target, self.slots[p.name], p.low, p.high, p.type,
                              p.via.match, p.via.template, p.via.template_file)
                      for p in self.every if p.via is not None)
        return to_json(bound) if bound else None

    def to_named(self, x: Sequence[float]) -> dict[str, float]:
        return {p.name: float(v) for p, v in zip(self.params, self.snap(x), strict=True)}

    def from_named(self, values: Mapping[str, float]) -> tuple[float, ...]:
        """The inverse of `to_named`; a missing name is a KeyError."""
        return tuple(float(values[p.name]) for p in self.params)

    def to_dict(self) -> dict[str, Any]:
        """The TOML file's structure, with each slot a kind other than `offset` got; used for the journal
        header, where equality means 'same space'."""
        def entry(p: Parameter) -> dict[str, Any]:
            return {**p.to_dict(), **({"slot": self.slots[p.name]} if p.via is not None else {})}

        return {"param": [entry(p) for p in self.params], "fixed": [entry(f) for f in self.fixed]}

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> ParameterSpace:
        if not isinstance(data, Mapping):
            raise SpaceError("the space description is not a table")
        unknown = set(data) - {"param", "fixed"}
        if unknown:
            raise SpaceError(f"unknown top-level key(s): {', '.join(sorted(unknown))}")
        params = tuple(Parameter(name, offset, _number(t, "low", name), _number(t, "high", name), kind, via)
                       for t, name, offset, kind, via in _entries(data, "param", {"low", "high"}))
        fixed = tuple(FixedParameter(name, offset, _number(t, "value", name), kind, via)
                      for t, name, offset, kind, via in _entries(data, "fixed", {"value"}))
        space = cls(params, fixed)
        for key in ("param", "fixed"):
            for t in data.get(key, []):
                if "slot" in t and t["slot"] != space.slots[t["name"]]:
                    raise SpaceError(f"{t['name']!r}: recorded in slot {t['slot']}, but this version gives it "
                                     f"slot {space.slots[t['name']]}")
        return space

    @classmethod
    def load(cls, path: Path | str) -> ParameterSpace:
        try:
            with open(path, "rb") as f:
                data = tomllib.load(f)
        except OSError as e:
            raise SpaceError(f"{path}: cannot read: {e.strerror}") from None
        except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
            raise SpaceError(f"{path}: not valid TOML: {e}") from None
        try:
            return cls.from_dict(data)
        except SpaceError as e:
            raise SpaceError(f"{path}: {e}") from None

    def describe(self) -> str:
        """One line for error messages and summaries."""
        def where(p: Parameter) -> str:
            return f"@{p.offset}" if p.via is None else f"({p.via.describe()})"

        parts = [f"{p.name}{where(p)}[{p.low:g},{p.high:g}]" for p in self.params]
        parts += [f"{f.name}{where(f)}={f.value:g}" for f in self.fixed]
        return " ".join(parts)


def _target(p: Parameter) -> tuple:
    """What a parameter sets: two parameters on one target would fight over it."""
    if p.via is None:
        return ("offset", p.offset)
    if p.via.kind == "file":
        return ("file", p.name)  # its placeholder; a file takes many
    return (p.via.kind, p.via.target, p.via.match)


def _check_value(p: Parameter, what: str, value: float) -> None:
    """A value its slot, or the program's variable, cannot hold would fail inside a worker, test after test."""
    kind = p.range_type
    if kind in FLOAT_TYPES:
        limit = FLOAT32_MAX if kind == "f32" else math.inf
        if not (math.isfinite(value) and abs(value) <= limit):
            raise SpaceError(f"{p.name!r}: {what} {value!r} does not fit a float32 slot (a finite number within "
                             f"±{FLOAT32_MAX:.7g})" if kind == "f32" else f"{p.name!r}: {what} {value!r} is not finite")
        return
    lo, hi = int_range(kind)
    if not (math.isfinite(value) and value == int(value) and lo <= value <= hi):
        raise SpaceError(f"{p.name!r}: {what} {value!r} is not an integer of {kind} ({lo}..{hi})")


def _check_offset(name: str, offset: int, storage: str) -> None:
    if not Rx.PARAMS <= offset <= _LAST_OFFSET:
        raise SpaceError(f"{name!r}: offset {offset} is outside the parameter area {Rx.PARAMS}..{_LAST_OFFSET}")
    if offset % SLOT_ALIGN:
        raise SpaceError(f"{name!r}: offset {offset} is not {SLOT_ALIGN}-byte aligned")
    if not fits_area(offset, storage):
        raise SpaceError(f"{name!r}: an {storage} at offset {offset} runs past the parameter area's end {PARAM_END}")


def _entries(data: Mapping[str, Any], key: str, own_keys: set[str]
             ) -> list[tuple[Mapping[str, Any], str, int | None, str, Via | None]]:
    """The array of tables `key` as (table, name, offset, type, via), checking the keys every entry needs; an
    unknown key is an error, since a misspelt 'hihg' would otherwise silently be ignored."""
    entries = data.get(key, [])
    if not isinstance(entries, list) or not all(isinstance(t, Mapping) for t in entries):
        raise SpaceError(f"'{key}' must be an array of tables ([[{key}]])")
    out = []
    for i, t in enumerate(entries):
        name = t.get("name")
        if not isinstance(name, str):
            raise SpaceError(f"[[{key}]] #{i + 1}: missing or non-string 'name'")
        unknown = set(t) - {"name", "type", "slot", *_KIND_KEYS, *_VIA_KEYS} - own_keys
        if unknown:
            raise SpaceError(f"{name!r}: unknown key(s): {', '.join(sorted(unknown))}")
        kinds = [k for k in _KIND_KEYS if k in t]
        if len(kinds) > 1:
            raise SpaceError(f"{name!r}: {' and '.join(kinds)}: a parameter reaches the program one way; give one")
        kind = kinds[0] if kinds else "offset"
        type_ = t.get("type", "float")
        if not isinstance(type_, str):
            raise SpaceError(f"{name!r}: type must be a string ({', '.join(SPACE_TYPES)})")
        offset, via = None, None
        if kind == "offset":
            offset = t.get("offset")
            if isinstance(offset, bool) or not isinstance(offset, int):
                raise SpaceError(f"{name!r}: missing or non-integer 'offset' (or say how else it reaches the "
                                 f"program: {', '.join(KINDS)})")
        else:
            via = _via(name, kind, t)
        if via is None or via.kind != "file":
            stray = sorted(_VIA_KEYS & set(t))
            if stray:
                raise SpaceError(f"{name!r}: {', '.join(stray)} belongs to a file parameter (file = \"...\")")
        out.append((t, name, offset, type_, via))
    return out


def _via(name: str, kind: str, t: Mapping[str, Any]) -> Via:
    value = t[kind]
    if kind == "source":
        if not isinstance(value, Mapping) or set(value) != {"file", "match"} or not all(
                isinstance(v, str) and v for v in value.values()):
            raise SpaceError(f"{name!r}: source must be {{ file = \"app/pid.h\", match = \"KP = (.*);\" }}")
        return Via(kind, value["file"], value["match"])
    if not isinstance(value, str) or not value:
        raise SpaceError(f"{name!r}: {kind} must be a non-empty string")
    if kind == "file":
        template, template_file = t.get("template"), t.get("template_file")
        if not all(v is None or isinstance(v, str) for v in (template, template_file)):
            raise SpaceError(f"{name!r}: template and template_file are strings")
        return Via(kind, value, None, template, template_file)
    return Via(kind, value)


def _number(table: Mapping[str, Any], key: str, name: str) -> float:
    value = table.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SpaceError(f"{name!r}: missing or non-numeric '{key}'")
    return float(value)
