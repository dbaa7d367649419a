"""The search space of a campaign: which float32 control parameters are searched, in what ranges, and which
are held fixed.

A parameter is identified by its data offset in `unity_mmap.bin`'s parameter area, because that offset is
what the robot app reads (`read_f32(0x090F0000 + offset)`); the name is for people, plots and the journal.
The paper's experiment (Kp, Ki, Kd in [0, 5], motor power 15) is `ParameterSpace.default()`; any other is a
small TOML file (see docs/space-example.toml), so a user can search a line threshold or the motor power
without touching code.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from hakoniwa.clickutil import FLOAT32_MAX
from hakoniwa.wire.protocol import PARAM_END, Rx
from testctl import paper

_FLOAT_SIZE = 4
_LAST_OFFSET = PARAM_END - _FLOAT_SIZE


class SpaceError(ValueError):
    """A parameter-space description is unusable; the message is one line naming the problem."""


@dataclass(frozen=True)
class Parameter:
    """A searched, continuous float32 parameter."""

    name: str
    offset: int
    low: float
    high: float


@dataclass(frozen=True)
class FixedParameter:
    """A float32 parameter written with the same value in every test (e.g. the paper's motor power 15)."""

    name: str
    offset: int
    value: float


@dataclass(frozen=True)
class ParameterSpace:
    """Searched and fixed parameters; construction validates offsets, names and ranges."""

    params: tuple[Parameter, ...]
    fixed: tuple[FixedParameter, ...] = ()

    def __post_init__(self) -> None:
        if not self.params:
            raise SpaceError("the space has no searched parameter")
        seen_names: set[str] = set()
        seen_offsets: dict[int, str] = {}
        for p in (*self.params, *self.fixed):
            if not p.name:
                raise SpaceError("a parameter has an empty name")
            if p.name in seen_names:
                raise SpaceError(f"parameter name {p.name!r} is used twice")
            seen_names.add(p.name)
            _check_offset(p.name, p.offset)
            if p.offset in seen_offsets:
                raise SpaceError(f"{p.name!r} and {seen_offsets[p.offset]!r} share offset {p.offset}")
            seen_offsets[p.offset] = p.name
        for p in self.params:
            _check_float32(p.name, "low", p.low)
            _check_float32(p.name, "high", p.high)
            if p.low >= p.high:
                raise SpaceError(f"{p.name!r}: low {p.low} must be below high {p.high}")
        for f in self.fixed:
            _check_float32(f.name, "value", f.value)

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

    def to_offsets(self, x: Sequence[float]) -> dict[int, float]:
        """What the trial runner writes: {data offset: value} for a point `x` (in `names` order) plus the fixed
        parameters."""
        if len(x) != self.dim:
            raise ValueError(f"point has {len(x)} coordinates, the space has {self.dim}")
        values = {p.offset: float(v) for p, v in zip(self.params, x)}
        values.update((f.offset, f.value) for f in self.fixed)
        return values

    def to_named(self, x: Sequence[float]) -> dict[str, float]:
        return {p.name: float(v) for p, v in zip(self.params, x, strict=True)}

    def from_named(self, values: Mapping[str, float]) -> tuple[float, ...]:
        """The inverse of `to_named`; a missing name is a KeyError."""
        return tuple(float(values[p.name]) for p in self.params)

    def to_dict(self) -> dict[str, Any]:
        """The TOML file's structure; used for the journal header, where equality means 'same space'."""
        return {
            "param": [{"name": p.name, "offset": p.offset, "low": p.low, "high": p.high} for p in self.params],
            "fixed": [{"name": f.name, "offset": f.offset, "value": f.value} for f in self.fixed],
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> ParameterSpace:
        if not isinstance(data, Mapping):
            raise SpaceError("the space description is not a table")
        unknown = set(data) - {"param", "fixed"}
        if unknown:
            raise SpaceError(f"unknown top-level key(s): {', '.join(sorted(unknown))}")
        params = tuple(
            Parameter(name, offset, _number(t, "low", name), _number(t, "high", name))
            for t, name, offset in _entries(data, "param", {"low", "high"})
        )
        fixed = tuple(
            FixedParameter(name, offset, _number(t, "value", name))
            for t, name, offset in _entries(data, "fixed", {"value"})
        )
        return cls(params, fixed)

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
        parts = [f"{p.name}@{p.offset}[{p.low:g},{p.high:g}]" for p in self.params]
        parts += [f"{f.name}@{f.offset}={f.value:g}" for f in self.fixed]
        return " ".join(parts)


def _check_float32(name: str, what: str, value: float) -> None:
    """Every slot is a float32: a value it cannot hold would fail inside a worker, test after test."""
    if not (math.isfinite(value) and abs(value) <= FLOAT32_MAX):
        raise SpaceError(f"{name!r}: {what} {value!r} does not fit a float32 slot (a finite number within "
                         f"±{FLOAT32_MAX:.7g})")


def _check_offset(name: str, offset: int) -> None:
    if not Rx.PARAMS <= offset <= _LAST_OFFSET:
        raise SpaceError(f"{name!r}: offset {offset} is outside the parameter area {Rx.PARAMS}..{_LAST_OFFSET}")
    if offset % _FLOAT_SIZE:
        raise SpaceError(f"{name!r}: offset {offset} is not {_FLOAT_SIZE}-byte aligned")


def _entries(data: Mapping[str, Any], key: str, own_keys: set[str]) -> list[tuple[Mapping[str, Any], str, int]]:
    """The array of tables `key` as (table, name, offset), checking the keys every entry needs; an unknown key
    is an error, since a misspelt 'hihg' would otherwise silently be ignored."""
    entries = data.get(key, [])
    if not isinstance(entries, list) or not all(isinstance(t, Mapping) for t in entries):
        raise SpaceError(f"'{key}' must be an array of tables ([[{key}]])")
    out = []
    for i, t in enumerate(entries):
        name = t.get("name")
        if not isinstance(name, str):
            raise SpaceError(f"[[{key}]] #{i + 1}: missing or non-string 'name'")
        offset = t.get("offset")
        if isinstance(offset, bool) or not isinstance(offset, int):
            raise SpaceError(f"{name!r}: missing or non-integer 'offset'")
        unknown = set(t) - {"name", "offset"} - own_keys
        if unknown:
            raise SpaceError(f"{name!r}: unknown key(s): {', '.join(sorted(unknown))}")
        out.append((t, name, offset))
    return out


def _number(table: Mapping[str, Any], key: str, name: str) -> float:
    value = table.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SpaceError(f"{name!r}: missing or non-numeric '{key}'")
    return float(value)
