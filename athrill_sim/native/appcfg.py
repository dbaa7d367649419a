"""`app.cfg` as the native kernel's tables: `kernel_cfg.h` (the object IDs) and `kernel_cfg.c`.

As TOPPERS' configurator does, the file goes through the C preprocessor first (with TOPPERS_MACRO_ONLY, so
headers contribute macros only); each static API's arguments are then copied into `kernel_cfg.c` as C
expressions for the compiler to evaluate, so priorities, stack sizes and periods may use any macro or
constant of the program's headers, and a wrong one is a compiler error that names it.

Static APIs:
- `CRE_TSK(ID, { attr, exinf, task, priority, stack size, stack })`: a task; TA_ACT starts it.
- `EV3_CRE_CYC(ID, { attr, exinf, handler, period, phase })`: EV3RT's cyclic handler, times in
  milliseconds; TA_STA starts it, as do `ev3_sta_cyc` / `ev3_stp_cyc`.
- `CRE_CYC(ID, { attr, { TNFY_HANDLER, exinf, handler } or { TNFY_ACTTSK | TNFY_WUPTSK, task }, period,
  phase })`: ASP3's cyclic handler, times in microseconds; `sta_cyc` / `stp_cyc`. The two kinds are numbered
  apart, each from 1, as on EV3RT, where `ev3_sta_cyc` takes only an EV3 cyclic's ID (else E_ID).
- `INCLUDE("file.cfg")`: read from the program's folder; EV3RT's own configuration files are skipped.
- `DOMAIN(...) { }`, `ATT_MOD(...)` and `ATT_INI(...)` (HRP3: memory protection, initialization routines) are
  skipped. Anything else is an error that names it.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from athrill_sim.native import NativeBuildError

KERNEL_CFG_H = "kernel_cfg.h"
KERNEL_CFG_C = "kernel_cfg.c"
SYSTEM_CFGS = frozenset({"app_common.cfg", "tecsgen.cfg", "ev3api.cfg", "ev3.cfg", "target_kernel.cfg",
                         "syssvc/syslog.cfg", "syssvc/serial.cfg", "syssvc/banner.cfg", "syssvc/logtask.cfg"})
SKIPPED = frozenset({"DOMAIN", "KERNEL_DOMAIN", "ATT_MOD", "ATT_INI"})
SUPPORTED = ("CRE_TSK", "EV3_CRE_CYC", "CRE_CYC", "INCLUDE", *sorted(SKIPPED))
# A program given as one .c file: its main_task is the one task, as in EV3RT's samples.
DEFAULT_CFG = "CRE_TSK(MAIN_TASK, { TA_ACT, 0, main_task, TMIN_APP_TPRI + 1, STACK_SIZE, NULL });"
KERNEL_HEADERS = ('"kernel.h"', '"ev3.h"', '"hako_cfg.h"')

_TOKEN = re.compile(r'\s+|"(?:\\.|[^"\\])*"|\'(?:\\.|[^\'\\])*\'|[A-Za-z_]\w*|\d[\w.]*|.', re.S)
_INCLUDE_LINE = re.compile(r'^\s*#\s*include\s*([<"][^>"]+[>"])', re.M)
_IDENT = re.compile(r"[A-Za-z_]\w*")
_API = re.compile(r"[A-Z][A-Z0-9_]*")
_NESTING = {"(": 1, "{": 1, "[": 1, ")": -1, "}": -1, "]": -1}

Preprocess = Callable[[Path], str]  # a .cfg file through the C preprocessor (NativeBuildError on failure)


@dataclass(frozen=True)
class Task:
    name: str
    attr: str
    exinf: str
    entry: str
    priority: str
    stack_size: str


@dataclass(frozen=True)
class Cyclic:
    name: str
    attr: str
    notify: str  # a hako_notify initializer
    handler: str | None  # the function it calls, if any
    period_us: str
    phase_us: str
    ev3: bool  # EV3_CRE_CYC (its ID is ev3_sta_cyc's), else CRE_CYC (sta_cyc's)


@dataclass
class KernelConfig:
    tasks: list[Task]
    cyclics: list[Cyclic]
    includes: list[str]  # the #include lines of the .cfg files, for kernel_cfg.c

    def header(self) -> str:
        lines = ["/* Generated from app.cfg by athrill_sim/native/appcfg.py; do not edit. */",
                 "#ifndef HAKO_KERNEL_CFG_H", "#define HAKO_KERNEL_CFG_H",
                 f"#define TNUM_TSKID {len(self.tasks)}",
                 f"#define TNUM_CYCID {sum(not c.ev3 for c in self.cyclics)}"]
        lines += [f"#define {t.name} {i}" for i, t in enumerate(self.tasks, 1)]
        for ev3 in (True, False):
            lines += [f"#define {c.name} {i}" for i, c in enumerate((c for c in self.cyclics if c.ev3 == ev3), 1)]
        return "\n".join([*lines, "#endif", ""])

    def source(self) -> str:
        out = ["/* Generated from app.cfg by athrill_sim/native/appcfg.py; do not edit. */"]
        out += [f"#include {h}" for h in dict.fromkeys([*KERNEL_HEADERS, *self.includes, f'"{KERNEL_CFG_H}"'])]
        functions = [t.entry for t in self.tasks] + [c.handler for c in self.cyclics if c.handler]
        out += [f"void {f}(intptr_t exinf);" for f in dict.fromkeys(functions)]
        for t in self.tasks:
            out.append(f'_Static_assert(TMIN_TPRI <= ({t.priority}) && ({t.priority}) <= TMAX_TPRI, '
                       f'"CRE_TSK {t.name}: the priority must be within TMIN_TPRI..TMAX_TPRI");')
        for c in self.cyclics:
            out.append(f'_Static_assert(({c.period_us}) > 0, "{c.name}: the period must be positive");')
        out.append("const hako_task_cfg hako_task_table[] = {")
        out += [f'    {{"{t.name}", ({t.attr}), (intptr_t)({t.exinf}), {t.entry}, ({t.priority}), ({t.stack_size})}},'
                for t in self.tasks]
        out += ["    {0}", "};", f"const uint_t hako_task_count = {len(self.tasks)};",
                "const hako_cyclic_cfg hako_cyclic_table[] = {"]
        out += [f'    {{"{c.name}", ({c.attr}), {c.notify}, ({c.period_us}), ({c.phase_us}), {str(c.ev3).lower()}}},'
                for c in self.cyclics]
        out += ["    {0}", "};", f"const uint_t hako_cyclic_count = {len(self.cyclics)};", ""]
        return "\n".join(out)


def kernel_config(cfg: Path | None, preprocess: Preprocess) -> KernelConfig:
    """The kernel objects `cfg` declares (the default single task without one)."""
    reader = _Reader(preprocess)
    if cfg is None:
        reader.declare(_static_apis(DEFAULT_CFG, "the default configuration"), None)
    else:
        reader.read(cfg)
    config = reader.config
    names = [t.name for t in config.tasks] + [c.name for c in config.cyclics]
    if dup := next((n for n in names if names.count(n) > 1), None):
        raise NativeBuildError(f"{cfg}: {dup} is declared twice")
    return config


class _Reader:
    """Reads .cfg files into one KernelConfig, following INCLUDE."""

    def __init__(self, preprocess: Preprocess) -> None:
        self.config = KernelConfig([], [], [])
        self.preprocess = preprocess
        self.seen: set[Path] = set()

    def read(self, cfg: Path) -> None:
        if cfg in self.seen:
            raise NativeBuildError(f"{cfg}: INCLUDEs itself")
        self.seen.add(cfg)
        self.config.includes += _INCLUDE_LINE.findall(cfg.read_text(errors="replace"))
        self.declare(_static_apis(self.preprocess(cfg), str(cfg)), cfg)

    def declare(self, apis: list[tuple[str, list[str]]], cfg: Path | None) -> None:
        where = str(cfg) if cfg else "the default configuration"
        tasks, cyclics = self.config.tasks, self.config.cyclics
        for name, args in apis:
            if name in SKIPPED:
                continue
            if name == "INCLUDE" and cfg is not None:
                self.include(args, cfg)
            elif name == "CRE_TSK":
                ident, (attr, exinf, entry, priority, stack_size, _stack) = _object(name, args, 6, where)
                tasks.append(Task(ident, attr, exinf, _function(entry, name, where), priority, stack_size))
            elif name == "EV3_CRE_CYC":
                ident, (attr, exinf, handler, period_ms, phase_ms) = _object(name, args, 5, where)
                handler = _function(handler, name, where)
                cyclics.append(Cyclic(ident, attr, f"{{TNFY_HANDLER, (intptr_t)({exinf}), {handler}}}", handler,
                                      f"(RELTIM)({period_ms}) * 1000U", f"(RELTIM)({phase_ms}) * 1000U", True))
            elif name == "CRE_CYC":
                ident, (attr, notify, period_us, phase_us) = _object(name, args, 4, where)
                parts = _braced(notify, f"{name}({ident}) notification", where)
                if not 2 <= len(parts) <= 3:
                    raise NativeBuildError(f"{where}: {name}({ident}): the notification is {{mode, task}} or "
                                           "{mode, exinf, handler}")
                calls = _function(parts[2], name, where) if len(parts) == 3 else None
                cyclics.append(Cyclic(ident, attr, "{" + ", ".join(parts) + "}", calls, period_us, phase_us, False))
            else:
                raise NativeBuildError(f"{where}: {name} is not supported by the native mock (it supports "
                                       f"{', '.join(SUPPORTED)}; see docs/NATIVE.md)")

    def include(self, args: list[str], cfg: Path) -> None:
        if len(args) != 1 or not args[0].startswith('"'):
            raise NativeBuildError(f"{cfg}: INCLUDE takes one file name in quotes")
        name = args[0][1:-1]
        if (cfg.parent / name).is_file():
            self.read((cfg.parent / name).resolve())
        elif name not in SYSTEM_CFGS:
            raise NativeBuildError(f"{cfg}: INCLUDE(\"{name}\"): no such file beside it")


def _object(api: str, args: list[str], count: int, where: str) -> tuple[str, list[str]]:
    if len(args) != 2 or not _IDENT.fullmatch(args[0]):
        raise NativeBuildError(f"{where}: {api} takes an ID and {{ ... }}")
    values = _braced(args[1], f"{api}({args[0]})", where)
    if len(values) != count:
        raise NativeBuildError(f"{where}: {api}({args[0]}) takes {count} values in braces, got {len(values)}")
    return args[0], values


def _braced(text: str, what: str, where: str) -> list[str]:
    text = text.strip()
    if not (text.startswith("{") and text.endswith("}")):
        raise NativeBuildError(f"{where}: {what}: expected {{ ... }}")
    return _split(_tokens(text[1:-1]), where)


def _function(name: str, api: str, where: str) -> str:
    if not _IDENT.fullmatch(name):
        raise NativeBuildError(f"{where}: {api}: {name!r} is not a function name")
    return name


def _tokens(text: str) -> list[str]:
    return [t for t in _TOKEN.findall(text) if not t.isspace()]


def _split(tokens: list[str], where: str) -> list[str]:
    """Comma-separated arguments at the top nesting level, each joined back into text."""
    args: list[list[str]] = [[]]
    depth = 0
    for t in tokens:
        depth += _NESTING.get(t, 0)
        if depth < 0:
            raise NativeBuildError(f"{where}: unbalanced {t!r}")
        if t == "," and depth == 0:
            args.append([])
        else:
            args[-1].append(t)
    return [" ".join(a) for a in args] if any(args) else []


def _static_apis(text: str, where: str) -> list[tuple[str, list[str]]]:
    """The static API calls in preprocessed .cfg text, in order. Anything at statement level that is not an
    upper-case call (a C declaration from a header not guarded by TOPPERS_MACRO_ONLY) is skipped to its `;`."""
    tokens = _tokens(text)
    apis = []
    i = 0
    while i < len(tokens):
        t = tokens[i]
        if t in (";", "{", "}"):
            i += 1
        elif _API.fullmatch(t) and i + 1 < len(tokens) and tokens[i + 1] == "(":
            end = _closing(tokens, i + 1, where)
            apis.append((t, _split(tokens[i + 2:end], where)))
            i = end + 1
        else:
            i = _statement_end(tokens, i)
    return apis


def _closing(tokens: list[str], open_at: int, where: str) -> int:
    depth = 0
    for j in range(open_at, len(tokens)):
        depth += _NESTING.get(tokens[j], 0)
        if depth == 0:
            return j
    raise NativeBuildError(f"{where}: {tokens[open_at - 1]}( is never closed")


def _statement_end(tokens: list[str], i: int) -> int:
    depth = 0
    while i < len(tokens):
        depth += _NESTING.get(tokens[i], 0)
        i += 1
        if depth == 0 and tokens[i - 1] == ";":
            break
    return i
