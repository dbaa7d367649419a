"""The results printed in docs/, made by running the commands that print them, so a doc cannot drift from the code.

Each result in the docs sits between markers: `<!-- doc-results: NAME -->` ... `<!-- /doc-results -->` in
Markdown (on a line of their own, or inside a table cell), `# doc-results: NAME` ... `# /doc-results` in TOML.
A block named `console` is a shell session: its `$ ` lines are run in order with bash in an empty folder (with
the project's `tests/` beside them) and what they print follows each. Any other name is one of RESULTS: a
command run once, its output written into each of its views (a console excerpt, a table cell, a comment).

Usage: python scripts/doc_results.py [--check] [--all] [--only NAME]...
Without --check the docs are rewritten; with it nothing is written, and the exit status is 1 when a doc's result
differs from what the code prints now. The console blocks take seconds and run by default; RESULTS' campaigns
take minutes and run with --all (`tests/project/test_doc_results.py`: the console blocks in the fast suite, the rest
slow). Every command is exactly repeatable (fixed seeds, one bench); wall times are the only thing compared
loosely (VOLATILE), and a doc keeps its own figure for them.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import click

REPO = Path(__file__).resolve().parents[1]
DOCS = ("docs/MAZELOG.md", "docs/CI.md", "docs/BENCHMARKS.md", "docs/examples/hako-tests.toml")
BLOCK = re.compile(r"(?P<open>(?:<!-- |# )doc-results: (?P<name>[\w-]+)(?: -->)?\n?)(?P<body>.*?)"
                   r"(?P<close>(?:<!-- |# )/doc-results(?: -->)?)", re.DOTALL)
CONSOLE = "console"
PROMPT = "$ "
FENCE = "```"
VOLATILE = (re.compile(r"(?<= in )\d+\.\d+(?= s$)"),)  # `commands: 1533 in 0.23 s`: a wall time
COMMAND_TIMEOUT_S = 1800


@dataclass(frozen=True)
class Result:
    """A command whose output the docs quote: `views` turn its stdout into each quoted piece, by block name."""

    argv: tuple[str, ...]  # `{out}` is a fresh output folder
    views: dict[str, Callable[[str], str]]


def _field(pattern: str, text: str) -> re.Match[str]:
    found = re.search(pattern, text, re.MULTILINE)
    if found is None:
        raise click.ClickException(f"the output has no line matching {pattern!r}:\n{text}")
    return found


VALIDATE = ("hako", "run", "--trials", "20", "--validate", "30", "--out", "runs/x")
BEST = r"^best: \[(?P<params>[^\]]*)\] lap (?P<lap>[\d.]+) s \(set (?P<set>\d+)\)$"
VALIDATION = (r"^validation on (?P<draws>\d+) fresh noise draws: (?P<goals>\d+)/\d+ reached GOAL .*lap p50 "
              r"(?P<p50>[\d.]+) s, p90 (?P<p90>[\d.]+) s .*$")
TESTS = r"^sets: (?P<sets>\d+), tests: (?P<tests>\d+)"


def _params(best: re.Match[str]) -> str:
    """`Kp 3.633, Ki 0, Kd 0` from `Kp=3.633, Ki=0.000, Kd=0.000`."""
    return ", ".join(f"{name} {float(value):g}" for name, value in (p.split("=") for p in best["params"].split(", ")))


def validate_console(out: str) -> str:
    return "\n".join([FENCE, PROMPT + " ".join(VALIDATE), _field(BEST, out)[0], "...", _field(VALIDATION, out)[0],
                      FENCE]) + "\n"


def validate_row(out: str) -> str:
    best, val = _field(BEST, out), _field(VALIDATION, out)
    return (f"best {_params(best)} (set {best['set']}), campaign estimate {best['lap']} s; on {val['draws']} fresh "
            f"draws {val['goals']}/{val['draws']} GOAL, p50 {val['p50']} s, p90 {val['p90']} s")


def validate_comment(out: str) -> str:
    best, val = _field(BEST, out), _field(VALIDATION, out)
    return (f"# `{' '.join(VALIDATE[:6])}` now finds {_params(best)}: lap {best['lap']} s, {val['goals']}/"
            f"{val['draws']} GOAL, p50 {val['p50']} s, p90 {val['p90']} s\n")


def space_row(out: str) -> str:
    best, counts = _field(BEST, out), _field(TESTS, out)
    return (f"best {best['lap']} s (mean of its laps) at {_params(best)} (set {best['set']} of {counts['sets']}), "
            f"{counts['tests']} tests")


RESULTS: dict[str, Result] = {
    "validate-example": Result(("hako", "run", "--trials", "20", "--validate", "30", "--out", "{out}"),
                               {"validate-example-console": validate_console, "validate-example-row": validate_row,
                                "validate-example-comment": validate_comment}),
    "space-example": Result(("hako", "run", "--space", "docs/space-example.toml", "--validate", "0", "--out",
                             "{out}"), {"space-example-row": space_row}),
}
VIEWS = {view: name for name, result in RESULTS.items() for view in result.views}


def loose(text: str) -> str:
    """The text with its wall times blanked, for comparing runs."""
    lines = text.splitlines()
    for pattern in VOLATILE:
        lines = [pattern.sub("#", line) for line in lines]
    return "\n".join(lines)


def keep_volatile(old: str, new: str) -> str:
    """`new`, but each line that differs from `old`'s only in a wall time keeps `old`'s, so a rerun changes
    nothing that has not changed."""
    old_lines, new_lines = old.splitlines(keepends=True), new.splitlines(keepends=True)
    if len(old_lines) != len(new_lines):
        return new
    return "".join(o if loose(o) == loose(n) else n for o, n in zip(old_lines, new_lines))


def run_console(body: str) -> str:
    """The session's commands, each followed by what it prints now (stdout and stderr as a terminal shows them)."""
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}",
           "COLUMNS": "120"}
    lines = body.splitlines()
    fence = [line for line in lines if line.startswith(FENCE)]
    commands = [line for line in lines if line.startswith(PROMPT)]
    out = [fence[0]] if fence else []
    with tempfile.TemporaryDirectory(prefix="doc-results-") as folder:
        (Path(folder) / "tests").symlink_to(REPO / "tests")
        for line in commands:
            done = subprocess.run(["bash", "-c", line[len(PROMPT):]], cwd=folder, env=env, stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True, timeout=COMMAND_TIMEOUT_S)
            out.append(line)
            out.extend(done.stdout.rstrip("\n").splitlines())
    return "\n".join(out + [FENCE] * bool(fence)) + "\n"


