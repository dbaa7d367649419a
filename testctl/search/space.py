"""The search space of a campaign: which control parameters are searched, in what ranges, which are held
fixed, and how each reaches the robot program.

The paper's programs read their parameters from guest memory, so a parameter is by default an `offset` in
`unity_mmap.bin`'s parameter area: what the app reads (`read_f32(0x090F0000 + offset)`). A program written
without the bench keeps its gains elsewhere, and a parameter may say so instead, in another of the forms
`athrill_sim.tuning.bindings.FORMS` lists: `define = "KP"` (built with -DKP=value), `symbol = "g_kp"` (a global's
initial value), `file = "gains.csv"` (a data file written from a template) or `source = { file, match }` (a
constant in the source, rewritten). Each form parses its own keys (`athrill_sim.tuning.forms`). Every parameter still
travels through a slot of the parameter area (`hakoniwa.wire.params`): an `offset` one in its own, the others in
slots allocated from the top of the area in the space's order, so the wire stays the one contract and a cluster
needs nothing else. `type = "int"` makes a parameter an integer,
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

from athrill_sim.tuning.bindings import DEFAULT_FORM, FORMS, SPACE_TYPES, to_json
from athrill_sim.tuning.forms.form import Binding, BindingError, Form
from athrill_sim.tuning.forms.offset import Offset
from hakoniwa.conventions import FLOAT32_MAX
from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.params import CARRIER, FIRST_SLOT, FLOAT_TYPES, INT_TYPES, SLOT_ALIGN, int_range, slot_size
from hakoniwa.wire.protocol import PARAM_END, Rx
from testctl import paper


class SpaceError(HakoError, ValueError):
    """A parameter-space description is unusable; the message is one line naming the problem."""


@dataclass(frozen=True)
class Parameter:
    """A searched parameter: continuous, or an integer (`type = "int"` or an integer storage type)."""

    name: str
    offset: int | None  # None: it reaches the program `via` another form
    low: float
    high: float
    type: str = "float"
    via: Form | None = None  # the form it reaches the program by, when that is not its `offset`

    @property
    def form(self) -> Form:
        if self.via is not None:
            return self.via
        assert self.offset is not None  # a space refuses a parameter with neither
        return Offset(self.offset)

    @property
    def integer(self) -> bool:
        return self.type == "int" or self.type in INT_TYPES

    @property
    def kind(self) -> str:
        """Its form's name: `offset`, `define`, ..."""
        return self.form.key

    @property
    def storage(self) -> str:
        """What its slot holds: an `offset` parameter's slot is the program's own variable (float32 unless the
        type says otherwise); every other form's slot carries the value exactly as an f64."""
        return self.form.storage(self.type)

    @property
    def range_type(self) -> str:
        """The type whose values the parameter must stay within: what the program reads (a float32 unless it
        says f64; an int unless it says which), which is also an `offset` parameter's storage."""
        return {"float": "f32", "int": "i32"}.get(self.type, self.type)

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, **self.form.toml(), "low": self.low, "high": self.high,
                **({"type": self.type} if self.type != "float" else {})}


@dataclass(frozen=True)
class FixedParameter(Parameter):
    """A parameter written with the same value in every test (e.g. the paper's motor power 15)."""

    def __init__(self, name: str, offset: int | None, value: float, type: str = "float", via: Form | None = None):
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
    """Searched and fixed parameters; construction validates forms, slots, names and ranges."""

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
                raise SpaceError(f"{p.name!r}: give exactly one of {', '.join(FORMS)}")
            try:
                p.form.check_param(p.name, p.storage)
            except BindingError as e:
                raise SpaceError(str(e)) from None
            key = p.form.sets(p.name)
            if key in targets:
                raise SpaceError(p.form.conflict(p.name, targets[key]))
            targets[key] = p.name
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
        own = [(p, p.offset) for p in self.every if p.offset is not None]  # the others come `via` a form
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
        """What the test runner writes: {slot offset: value} for a point `x` (in `names` order) plus the fixed
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
        """How the parameters of other forms than `offset` reach the program, for the bench
        (`BenchOptions.bindings`); None when every parameter is an `offset`."""
        bound = tuple(Binding(p.name, p.via, self.slots[p.name], p.low, p.high, p.type)
                      for p in self.every if p.via is not None)
        return to_json(bound) if bound else None

    def to_named(self, x: Sequence[float]) -> dict[str, float]:
        return {p.name: float(v) for p, v in zip(self.params, self.snap(x), strict=True)}

    def from_named(self, values: Mapping[str, float]) -> tuple[float, ...]:
        """The inverse of `to_named`; a missing name is a KeyError."""
        return tuple(float(values[p.name]) for p in self.params)

    def to_dict(self) -> dict[str, Any]:
        """The TOML file's structure, with each slot a form other than `offset` got; used for the journal
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
        parts = [f"{p.name}{p.form.at()}[{p.low:g},{p.high:g}]" for p in self.params]
        parts += [f"{f.name}{f.form.at()}={f.value:g}" for f in self.fixed]
        return " ".join(parts)


