"""The test file (`hako-tests.toml`): named cases a user keeps beside the robot program, read and checked
whole before any test runs, so that a typo is one line at once rather than a red pipeline an hour later.

    [defaults]                      # optional: keys every case starts from
    seeds = 10

    [case.paper-gains]
    app = "line_trace"              # the bench keys: BenchOptions' own fields (course, app, time_limit_s)
    params = { Kp = 1.539, Ki = 4.267, Kd = 4.511 }
    expect = ["GOAL", "lap_s < 60", "p90 < 58", "success >= 0.9"]

    [case.tuned]
    from = "runs/paper"             # the best set of that campaign (its best.json, named by its journal's space,
    seeds = [0, 7, 42]              # each value reaching the program as its kind says); a count draws that many
    expect = ["not HIT_WALL"]

    [case.patched]
    app = "my_app"                  # a program best.patch set the tuned values in: it reads no parameter
    params = {}
    expect = ["GOAL"]

A case's bench keys are the fields of `BenchOptions` a test file may fix, read through the very click
options of the command line (so `time_limit_s = 0` is refused with the command line's words); a bench field
added there (a robot, a scenario) becomes a case key with nothing to change here. Where the emulator lives
and how long a silent one is waited for belong to the machine, not to the test, so they stay on the
command line. Relative paths are the test file's folder's.
"""

from __future__ import annotations

import dataclasses
import json
import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import click

from hakoniwa.conventions import NOISE_SCALE
from hakoniwa.wire.errors import HakoError
from testctl.bench_options import BENCH_FIELDS, BenchOptions, bench_options
from testctl.campaign.journal import JOURNAL_FILE, JournalError, read_journal
from testctl.noise_seed import SEED_BITS, noise_seed
from testctl.search.space import ParameterSpace, SpaceError
from testctl.suite.expect import Expectation, ExpectationError, parse_expectation

DEFAULT_FILE = "hako-tests.toml"
MACHINE_FIELDS = ("athrill2", "athrill_timeout_s")  # the machine's business: command line only
SPACE_FIELDS = ("bindings",)  # made from the case's space, never given
_DECLARED = {p.name: p for p in bench_options(click.Command("bench")).params}
_BENCH_PARAMS = {name: _DECLARED[name] for name in BENCH_FIELDS if name not in (*MACHINE_FIELDS, *SPACE_FIELDS)}
CASE_KEYS = (*_BENCH_PARAMS, "params", "from", "space", "seeds", "noise", "expect")
DEFAULT_SEEDS = 5
DEFAULT_NOISE = 1.0  # the course's own noise levels: a test sees the bench a campaign tunes on


class SuiteError(HakoError, ValueError):
    """The test file cannot be used; the message is one line naming the file, the case and the problem."""


@dataclass(frozen=True)
class Case:
    """One named case: the bench it runs on, what it writes into the parameter area, the noise draws it
    runs with (one test each) and what every one of them, or all of them together, must show."""

    name: str
    bench: BenchOptions  # with the space's bindings: how parameters of other kinds reach the program
    params: Mapping[int, float]  # {slot offset: value}, what the bench writes
    named: Mapping[str, float]  # the same by name, for people
    seeds: tuple[int, ...]
    noise: float
    expect: tuple[Expectation, ...]
    slot_types: Mapping[int, str] = dataclasses.field(default_factory=dict)  # slots that are not float32


def drawn_seeds(count: int) -> tuple[int, ...]:
    """The noise seeds of a case that asks for `count` draws: the same for every case, so two cases differ
    only in what they state, and never a function of a case's place in the file."""
    return tuple(noise_seed(0, 0, rep) for rep in range(1, count + 1))


def load_suite(path: Path, base: BenchOptions) -> tuple[Case, ...]:
    """Every case of the test file at `path`, on `base` (the command line's bench) with the case's own
    bench keys on top."""
    try:
        with open(path, "rb") as f:
            data = tomllib.load(f)
    except FileNotFoundError:
        raise SuiteError(f"{path}: no such test file") from None
    except OSError as e:
        raise SuiteError(f"{path}: cannot read: {e.strerror}") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
        raise SuiteError(f"{path}: not valid TOML: {e}") from None
    unknown = set(data) - {"defaults", "case"}
    if unknown:
        raise SuiteError(f"{path}: unknown top-level key(s) {', '.join(sorted(unknown))} (known: defaults, case)")
    defaults = _table(data.get("defaults", {}), f"{path}: [defaults]")
    cases = _table(data.get("case", {}), f"{path}: [case]")
    if not cases:
        raise SuiteError(f"{path}: no cases (add a [case.NAME] table)")
    folder = Path(path).resolve().parent
    out = []
    for name, table in cases.items():
        where = f"{path}: case {name!r}"
        keys = {**defaults, **_table(table, where)}
        try:
            out.append(_case(name, keys, base, folder))
        except SuiteError as e:
            raise SuiteError(f"{where}: {e}") from None
    folders: dict[str, str] = {}
    for case in out:
        other = folders.setdefault(case_folder(case.name), case.name)
        if other != case.name:
            raise SuiteError(f"{path}: cases {other!r} and {case.name!r} would share the folder "
                             f"{case_folder(case.name)!r}")
    return tuple(out)