def run_result(name: str) -> str:
    with tempfile.TemporaryDirectory(prefix="doc-results-") as folder:
        argv = [a.replace("{out}", str(Path(folder) / "out")) for a in RESULTS[name].argv]
        done = subprocess.run(argv, cwd=REPO, capture_output=True, text=True, timeout=COMMAND_TIMEOUT_S)
    if done.returncode != 0:
        raise click.ClickException(f"{' '.join(argv)} exited with {done.returncode}: {done.stderr.strip()[-500:]}")
    return done.stdout


@dataclass
class Drift:
    doc: str
    name: str
    old: str
    new: str


def refresh(text: str, doc: str, wanted: Callable[[str], bool], outputs: dict[str, str]) -> tuple[str, list[Drift]]:
    """`text` with each wanted block made from what its command prints now, and the blocks that changed.
    `outputs` caches each result's output across blocks and docs."""
    drifts: list[Drift] = []

    def block(m: re.Match[str]) -> str:
        name, body = m["name"], m["body"]
        if not wanted(name):
            return m[0]
        if name == CONSOLE:
            new = run_console(body)
        elif name in VIEWS:
            result = VIEWS[name]
            if result not in outputs:
                outputs[result] = run_result(result)
            new = RESULTS[result].views[name](outputs[result])
            if not body.endswith("\n"):
                new = new.rstrip("\n")
        else:
            raise click.ClickException(f"{doc}: unknown result {name!r} (known: {CONSOLE}, {', '.join(VIEWS)})")
        new = keep_volatile(body, new)
        if new != body:
            drifts.append(Drift(doc, name, body, new))
        return m["open"] + new + m["close"]

    return BLOCK.sub(block, text), drifts


def chooser(only: tuple[str, ...], expensive: bool) -> Callable[[str], bool]:
    """Which blocks to make: those named, else the console sessions, and with `expensive` every block."""
    if only:
        return lambda name: name in only or VIEWS.get(name) in only
    return lambda name: expensive or name == CONSOLE


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--check", is_flag=True, help="Write nothing; exit 1 if a doc's result differs from the code's.")
@click.option("--all", "expensive", is_flag=True, help="Also the campaigns (minutes each), not only the consoles.")
@click.option("--only", multiple=True, metavar="NAME",
              help=f"Only these blocks or results ({CONSOLE}, {', '.join([*RESULTS, *VIEWS])}); repeatable.")
def main(check: bool, expensive: bool, only: tuple[str, ...]) -> None:
    """Run the commands whose results docs/ prints and put what they print now into the marked blocks."""
    wanted, outputs, drifts = chooser(only, expensive), {}, []
    for doc in DOCS:
        path = REPO / doc
        text, found = refresh(path.read_text(), doc, wanted, outputs)
        drifts += found
        if found and not check:
            path.write_text(text)
    for d in drifts:
        click.echo(f"{d.doc}: {d.name}: {'differs from' if check else 'now'} what the code prints"
                   + (f":\n--- the doc\n{d.old}--- the code\n{d.new}" if check else ""))
    if check and drifts:
        sys.exit(1)


if __name__ == "__main__":
    main()
