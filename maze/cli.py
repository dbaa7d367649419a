"""`mazelog`: inspect, convert and replay micromouse wall logs (and, with `explore`, make them)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import click

from .compare import compare
from .direction import LETTER
from .errors import MazeError
from .explorer import STRATEGIES, explore as run_search
from .flash import log_sectors, log_writes, run_writes
from .mazefile import dump_maze, parse_maze
from .mazejson import maze_to_json
from .model import Maze, inner_wall_count
from .render import Overlay, save_png
from .restore import LoadedLog, load_log, restore, select
from .wallrecord import COORD_LIMIT, RECORD_BYTES, TEXT_HEADER, encode_log, parse_text_records

MAX_WARNINGS = 20
DEFAULT_SIZE = 32  # the seed's mouse keeps a 32x32 map even for smaller mazes

InFile = click.Path(exists=True, dir_okay=False, path_type=Path)
OutFile = click.Path(dir_okay=False, writable=True, path_type=Path)
size_option = click.option("--size", type=click.IntRange(1, COORD_LIMIT), default=DEFAULT_SIZE, show_default=True,
                           help="Side of the maze the log belongs to (a log does not record it).")
strict_option = click.option("--strict", is_flag=True,
                             help="Refuse a log with any anomaly instead of skipping the bad records.")


class MazeGroup(click.Group):
    """Turns MazeError from any command into click's one-line error and exit status 1."""

    def invoke(self, ctx: click.Context) -> object:
        try:
            return super().invoke(ctx)
        except MazeError as e:
            raise click.ClickException(str(e)) from None
        except BrokenPipeError:
            # the reader (say `head`) has gone; silence the flush at exit, as the Python docs advise
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            ctx.exit(1)
        except OSError as e:
            raise click.ClickException(f"{e.filename or 'output'}: {e.strerror}") from None


@click.group(cls=MazeGroup, context_settings={"help_option_names": ["-h", "--help"]})
def main() -> None:
    """Micromouse wall logs: 16-bit WallRecords appended during a search (see docs/MAZELOG.md)."""


def read_maze(path: Path) -> Maze:
    try:
        return parse_maze(path.read_text(encoding="utf-8"))
    except UnicodeDecodeError:
        raise MazeError(f"{path}: not a text maze file") from None
    except MazeError as e:
        raise MazeError(f"{path}: {e}") from None


def read_log(path: Path, size: int, strict: bool) -> LoadedLog:
    log = load_log(path.read_bytes(), size, strict)
    for a in log.anomalies[:MAX_WARNINGS]:
        click.echo(f"warning: {a} (skipped)", err=True)
    if len(log.anomalies) > MAX_WARNINGS:
        click.echo(f"warning: ... {len(log.anomalies) - MAX_WARNINGS} more anomalies", err=True)
    return log


def emit(text: str, out: Path | None) -> None:
    if out is None:
        click.echo(text, nl=False)
    else:
        out.write_text(text, encoding="utf-8")


def text_view(maze: Maze, view: int | None, footer: str) -> str:
    return dump_maze(maze, post="+", extent=view) + footer + "\n"


@main.command()
@click.argument("log", type=InFile)
@size_option
@click.option("--drop-last", type=click.IntRange(min=0), default=0, help="Undo the last N records (crash rollback).")
@click.option("--until", type=click.IntRange(min=0), default=None, help="Show the state after the first K records.")
@click.option("--format", "fmt", type=click.Choice(["text", "mazefile", "json", "png"]), default="text",
              show_default=True, help="text: '+' posts, dots for unknown walls; mazefile: the common format.")
@click.option("--out", type=OutFile, default=None, help="Write here instead of stdout (required for png).")
@click.option("--view", type=click.IntRange(min=1), default=None,
              help="text only: draw just the lower-left N x N cells.")
@strict_option
def replay(log: Path, size: int, drop_last: int, until: int | None, fmt: str, out: Path | None,
           view: int | None, strict: bool) -> None:
    """Restore the maze a wall log describes, starting from an all-unknown maze."""
    if view is not None and (fmt != "text" or view > size):
        raise click.UsageError("--view needs --format text and at most --size cells")
    if fmt == "png" and out is None:
        raise click.UsageError("--format png needs --out FILE")
    loaded = read_log(log, size, strict)
    records = select(loaded.records, until=until, drop_last=drop_last)
    maze, contradictions = restore(records, size)
    footer = (f"records applied: {len(records)} of {len(loaded.records)}; known inner walls: "
              f"{maze.known_inner()} of {inner_wall_count(size)}; contradictions: {contradictions}")
    if fmt == "png":
        save_png(maze, out, title=f"{log.name}: {footer}")
    elif fmt == "json":
        emit(maze_to_json(maze) + "\n", out)
    elif fmt == "mazefile":
        emit(dump_maze(maze), out)
    else:
        emit(text_view(maze, view, footer), out)


@main.command()
@click.argument("mazefile", type=InFile)
@click.option("--png", type=OutFile, default=None, help="Also draw the maze into this PNG file.")
def show(mazefile: Path, png: Path | None) -> None:
    """Print a maze file (checking it parses) with its size, start and goal."""
    maze = read_maze(mazefile)
    goals = " ".join(f"({x},{y})" for x, y in maze.goals)
    click.echo(text_view(maze, None, f"{maze.size}x{maze.size}, start {maze.start}, goal {goals}"), nl=False)
    if png is not None:
        save_png(maze, png, title=mazefile.name)


