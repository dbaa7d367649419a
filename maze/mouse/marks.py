"""What a mouse program paints on the maze (mms's setColor / setText and their clears), kept in order with the
number of walls it had sensed by then, so that a film can show them as they were."""

from __future__ import annotations

from dataclasses import dataclass

from ..model import Cell

CLEAR_ALL: Cell = (-1, -1)  # the cell of a clearAllColor / clearAllText mark


@dataclass(frozen=True)
class Mark:
    records: int  # sensed records when it was made
    cell: Cell
    colour: str | None = None  # None: leaves the colour alone; "": clears it
    text: str | None = None  # likewise


def marks_at(marks: list[Mark], records: int) -> dict[Cell, tuple[str, str]]:
    """Each painted cell's (colour letter, text) once `records` walls had been sensed."""
    state: dict[Cell, list[str]] = {}
    for mark in marks:
        if mark.records > records:
            break
        cells = list(state.values()) if mark.cell == CLEAR_ALL else [state.setdefault(mark.cell, ["", ""])]
        for entry in cells:
            if mark.colour is not None:
                entry[0] = mark.colour
            if mark.text is not None:
                entry[1] = mark.text
    return {cell: (c, t) for cell, (c, t) in state.items() if c or t}
