"""The tables of docs/BENCHMARKS.md, each rendered from the data its benchmark recorded (docs/benchmarks/NAME.json),
so that the page shows what was measured, how, where and when, and cannot drift from it.

A table sits between markers on lines of their own: `<!-- bench-table: NAME -->` ... `<!-- /bench-table -->`.
Its data is a JSON object: the `command` that measured it, the `machine` it ran on (cores, CPU, load), the
`date` (YYYY-MM-DD), and either `columns` and `rows` (the figures as a table) or `output` (the lines the command
printed, shown as printed). A page line over MAX_LINE characters is refused: a figure belongs in a cell of its
own, not in prose.

Usage:
  python scripts/benchmark_tables.py [--check]             render every table into docs/BENCHMARKS.md; with
                                                           --check write nothing, and exit 1 if a table differs
                                                           from its data
  python scripts/benchmark_tables.py record NAME -- CMD... run CMD (a benchmark script), record what it printed
                                                           as the data of table NAME, with this machine and
                                                           today's date, and render the page
                                                           (`tests/project/test_benchmark_tables.py` fails on a
                                                           table its data no longer gives)
"""

from __future__ import annotations

import datetime as dt
import json
import os
import platform
import re
import shlex
import subprocess
import sys
from pathlib import Path

import click

REPO = Path(__file__).resolve().parents[1]
PAGE = REPO / "docs" / "BENCHMARKS.md"
DATA = REPO / "docs" / "benchmarks"
MAX_LINE = 300
BLOCK = re.compile(r"^<!-- bench-table: (?P<name>[\w-]+) -->\n(?P<body>.*?)^<!-- /bench-table -->$",
                   re.DOTALL | re.MULTILINE)
FENCE = "```"


class TableError(click.ClickException):
    """A table or its data that cannot be rendered; the message is one line."""


def load(name: str, folder: Path = DATA) -> dict:
    path = folder / f"{name}.json"
    try:
        return json.loads(path.read_text())
    except OSError as e:
        raise TableError(f"table {name!r} has no data: {path}: {e.strerror}") from None
    except ValueError as e:
        raise TableError(f"{path}: not JSON: {e}") from None


def render(name: str, data: dict) -> str:
    """The body of table `name`: where it was measured, then the figures."""
    try:
        lines = [f"`{data['command']}` · {data['machine']} · {data['date']}", ""]
        if "output" in data:
            lines += [FENCE + "text", *data["output"], FENCE]
        else:
            columns, rows = data["columns"], data["rows"]
            lines += [_row(columns), _row(["---"] * len(columns))]
            for row in rows:
                if len(row) != len(columns):
                    raise TableError(f"table {name!r}: a row of {len(row)} cells under {len(columns)} columns: {row}")
                lines.append(_row(row))
    except KeyError as e:
        raise TableError(f"table {name!r}: its data lacks {e}") from None
    long = [line for line in lines if len(line) > MAX_LINE]
    if long:
        raise TableError(f"table {name!r}: a line of {len(long[0])} characters (at most {MAX_LINE}): {long[0][:80]}...")
    return "\n".join(lines) + "\n"


def _row(cells: list[str]) -> str:
    return "| " + " | ".join(str(c).replace("|", "\\|") for c in cells) + " |"


def refresh(page: str, folder: Path = DATA) -> tuple[str, list[str]]:
    """`page` with every table rendered from its data, and the names of those that changed."""
    changed: list[str] = []

    def table(m: re.Match[str]) -> str:
        body = render(m["name"], load(m["name"], folder))
        if body != m["body"]:
            changed.append(m["name"])
        return f"<!-- bench-table: {m['name']} -->\n{body}<!-- /bench-table -->"

    return BLOCK.sub(table, page), changed


def tables(page: str) -> list[str]:
    """The names of the page's tables, in order."""
    return [m["name"] for m in BLOCK.finditer(page)]


def machine() -> str:
    """This machine, as a table says where it was measured."""
    model = ""
    try:
        model = next((line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                      if line.startswith("model name")), "")
    except OSError:
        pass
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    return f"{os.cpu_count()}-core {platform.machine()}{f' ({model})' if model else ''}, load average {load}"


def record(name: str, command: list[str], folder: Path = DATA) -> dict:
    """Run `command` and write what it printed as the data of table `name`; its exit status must be 0."""
    where = machine()  # before the run: the load the benchmark met, not the one it made
    done = subprocess.run(command, stdout=subprocess.PIPE, text=True)
    if done.returncode != 0:
        raise TableError(f"{shlex.join(command)} exited with {done.returncode}: nothing recorded")
    data = {"command": shlex.join(command), "machine": where, "date": dt.date.today().isoformat(),
            "output": done.stdout.rstrip("\n").splitlines()}
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{name}.json").write_text(json.dumps(data, indent=1, ensure_ascii=False) + "\n")
    return data


@click.group(invoke_without_command=True, context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--check", is_flag=True, help="Write nothing; exit 1 if a table differs from its data.")
@click.pass_context
def main(ctx: click.Context, check: bool) -> None:
    """Render docs/BENCHMARKS.md's tables from docs/benchmarks/ (or check them)."""
    if ctx.invoked_subcommand is not None:
        return
    text, changed = refresh(PAGE.read_text())
    for name in changed:
        click.echo(f"docs/BENCHMARKS.md: table {name} {'differs from' if check else 'now'} its data")
    if check and changed:
        sys.exit(1)
    if changed:
        PAGE.write_text(text)


@main.command("record", context_settings={"ignore_unknown_options": True})
@click.argument("name")
@click.argument("command", nargs=-1, required=True, type=click.UNPROCESSED)
def record_command(name: str, command: tuple[str, ...]) -> None:
    """Run COMMAND and record what it printed as table NAME's data; then render the page."""
    record(name, list(command))
    page = PAGE.read_text()
    if name not in tables(page):
        click.echo(f"recorded docs/benchmarks/{name}.json; put <!-- bench-table: {name} --> and "
                   "<!-- /bench-table --> into docs/BENCHMARKS.md where it belongs")
        return
    PAGE.write_text(refresh(page)[0])
    click.echo(f"recorded docs/benchmarks/{name}.json and rendered it into docs/BENCHMARKS.md")


if __name__ == "__main__":
    main()