def _check_value(p: Parameter, what: str, value: float) -> None:
    """A value its slot, or the program's variable, cannot hold would fail inside a worker, test after test."""
    range_type = p.range_type
    if range_type in FLOAT_TYPES:
        limit = FLOAT32_MAX if range_type == "f32" else math.inf
        if not (math.isfinite(value) and abs(value) <= limit):
            raise SpaceError(f"{p.name!r}: {what} {value!r} does not fit a float32 slot (a finite number within "
                             f"±{FLOAT32_MAX:.7g})" if range_type == "f32"
                             else f"{p.name!r}: {what} {value!r} is not finite")
        return
    lo, hi = int_range(range_type)
    if not (math.isfinite(value) and value == int(value) and lo <= value <= hi):
        raise SpaceError(f"{p.name!r}: {what} {value!r} is not an integer of {range_type} ({lo}..{hi})")


def _entries(data: Mapping[str, Any], key: str, own_keys: set[str]
             ) -> list[tuple[Mapping[str, Any], str, int | None, str, Form | None]]:
    """The array of tables `key` as (table, name, offset, type, via), checking the keys every entry needs; an
    unknown key is an error, since a misspelt 'hihg' would otherwise silently be ignored."""
    entries = data.get(key, [])
    if not isinstance(entries, list) or not all(isinstance(t, Mapping) for t in entries):
        raise SpaceError(f"'{key}' must be an array of tables ([[{key}]])")
    form_keys = {k for form in FORMS.values() for k in form.table_keys}
    out = []
    for i, t in enumerate(entries):
        name = t.get("name")
        if not isinstance(name, str):
            raise SpaceError(f"[[{key}]] #{i + 1}: missing or non-string 'name'")
        unknown = set(t) - {"name", "type", "slot", *FORMS, *form_keys} - own_keys
        if unknown:
            raise SpaceError(f"{name!r}: unknown key(s): {', '.join(sorted(unknown))}")
        given = [k for k in FORMS if k in t]
        if len(given) > 1:
            raise SpaceError(f"{name!r}: {' and '.join(given)}: a parameter reaches the program one way; give one")
        form_class = FORMS[given[0]] if given else DEFAULT_FORM
        type_ = t.get("type", "float")
        if not isinstance(type_, str):
            raise SpaceError(f"{name!r}: type must be a string ({', '.join(SPACE_TYPES)})")
        try:
            form = form_class.parse(name, t)
        except BindingError as e:
            others = ", ".join(k for k, f in FORMS.items() if f is not form_class)
            hint = "" if form_class is not DEFAULT_FORM else f" (or say how else it reaches the program: {others})"
            raise SpaceError(f"{e}{hint}") from None
        for other in FORMS.values():
            stray = sorted(other.table_keys & set(t)) if other is not form_class else []
            if stray:
                raise SpaceError(f"{name!r}: {', '.join(stray)} belongs to a {other.key} parameter ({other.key} = "
                                 '"...")')
        offset = form.own_offset
        out.append((t, name, offset, type_, None if offset is not None else form))
    return out


def _number(table: Mapping[str, Any], key: str, name: str) -> float:
    value = table.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SpaceError(f"{name!r}: missing or non-numeric '{key}'")
    return float(value)