@main.command()
@click.argument("log", type=InFile)
@size_option
@strict_option
def info(log: Path, size: int, strict: bool) -> None:
    """Summarise a log: records, bytes, the walls it makes known, anomalies."""
    loaded = read_log(log, size, strict)
    maze, contradictions = restore(loaded.records, size)
    scan = loaded.scan
    limit = inner_wall_count(size)
    click.echo(f"bytes:             {scan.total_bytes} ({scan.used_bytes} before the terminator)")
    click.echo(f"records:           {len(loaded.records)} usable of {scan.used_bytes // RECORD_BYTES}"
               f" (a full {size}x{size} log needs at most {limit}, {limit * RECORD_BYTES} bytes)")
    click.echo(f"known inner walls: {maze.known_inner()} of {limit}")
    click.echo(f"contradictions:    {contradictions}")
    click.echo(f"anomalies:         {len(loaded.anomalies)}")


@main.command()
@click.argument("source", type=click.File("r", encoding="utf-8"))
@click.argument("log", type=OutFile)
def encode(source: click.utils.LazyFile, log: Path) -> None:
    """Turn text records `(x, y, dir, bool)` (dir ^ > v <, N E S W or 0 2 4 6) into a binary log. SOURCE may be -."""
    records = parse_text_records(source.read())
    log.write_bytes(encode_log(records))
    click.echo(f"{len(records)} records, {len(records) * RECORD_BYTES} bytes -> {log}", err=True)


@main.command()
@click.argument("log", type=InFile)
@strict_option
def decode(log: Path, strict: bool) -> None:
    """Print a binary log as the seed's `(x, y, dir, bool)` lines."""
    loaded = read_log(log, COORD_LIMIT, strict)
    click.echo(TEXT_HEADER)
    for rec in loaded.records:
        click.echo(rec.to_text())


@main.command()
@click.argument("mazefile", type=InFile)
@click.argument("log", type=InFile)
@strict_option
def diff(mazefile: Path, log: Path, strict: bool) -> None:
    """Compare what LOG restores with the true maze in MAZEFILE (inner walls only)."""
    truth = read_maze(mazefile)
    loaded = read_log(log, truth.size, strict)
    restored, _ = restore(loaded.records, truth.size)
    result = compare(truth, restored)
    click.echo(f"right:   {result.right}")
    click.echo(f"wrong:   {len(result.wrong)}")
    click.echo(f"unknown: {result.unknown}")
    for x, y, d in result.wrong:
        truth_word = "wall" if truth.is_wall(x, y, d) else "open"
        click.echo(f"  wrong: ({x}, {y}) {LETTER[d]} is {truth_word} in the maze")



def parse_cell(ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> tuple[tuple[int, int], ...]:
    cells = []
    for value in values:
        try:
            x, y = (int(v) for v in value.split(","))
        except ValueError:
            raise click.BadParameter(f"{value!r} is not x,y") from None
        cells.append((x, y))
    return tuple(cells)


@main.command()
@click.argument("mazefile", type=InFile)
@click.option("--strategy", type=click.Choice(list(STRATEGIES)), default="closing-stop", show_default=True,
              help="; ".join(f"{k}: {v}" for k, v in STRATEGIES.items()))
@click.option("--log", "log_path", type=OutFile, required=True, help="Where to write the wall log.")
@click.option("--goal", multiple=True, callback=parse_cell, metavar="X,Y",
              help="Goal cell (repeatable); default: the G cells of the file, else the central 2x2.")
@click.option("--png", type=OutFile, default=None, help="Draw the mouse's maze, path, visited cells, virtual walls.")
@click.option("--power-cut", type=click.IntRange(min=0), default=None, metavar="BYTE",
              help="Write the flash image as a power loss before log byte BYTE would leave it.")
def explore(mazefile: Path, strategy: str, log_path: Path, goal: tuple[tuple[int, int], ...], png: Path | None,
            power_cut: int | None) -> None:
    """Let a virtual mouse search MAZEFILE (Adachi method) and write the wall log it would keep."""
    truth = read_maze(mazefile)
    if goal:
        for x, y in goal:
            if not truth.inside(x, y):
                raise click.BadParameter(f"({x}, {y}) is outside the {truth.size}x{truth.size} maze", param_hint="--goal")
        truth.goals = goal
    result = run_search(truth, strategy)
    data = encode_log(result.records)
    if power_cut is not None:
        flash, _ = run_writes(log_writes(result), log_sectors(truth.size), power_cut)
        data = bytes(flash.data)
        click.echo(f"power cut before byte {power_cut}: {min(power_cut, len(result.records) * RECORD_BYTES) // RECORD_BYTES}"
                   f" records fully written, flash image {len(data)} bytes")
    log_path.write_bytes(data)
    verdict = "yes" if result.shortest else "NO"
    click.echo(f"strategy:      {strategy} ({STRATEGIES[strategy]})")
    click.echo(f"steps:         {result.steps}")
    click.echo(f"turns:         {result.turns}")
    click.echo(f"cells visited: {len(set(result.trace))} of {truth.size ** 2}")
    click.echo(f"wall log:      {len(result.records)} records, {len(result.records) * RECORD_BYTES} bytes -> {log_path}")
    click.echo(f"virtual walls: {len(result.virtual)}")
    click.echo(f"shortest path: found {result.found_length}, true {result.true_length}: {verdict}")
    if png is not None:
        overlay = Overlay(path=result.found_path, visited=set(result.trace), virtual=result.virtual)
        save_png(result.maze, png, title=f"{mazefile.name} {strategy}: {result.steps} steps", overlay=overlay)
