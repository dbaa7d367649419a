"""The mouse a time estimate is made for: speeds and accelerations from a TOML file (maze/data/mice.toml).

Frozen dataclasses, because the fast-run move graph caches its edge costs per parameter set.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, fields
from importlib.resources import files
from pathlib import Path
from typing import Any

from ..errors import MazeError

BUILTIN_FILE = "mice.toml"
CLASSIC_MAX_SIZE = 16  # mazes up to this side get the classic mouse by default, larger ones the half-size one


@dataclass(frozen=True)
class SearchParams:
    speed: float
    accel: float
    pivot_time: float


@dataclass(frozen=True)
class RunParams:
    accel: float
    top_speed: float
    diagonal_top_speed: float
    turn_speed: float
    lateral_accel: float


@dataclass(frozen=True)
class MouseParams:
    name: str
    cell: float
    search: SearchParams
    run: RunParams


def builtin_table() -> dict[str, Any]:
    return tomllib.loads(files("maze").joinpath("data", BUILTIN_FILE).read_text(encoding="utf-8"))


def default_mouse_name(size: int) -> str:
    return "classic" if size <= CLASSIC_MAX_SIZE else "halfsize"


def _section(cls: type, table: Any, where: str) -> Any:
    if not isinstance(table, dict):
        raise MazeError(f"{where}: expected a table")
    names = [f.name for f in fields(cls)]
    unknown = sorted(set(table) - set(names))
    if unknown:
        raise MazeError(f"{where}: unknown key {unknown[0]!r} (keys: {', '.join(names)})")
    missing = [n for n in names if n not in table]
    if missing:
        raise MazeError(f"{where}: missing key {missing[0]!r}")
    return cls(**{n: _positive(table[n], f"{where}.{n}") for n in names})


def _positive(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value < float("inf"):
        raise MazeError(f"{where}: must be a positive number, got {value!r}")
    return float(value)


def _merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    out = dict(base)
    for k, v in over.items():
        out[k] = _merge(base[k], v) if isinstance(v, dict) and isinstance(base.get(k), dict) else v
    return out


def mouse_from_table(name: str, table: dict[str, Any]) -> MouseParams:
    """Check the physics the time model relies on, so a bad file fails here and not as a wrong time."""
    extra = sorted(set(table) - {"cell", "search", "run"})
    if extra:
        raise MazeError(f"{name}: unknown key {extra[0]!r} (keys: cell, search, run)")
    if "cell" not in table:
        raise MazeError(f"{name}: missing key 'cell'")
    cell = _positive(table["cell"], f"{name}.cell")
    mouse = MouseParams(name, cell, _section(SearchParams, table.get("search"), f"{name}.search"),
                        _section(RunParams, table.get("run"), f"{name}.run"))
    half = cell / 2
    run, search = mouse.run, mouse.search
    if run.turn_speed > min(run.top_speed, run.diagonal_top_speed):
        raise MazeError(f"{name}.run: turn_speed must not exceed top_speed or diagonal_top_speed")
    # the first turn may come half a cell after a standing start; a search stop happens within half a cell
    if run.turn_speed ** 2 > 2 * run.accel * half:
        raise MazeError(f"{name}.run: cannot reach turn_speed {run.turn_speed} m/s within half a cell "
                        f"at accel {run.accel} m/s^2")
    if search.speed ** 2 > 2 * search.accel * half:
        raise MazeError(f"{name}.search: cannot reach speed {search.speed} m/s within half a cell "
                        f"at accel {search.accel} m/s^2")
    return mouse


def load_mouse(spec: str | None, size: int) -> MouseParams:
    """spec: a built-in name (classic, halfsize), a TOML file, or None for the built-in one that fits the size."""
    builtin = builtin_table()
    if spec is None or spec in builtin:
        name = spec or default_mouse_name(size)
        return mouse_from_table(name, builtin[name])
    path = Path(spec)
    try:
        table = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise MazeError(f"{spec}: no such mouse file (built-in mice: {', '.join(builtin)})") from None
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
        raise MazeError(f"{spec}: {e}") from None
    return mouse_from_table(path.name, _merge(builtin[default_mouse_name(size)], table))
