"""`offset = 540`: the paper's form. The program reads the value itself, from guest memory at `0x090F0000 +
offset` (the parameter area of `unity_mmap.bin`), in the slot's own type: nothing of the program changes, so
nothing is checked, applied or patched on its side."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from athrill_sim.tuning.forms.form import BindingError, Form
from hakoniwa.wire.params import SLOT_ALIGN, fits_area
from hakoniwa.wire.protocol import PARAM_END, Rx

_LAST_OFFSET = PARAM_END - 4


@dataclass(frozen=True)
class Offset(Form):
    key = "offset"

    offset: int

    @classmethod
    def parse(cls, name: str, table: Mapping[str, Any]) -> Offset:
        offset = table.get("offset")
        if isinstance(offset, bool) or not isinstance(offset, int):
            raise BindingError(f"{name!r}: missing or non-integer 'offset'")
        return cls(offset)

    def toml(self) -> dict[str, Any]:
        return {"offset": self.offset}

    def describe(self) -> str:
        return f"offset {self.offset}"

    def at(self) -> str:
        return f"@{self.offset}"

    def conflict(self, name: str, other: str) -> str:
        return f"{name!r} and {other!r} share offset {self.offset}"

    @property
    def own_offset(self) -> int:
        return self.offset

    def storage(self, type_: str) -> str:
        """The program's own variable: a float32 unless the type says otherwise."""
        return {"float": "f32", "int": "i32"}.get(type_, type_)

    def check_param(self, name: str, storage: str) -> None:
        if not Rx.PARAMS <= self.offset <= _LAST_OFFSET:
            raise BindingError(f"{name!r}: offset {self.offset} is outside the parameter area "
                               f"{Rx.PARAMS}..{_LAST_OFFSET}")
        if self.offset % SLOT_ALIGN:
            raise BindingError(f"{name!r}: offset {self.offset} is not {SLOT_ALIGN}-byte aligned")
        if not fits_area(self.offset, storage):
            raise BindingError(f"{name!r}: an {storage} at offset {self.offset} runs past the parameter area's end "
                               f"{PARAM_END}")