def case_folder(case_name: str) -> str:
    """A case's name as the name of the folder its pictures go to: what a shell and every file system take."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", case_name).strip(".") or "case"


def _case(name: str, keys: dict[str, Any], base: BenchOptions, folder: Path) -> Case:
    unknown = set(keys) - set(CASE_KEYS)
    if unknown:
        raise SuiteError(f"unknown key(s) {', '.join(sorted(unknown))} (known: {', '.join(CASE_KEYS)})")
    bench = dataclasses.replace(base, **{k: _bench_value(k, keys[k], folder) for k in _BENCH_PARAMS if k in keys})
    expect = keys.get("expect")
    if not isinstance(expect, list) or not expect:
        raise SuiteError('no expectations: give expect = ["GOAL", "lap_s < 40", ...]')
    try:
        expectations = tuple(parse_expectation(e) for e in expect)
    except ExpectationError as e:
        raise SuiteError(f"expect: {e}") from None
    named, offsets, space = _params(keys, folder)
    bench = dataclasses.replace(bench, bindings=space.bindings() if space is not None else None)
    return Case(name, bench, offsets, named, _seeds(keys.get("seeds", DEFAULT_SEEDS)),
                _convert(NOISE_SCALE, keys.get("noise", DEFAULT_NOISE), "noise"), expectations,
                space.slot_types if space is not None else {})


def _bench_value(key: str, value: Any, folder: Path) -> Any:
    value = _convert(_BENCH_PARAMS[key].type, value, key)
    if isinstance(value, str) and (folder / value).exists():
        return str((folder / value).resolve())
    return value


def _convert(kind: click.ParamType, value: Any, key: str) -> Any:
    if isinstance(value, (dict, list, bool)):
        raise SuiteError(f"{key}: {value!r} is not a {kind.name}")
    try:
        return kind.convert(value, None, None)
    except click.BadParameter as e:
        raise SuiteError(f"{key}: {e.message}") from None


def _seeds(value: Any) -> tuple[int, ...]:
    if isinstance(value, bool):
        raise SuiteError(f"seeds: {value!r} is neither a count nor a list of noise seeds")
    if isinstance(value, int):
        if value < 1:
            raise SuiteError(f"seeds: a count of noise draws must be at least 1, got {value}")
        return drawn_seeds(value)
    top = 2 ** SEED_BITS - 1
    if (not isinstance(value, list) or not value
            or not all(isinstance(s, int) and not isinstance(s, bool) and 0 <= s <= top for s in value)):
        raise SuiteError(f"seeds: give a count (at least 1) or a non-empty list of noise seeds in 0..{top}")
    return tuple(value)


def _params(keys: Mapping[str, Any], folder: Path
            ) -> tuple[dict[str, float], dict[int, float], ParameterSpace | None]:
    """The case's parameters by name and by slot, and their space: a campaign's best set (`from`) or the
    fixed values of the space, with `params` on top; every parameter of the space needs a value. An empty
    `params` with neither is a program that reads no parameter (one best.patch set its values in)."""
    given = _table(keys.get("params", {}), "params")
    if "from" in keys and "space" in keys:
        raise SuiteError("give either from (a campaign folder, whose journal names the parameters) or space")
    if "params" in keys and not given and "from" not in keys and "space" not in keys:
        return {}, {}, None
    values: dict[str, float] = {}
    try:
        if "from" in keys:
            space, values = _best_set(folder / _string(keys["from"], "from"))
        elif "space" in keys:
            space = ParameterSpace.load(folder / _string(keys["space"], "space"))
        else:
            space = ParameterSpace.default()
    except SpaceError as e:
        raise SuiteError(f"space: {e}") from None
    every = (*space.params, *space.fixed)
    values = {**{f.name: f.value for f in space.fixed}, **values}
    for k, v in given.items():
        if k not in {p.name for p in every}:
            raise SuiteError(f"params: no parameter {k!r} (the space has {', '.join(p.name for p in every)})")
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise SuiteError(f"params: {k} = {v!r} is not a number")
        values[k] = float(v)
    missing = [p.name for p in every if p.name not in values]
    if missing:
        raise SuiteError(f"params: no value for {', '.join(missing)}")
    for p in every:
        if p.integer and values[p.name] != int(values[p.name]):
            raise SuiteError(f"params: {p.name} = {values[p.name]!r} is an integer parameter")
    return ({p.name: values[p.name] for p in every}, {space.slots[p.name]: values[p.name] for p in every}, space)


def _best_set(campaign: Path) -> tuple[ParameterSpace, dict[str, float]]:
    from testctl.campaign.report import BEST_JSON  # matplotlib: only for a case that reads a campaign

    best_file = campaign / BEST_JSON
    try:
        best = json.loads(best_file.read_text())
    except FileNotFoundError:
        raise SuiteError(f"from: {best_file} does not exist (is {campaign} a finished campaign?)") from None
    except (OSError, ValueError) as e:
        raise SuiteError(f"from: cannot read {best_file}: {e}") from None
    if not best.get("success"):
        raise SuiteError(f"from: the campaign in {campaign} found no successful parameter set")
    try:
        header, _ = read_journal(campaign / JOURNAL_FILE)
        space = ParameterSpace.from_dict(header["space"])
    except (JournalError, KeyError) as e:
        raise SuiteError(f"from: {campaign / JOURNAL_FILE} does not name the parameters: {e}") from None
    return space, {**best["fixed"], **best["params"]}


def _table(value: Any, where: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise SuiteError(f"{where} must be a table")
    return value


def _string(value: Any, key: str) -> str:
    if not isinstance(value, str):
        raise SuiteError(f"{key}: {value!r} is not a path")
    return value
