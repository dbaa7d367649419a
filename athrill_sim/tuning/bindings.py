"""How a parameter reaches a program that was not written for the bench: the forms in one table, and the
parameters of forms other than `offset` as the physics process is told them (`--bindings`, JSON the
controller makes from the space).

Adding a form is one module in `athrill_sim/tuning/forms/` (a `Form` subclass) and one line of `FORMS`: the space
file parses it, the journal records it, the tuning applies it for each test and best.patch writes it, all
through the form's own methods.
"""

from __future__ import annotations

import json
from dataclasses import asdict

from athrill_sim.tuning.forms.define import Define
from athrill_sim.tuning.forms.file import File
from athrill_sim.tuning.forms.form import Binding, BindingError, Form
from athrill_sim.tuning.forms.ini import Ini
from athrill_sim.tuning.forms.offset import Offset
from athrill_sim.tuning.forms.row import Row
from athrill_sim.tuning.forms.source import Source
from athrill_sim.tuning.forms.symbol import Symbol
from hakoniwa.wire.params import FLOAT_TYPES, INT_TYPES

# By the key that names each in a [[param]] table; a parameter that names none is the first's.
FORMS: dict[str, type[Form]] = {form.key: form for form in (Offset, Define, Symbol, File, Source, Row, Ini)}
DEFAULT_FORM = next(iter(FORMS.values()))
SPACE_TYPES = ("float", "int", *FLOAT_TYPES, *INT_TYPES)  # what a space's `type` may say


def to_json(bindings: tuple[Binding, ...]) -> str:
    return json.dumps([{"name": b.name, "form": b.form.key, "where": asdict(b.form), "slot": b.slot, "low": b.low,
                        "high": b.high, "type": b.type} for b in bindings], sort_keys=True)


def from_json(text: str) -> tuple[Binding, ...]:
    try:
        data = json.loads(text)
        entries = [dict(entry) for entry in data]
    except (ValueError, TypeError) as e:
        raise BindingError(f"--bindings is not a list of parameter bindings: {e}") from None
    out = []
    for entry in entries:
        form = FORMS.get(str(entry.get("form")))
        if form is None or entry.get("type", "float") not in SPACE_TYPES:
            raise BindingError(f"--bindings: {entry.get('name')!r} has form {entry.get('form')!r} and type "
                               f"{entry.get('type')!r}")
        try:
            out.append(Binding(entry["name"], form(**entry["where"]), entry["slot"], entry["low"], entry["high"],
                               entry.get("type", "float")))
        except (KeyError, TypeError) as e:
            raise BindingError(f"--bindings is not a list of parameter bindings: {e}") from None
    return tuple(out)
