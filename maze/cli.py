"""`mazelog`: inspect, convert and replay micromouse wall logs (and, with `explore`, make them).

Start-up time matters (`mazelog --help`, a text `replay`: under 0.3 s), so this module imports only what the
text commands need; Pillow (pictures) and numpy/scipy (search, fast-run model, flash) are imported inside the
commands that use them.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click

from hakoniwa.wire.exits import EXIT_COMMAND_CAP, EXIT_INTERRUPTED

from .direction import LETTER
from .errors import MazeError, MazelogError
from .files.builtin import EXAMPLES, builtin_example, builtin_names, builtin_path
from .files.mazefile import dump_maze
from .files.mazeio import is_maze_file, read_maze, write_maze
from .files.mazejson import maze_to_json
from .log.restore import LoadedLog, load_log, restore, select
from .log.wallrecord import COORD_LIMIT, RECORD_BYTES, TEXT_HEADER, WallRecord, encode_log, parse_text_records
from .model import Cell, Maze, central_goals, goals_text, inner_wall_count
from .outputs import atomic_open, refuse_overwrite, write_bytes, write_text
from .scoring.compare import WallDiff, compare
from .search.strategies import OBJECTIVES, STRATEGIES
from .timing.mouseparams import MouseParams, load_mouse

if TYPE_CHECKING:
    from .fastpath import Route
    from .mouse.harness import MouseRun
    from .mouse.mmsworld import MmsWorld
    from .pictures.film import Replay
    from .search.explorer import SearchResult
    from .timing.motion import SearchRun

F = TypeVar("F", bound=Callable[..., Any])
MAX_WARNINGS = 20
DEFAULT_SIZE = 32  # the seed's mouse keeps a 32x32 map even for smaller mazes
DEFAULT_STRATEGY = "stop"  # closing-stop is step for step the same (measured), so closing is left to `closing`

InFile = click.Path(exists=True, dir_okay=False, path_type=Path)
OutFile = click.Path(dir_okay=False, writable=True, path_type=Path)


class ShippedSource(click.ParamType):
    """A file, or (when no such file exists) the name of one shipped in the package; `-` for stdin if allowed."""

    def __init__(self, name: str, what: str, lookup: Callable[[str], Path | None], names: Callable[[], list[str]],
                 stdin: bool = False) -> None:
        self.name, self.what, self.lookup, self.names, self.stdin = name, what, lookup, names, stdin

    def convert(self, value: object, param: click.Parameter | None, ctx: click.Context | None) -> Path | None:
        if self.stdin and value == "-":
            return None
        path = Path(str(value))
        if path.is_file():
            return path
        found = self.lookup(str(value))
        if found is None:
            self.fail(f"{value!r} is neither a file nor {self.what} ({', '.join(self.names())})", param, ctx)
        return found


def MazeSource() -> ShippedSource:
    """A maze file, or the name of a built-in maze (`mazelog mazes`)."""
    return ShippedSource("MAZE", "a built-in maze", builtin_path, builtin_names)


def TextSource() -> ShippedSource:
    """A text file, `-` for stdin, or a text example shipped in the package (`seed-log.txt`, the seed's log)."""
    return ShippedSource("TEXT", "a shipped example", builtin_example, lambda: list(EXAMPLES), stdin=True)


class PowerCutPoint(click.ParamType):
    """A log byte, or `reset`: where the first --reset-at happens."""

    name = "BYTE|reset"

    def convert(self, value: object, param: click.Parameter | None, ctx: click.Context | None) -> int | str:
        if value == "reset" or isinstance(value, int):
            return value
        try:
            byte = int(str(value))
        except ValueError:
            byte = -1
        if byte < 0:
            self.fail(f"{value!r} is neither a byte offset (0 or more) nor 'reset'", param, ctx)
        return byte


def size_option_for(with_maze: bool) -> Callable[[F], F]:
    return click.option("--size", type=click.IntRange(1, COORD_LIMIT), default=None,
                        help=f"Side of the maze the log belongs to (a log does not record it) "
                             f"[default: {DEFAULT_SIZE}{'; with --maze, its size' if with_maze else ''}].")


size_option = size_option_for(with_maze=True)
strict_option = click.option("--strict", is_flag=True,
                             help="Refuse a log with any anomaly instead of skipping the bad records, and a .num or "
                                  ".maz maze whose two cells beside a wall disagree about it instead of a warning.")
maze_strict_option = click.option("--strict", is_flag=True,
                                  help="Refuse a .num or .maz maze whose two cells beside a wall disagree about it "
                                       "(a warning without).")
timing_option = click.option("--timing", "timing_spec", default=None, metavar="NAME|FILE",
                             help="Time model of the mouse: built-in (classic, halfsize) or a TOML file "
                                  "[default: classic up to 16x16, halfsize above; see maze/data/mice.toml].")
objective_option = click.option("--objective", type=click.Choice(list(OBJECTIVES)), default="cells",
                                show_default=True, help="; ".join(f"{k}: {v}" for k, v in OBJECTIVES.items()))
diagonal_option = click.option("--diagonal", is_flag=True, help="Allow diagonal runs and 45/135/V90 turns.")


def timeout_option(whose: str) -> Callable[[F], F]:
    """`--timeout` of a mouse run, for `explore --mouse` and `bench`, whose help names the program as `whose`."""
    return click.option("--timeout", type=click.FloatRange(min=0, min_open=True), default=10.0, show_default=True,
                        metavar="SECONDS", help=f"{whose} next command (its first, at start-up, may take longer).")


def parse_cell(ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> tuple[Cell, ...]:
    cells = []
    for value in values:
        try:
            x, y = (int(v) for v in value.split(","))
        except ValueError:
            raise click.BadParameter(f"{value!r} is not x,y") from None
        cells.append((x, y))
    return tuple(cells)


goal_option = click.option("--goal", multiple=True, callback=parse_cell, metavar="X,Y",
                           help="Goal cell (repeatable); default: the G cells of the file, else the central 2x2.")


class MazeGroup(click.Group):
    """Turns MazelogError from any command into click's one-line error and exit status 1."""

    def invoke(self, ctx: click.Context) -> object:
        try:
            return super().invoke(ctx)
        except MazelogError as e:
            raise click.ClickException(str(e)) from None
        except BrokenPipeError:
            # the reader (say `head`) has gone; silence the flush at exit, as the Python docs advise
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            ctx.exit(1)
        except OSError as e:
            raise click.ClickException(f"{e.filename or 'output'}: {e.strerror}") from None


@click.group(cls=MazeGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="hakoniwa-py", prog_name="mazelog")
def main() -> None:
    """Micromouse wall logs: 16-bit WallRecords appended during a search (see docs/MAZELOG.md).

    A MAZE argument is a maze file or the name of a built-in maze (`mazelog mazes`)."""


def read_log(path: Path, size: int, strict: bool) -> LoadedLog:
    log = load_log(path.read_bytes(), size, strict)
    for a in log.anomalies[:MAX_WARNINGS]:
        click.echo(f"warning: {a} (skipped)", err=True)
    if len(log.anomalies) > MAX_WARNINGS:
        click.echo(f"warning: ... {len(log.anomalies) - MAX_WARNINGS} more anomalies", err=True)
    return log


def load_maze(path: Path, strict: bool = False) -> Maze:
    """A maze file as every command reads it: a wall its two cells disagree about is a warning on stderr."""
    return read_maze(path, strict, warn=lambda message: click.echo(f"warning: {message}", err=True))


def with_goals(maze: Maze, goals: tuple[Cell, ...]) -> Maze:
    for x, y in goals:
        if not maze.inside(x, y):
            raise click.BadParameter(f"({x}, {y}) is outside the {maze.size}x{maze.size} maze", param_hint="--goal")
    if goals:
        maze.goals = goals
    return maze


def emit(text: str, out: Path | None) -> None:
    if out is None:
        click.echo(text, nl=False)
    else:
        write_text(out, text)


def text_view(maze: Maze, view: int | None, footer: str) -> str:
    return dump_maze(maze, post="+", extent=view) + footer + "\n"


def replay_footer(applied: int, loaded: LoadedLog, drop_last: int, maze: Maze, contradictions: int) -> str:
    """Every record of the log accounted for: applied, skipped as anomalous, rolled back, or not (yet) applied."""
    in_log = loaded.in_log
    parts = [f"{n} {what}" for n, what in ((in_log - len(loaded.records), "skipped as anomalous"),
                                           (drop_last, "rolled back"),
                                           (len(loaded.records) - drop_last - applied, "later ones not applied"))
             if n]
    detail = f" ({', '.join(parts)})" if parts else ""
    return (f"records applied: {applied} of {in_log} in the log{detail}; known inner walls: "
            f"{maze.known_inner()} of {inner_wall_count(maze.size)}; contradictions: {contradictions}")


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
@click.option("--maze", "truth_path", type=MazeSource(), default=None,
              help="The true maze: png and --animate then mark the mouse's path and walls that contradict it.")
@click.option("--animate", type=OutFile, default=None, metavar="GIF",
              help="Also write a GIF of the known walls growing, one frame per --stride records.")
@click.option("--stride", type=click.IntRange(min=1), default=None,
              help="Records per frame of --animate [default: 1, or more so that the film has at most 400 frames].")
@strict_option
def replay(log: Path, size: int | None, drop_last: int, until: int | None, fmt: str, out: Path | None,
           view: int | None, truth_path: Path | None, animate: Path | None, stride: int | None,
           strict: bool) -> None:
    """Restore the maze a wall log describes, starting from an all-unknown maze."""
    refuse_overwrite({"LOG": log, "--maze": truth_path}, {"--out": out, "--animate": animate})
    truth = load_maze(truth_path, strict) if truth_path else None
    if truth is not None and size is not None and size != truth.size:
        raise click.UsageError(f"--size {size} but the maze is {truth.size}x{truth.size}")
    size = truth.size if truth is not None else size or DEFAULT_SIZE
    if view is not None and (fmt != "text" or view > size):
        raise click.UsageError("--view needs --format text and at most --size cells")
    if fmt == "png" and out is None:
        raise click.UsageError("--format png needs --out FILE")
    loaded = read_log(log, size, strict)
    if loaded.in_log == 0:
        click.echo(f"note: {log} holds no records: the maze shown is all unknown", err=True)
    records = select(loaded.records, until=until, drop_last=drop_last)
    if fmt == "png" or animate is not None:
        draw_replay(log, loaded, records, drop_last, truth_path if truth else None, truth, size,
                    out if fmt == "png" else None, animate, stride)
        if fmt == "png":
            return
    maze, contradictions = restore(records, size)
    footer = replay_footer(len(records), loaded, drop_last, maze, contradictions)
    if fmt == "json":
        emit(maze_to_json(maze) + "\n", out)
    elif fmt == "mazefile":
        emit(dump_maze(maze), out)
    else:
        emit(text_view(maze, view, footer), out)


def draw_replay(log: Path, loaded: LoadedLog, records: list[WallRecord], drop_last: int, truth_path: Path | None,
                truth: Maze | None, size: int, png: Path | None, gif: Path | None, stride: int | None) -> None:
    from .pictures.film import Replay, default_stride

    def title(replay: Replay) -> list[str]:
        footer = replay_footer(replay.applied, loaded, drop_last, replay.maze, replay.contradictions)
        return [log.name + (f" on the true maze {truth_path.name}" if truth_path else ""), *footer.split("; ", 1)]

    if gif is not None:
        step = stride or default_stride(len(records))
        written = write_film(gif, Replay.start(size, truth), records, step, title)
        click.echo(f"film: {written} frames, one per {step} record{'s' * (step > 1)} -> {gif} "
                   f"({gif.stat().st_size} bytes)", err=True)
    if png is not None:
        replay = Replay.start(size, truth)
        for rec in records:
            replay.apply(rec)
        with atomic_open(png) as fp:
            replay.picture(title(replay)).save(fp, format="PNG")


@main.command()
@click.argument("mazefile", metavar="MAZE", type=MazeSource())
@click.option("--png", type=OutFile, default=None, help="Also draw the maze into this PNG file.")
@click.option("--out", type=OutFile, default=None,
              help="Also write the maze in the format its suffix names: .num (mms), .maz (16x16 binary), else text.")
@maze_strict_option
def show(mazefile: Path, png: Path | None, out: Path | None, strict: bool) -> None:
    """Print a maze file (.txt, .num or .maz; checking it parses) with its size, start and goal."""
    refuse_overwrite({"MAZE": mazefile}, {"--png": png, "--out": out})
    maze = load_maze(mazefile, strict)
    if out is not None:
        write_maze(out, maze)
    click.echo(text_view(maze, None, f"{maze.size}x{maze.size}, start {maze.start}, goal {goals_text(maze.goals)}"),
               nl=False)
    if png is not None:
        from .pictures.render import save_png

        save_png(maze, png, title=[mazefile.name])


@main.command()
def mazes() -> None:
    """List the built-in mazes (real contest mazes shipped with the package; see maze/data/mazes/README.md)."""
    names = builtin_names()
    width = max(map(len, names))
    for name in names:
        path = builtin_path(name)
        assert path is not None  # a name builtin_names() gave
        maze = read_maze(path)
        click.echo(f"{name:{width}}  {maze.size}x{maze.size}  goal {goals_text(maze.goals)}")


@main.command()
@click.argument("log", type=InFile)
@size_option_for(with_maze=False)
@strict_option
def info(log: Path, size: int | None, strict: bool) -> None:
    """Summarise a log: records, bytes, the walls it makes known, anomalies."""
    size = size or DEFAULT_SIZE
    loaded = read_log(log, size, strict)
    maze, contradictions = restore(loaded.records, size)
    scan = loaded.scan
    limit = inner_wall_count(size)
    click.echo(f"bytes:             {scan.total_bytes} ({scan.used_bytes} before the terminator)")
    click.echo(f"records:           {len(loaded.records)} usable of {loaded.in_log}"
               f" (a full {size}x{size} log needs at most {limit}, {limit * RECORD_BYTES} bytes)")
    click.echo(f"known inner walls: {maze.known_inner()} of {limit}")
    click.echo(f"contradictions:    {contradictions}")
    click.echo(f"anomalies:         {len(loaded.anomalies)}")


@main.command()
@click.argument("source", type=TextSource())
@click.argument("log", type=OutFile)
def encode(source: Path | None, log: Path) -> None:
    """Turn text records `(x, y, dir, bool)` (dir ^ > v <, N E S W or 0 2 4 6) into a binary log.

    SOURCE may be - (stdin) or seed-log.txt, the seed's 30-record example shipped in the package."""
    refuse_overwrite({"SOURCE": source}, {"LOG": log})
    try:
        text = sys.stdin.read() if source is None else source.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise MazeError(f"{source}: not a text file") from None
    records = parse_text_records(text)
    write_bytes(log, encode_log(records))
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
@click.argument("mazefile", metavar="MAZE", type=MazeSource())
@click.argument("log", type=InFile)
@click.option("--belief", "belief_path", type=InFile, default=None,
              help="The mouse's own setWall/clearWall marks (LOG.belief.bin of explore --mouse): compared with "
                   "the true maze and with the walls LOG says it was told.")
@strict_option
def diff(mazefile: Path, log: Path, belief_path: Path | None, strict: bool) -> None:
    """Compare what LOG restores with the true maze in MAZE (inner walls only), and a mouse's belief with both."""
    truth = load_maze(mazefile, strict)
    loaded = read_log(log, truth.size, strict)
    restored, _ = restore(loaded.records, truth.size)
    echo_diff("", compare(truth, restored), truth)
    if belief_path is None:
        return
    belief = restore_belief(read_log(belief_path, truth.size, strict).records, truth.size)
    echo_diff("belief ", compare(truth, belief), truth)
    told = [(x, y, d) for x, y, d in truth.inner_walls() if restored.is_known(x, y, d)
            and belief.is_known(x, y, d) and restored.is_wall(x, y, d) != belief.is_wall(x, y, d)]
    unmarked = sum(1 for x, y, d in truth.inner_walls()
                   if restored.is_known(x, y, d) and restored.is_wall(x, y, d) and not belief.is_known(x, y, d))
    click.echo(f"belief against what it was told: {len(told)} marked otherwise, {unmarked} walls told but not marked")
    for x, y, d in told:
        click.echo(f"  told otherwise: ({x}, {y}) {LETTER[d]} is {'wall' if restored.is_wall(x, y, d) else 'open'}")


def echo_diff(prefix: str, result: WallDiff, truth: Maze) -> None:
    click.echo(f"{prefix}right:   {result.right}")
    click.echo(f"{prefix}wrong:   {len(result.wrong)}")
    click.echo(f"{prefix}unknown: {result.unknown}")
    for x, y, d in result.wrong:
        click.echo(f"  {prefix}wrong: ({x}, {y}) {LETTER[d]} is {'wall' if truth.is_wall(x, y, d) else 'open'} "
                   f"in the maze")


def restore_belief(records: list[WallRecord], size: int) -> Maze:
    """setWall / clearWall as the mouse meant them: the last mark of a wall wins (a log's contradiction rule is
    for misreads, not for a mouse changing its mind)."""
    maze = Maze.unknown(size)
    for r in records:
        if not (maze.is_outer(r.x, r.y, r.d) and not r.wall):
            maze.set(r.x, r.y, r.d, r.wall)
    return maze


def objective_words(objective: str, diagonal: bool, mouse: MouseParams) -> str:
    if objective == "cells":
        return "cells (fewest cells)"
    return f"time, {'with' if diagonal else 'without'} diagonals ({mouse.name} mouse)"


@main.command()
@click.argument("mazefile", metavar="MAZE", type=MazeSource())
@click.option("--mouse", "program", default=None, metavar="CMD",
              help="Run this mms-protocol program (e.g. \"python3 Main.py\") as the mouse, unchanged, instead of "
                   "a built-in strategy; its stderr goes to LOG's name with .stderr.txt.")
@click.option("--strategy", type=click.Choice(list(STRATEGIES)), default=None,
              help="Built-in strategy [default: stop]: "
                   + "; ".join(f"{k}: {v.description}" for k, v in STRATEGIES.items()))
@objective_option
@diagonal_option
@timing_option
@click.option("--log", "log_path", type=OutFile, required=True, help="Where to write the wall log.")
@goal_option
@click.option("--png", type=OutFile, default=None,
              help="Draw the mouse's maze, the best path found, visited cells and virtual walls, with a legend.")
@click.option("--power-cut", type=PowerCutPoint(), default=None,
              help="Write the flash image as a power loss before log byte BYTE would leave it (with --mouse, "
                   "'reset': at the first --reset-at).")
@click.option("--max-steps", type=click.IntRange(min=1), default=None, help="--mouse: end after this many cells.")
@click.option("--time-budget", type=click.FloatRange(min=0, min_open=True), default=None, metavar="SECONDS",
              help="--mouse: end when the modelled search time passes this (a contest's search minutes).")
@timeout_option("--mouse: longest wait for the program's")
@click.option("--reset-at", type=click.IntRange(min=1), multiple=True, metavar="STEP",
              help="--mouse: press mms's Reset button after this many cells (repeatable).")
@click.option("--animate", type=OutFile, default=None, metavar="GIF",
              help="--mouse: a film of the walls it sensed with its own setColor/setText marks.")
@maze_strict_option
def explore(mazefile: Path, program: str | None, strategy: str | None, objective: str, diagonal: bool,
            timing_spec: str | None, log_path: Path, goal: tuple[Cell, ...], png: Path | None,
            power_cut: int | str | None, max_steps: int | None, time_budget: float | None, timeout: float,
            reset_at: tuple[int, ...], animate: Path | None, strict: bool) -> None:
    """Search MAZE with a virtual mouse (a built-in strategy, or your own mms program with --mouse) and write
    the wall log it would keep: for --mouse, the walls the simulator told the program, in order."""
    mouse_only = {"--max-steps": max_steps, "--time-budget": time_budget, "--reset-at": reset_at or None,
                  "--animate": animate}
    if program is None:
        given = [k for k, v in mouse_only.items() if v is not None] + (["--power-cut reset"]
                                                                      if power_cut == "reset" else [])
        if given:
            raise click.UsageError(f"{given[0]} needs --mouse")
    elif strategy is not None:
        raise click.UsageError("--strategy and --mouse exclude each other")
    refuse_overwrite({"MAZE": mazefile}, {"--log": log_path, "--png": png, "--animate": animate,
                                          **(mouse_files(log_path) if program else {})})
    truth = with_goals(load_maze(mazefile, strict), goal)
    timing = load_mouse(timing_spec, truth.size)
    if program is not None:
        explore_mouse(program, truth, mazefile, objective, diagonal, timing, log_path, png, power_cut, max_steps,
                      time_budget, timeout, reset_at, animate)
        return
    from .search.explorer import explore as run_search

    strategy = strategy or DEFAULT_STRATEGY
    result = run_search(truth, strategy, objective, diagonal, timing)
    log_line = write_search_log(result, log_path, power_cut)
    click.echo(f"strategy:      {strategy} ({STRATEGIES[strategy].description})")
    click.echo(f"objective:     {objective_words(objective, diagonal, timing)}")
    echo_search(result.steps, result.turns, result.search, timing, len(set(result.trace)), truth.size)
    click.echo(f"wall log:      {log_line}")
    click.echo(f"virtual walls: {len(result.virtual)}")
    if objective == "time":
        echo_fastest(result.found_route, result.true_route)
    else:
        echo_shortest(result.found_length, result.true_length)
    if png is not None:
        draw_search(result, truth, mazefile, strategy, objective, png)


BELIEF, STDERR = "the belief log", "the program's stderr"  # the names refuse_overwrite gives these files


def mouse_files(log_path: Path) -> dict[str, Path]:
    """The files a --mouse run writes beside its log."""
    return {BELIEF: log_path.with_name(log_path.stem + ".belief" + log_path.suffix),
            STDERR: log_path.with_name(log_path.stem + ".stderr.txt")}


def echo_search(steps: int, turns: int, run: SearchRun, timing: MouseParams, visited: int, size: int) -> None:
    click.echo(f"steps:         {steps}")
    click.echo(f"turns:         {turns}")
    click.echo(f"search time:   {run.seconds:.1f} s under the model ({run.metres:.1f} m at "
               f"{timing.search.speed:g} m/s, {run.turns} turns, {run.stops} stops)")
    click.echo(f"cells visited: {visited} of {size ** 2}")


def echo_fastest(found: Route | None, true: Route | None) -> None:
    assert true is not None  # a true maze without a run to its goal fails here either way
    shown = f"{found.seconds:.3f} s" if found is not None else "none"
    ok = found is not None and true is not None and found.seconds <= true.seconds + 1e-9
    click.echo(f"fastest path:  found {shown}, true {true.seconds:.3f} s: {'yes' if ok else 'NO'}")


def echo_shortest(found: int, true: int) -> None:
    click.echo(f"shortest path: found {found if found >= 0 else 'none'}, true {true}: "
               f"{'yes' if found == true else 'NO'}")


def explore_mouse(program: str, truth: Maze, mazefile: Path, objective: str, diagonal: bool, timing: MouseParams,
                  log_path: Path, png: Path | None, power_cut: int | str | None, max_steps: int | None,
                  time_budget: float | None, timeout: float, reset_at: tuple[int, ...],
                  animate: Path | None) -> None:
    """The user's program as the mouse; whatever happens, the log of what it sensed so far is written."""
    from .mouse.harness import program_argv, run_mouse
    from .mouse.mmsworld import MmsWorld

    if power_cut == "reset" and not reset_at:
        raise click.UsageError("--power-cut reset needs --reset-at")
    argv = program_argv(program)
    files = mouse_files(log_path)
    world = MmsWorld(truth, timing, reset_at)
    run = run_mouse(argv, world, files[STDERR], max_steps, time_budget, timeout)
    log_line = write_mouse_logs(run, log_path, files[BELIEF], power_cut)
    for warning in world.warnings[:MAX_WARNINGS]:
        click.echo(f"warning: {warning}", err=True)
    status = f", status {run.status}" if run.ended == "the program exited" else ""
    click.echo(f"mouse:         {program} ({run.ended}{status})")
    click.echo(f"commands:      {run.commands} in {run.wall_s:.2f} s")
    echo_search(world.steps, world.turns, world.search(), timing, len(set(world.trace)), truth.size)
    click.echo(f"wall log:      {log_line}")
    click.echo(f"belief:        {len(world.belief)} setWall/clearWall marks -> {files[BELIEF]}")
    click.echo(f"resets:        {world.resets}")
    stats = world.stats
    click.echo("mms stats:     " + ", ".join(f"{name} {stats.value(name)}" for name in
                                             ("total-distance", "total-turns", "best-run-distance",
                                              "best-run-turns", "score")))
    echo_mouse_paths(world.sensed, truth, objective, diagonal, timing)
    click.echo(f"stderr:        {files[STDERR]}")
    if png is not None:
        from .pictures.render import Overlay, save_png

        overlay = Overlay(visited=set(world.trace), marks=final_marks(world))
        save_png(world.sensed, png, title=[f"{mazefile.name}: {program}", f"{world.steps} steps, "
                                           f"{len(world.records)} walls sensed"], overlay=overlay)
    if animate is not None:
        film_mouse(world, mazefile, program, animate)
    kept = f"the log of what it sensed so far is kept in {log_path}"
    if run.at_command_cap:
        click.echo(f"Error: --mouse: cut at {run.commands} commands, its search unfinished (give --max-steps or "
                   f"--time-budget to end it sooner); {kept}", err=True)
        raise click.exceptions.Exit(EXIT_COMMAND_CAP)
    if run.fault is not None:
        message = f"--mouse: {run.fault} ({kept})"
        if run.fault.startswith("interrupted"):
            click.echo(f"Error: {message}", err=True)
            raise click.exceptions.Exit(EXIT_INTERRUPTED)
        raise MazeError(message)


def final_marks(world: MmsWorld) -> dict[Cell, tuple[str, str]]:
    from .mouse.marks import marks_at

    return marks_at(world.marks, len(world.records))


def write_film(gif: Path, start: Replay, records: list[WallRecord], step: int,
               title: Callable[[Replay], list[str]]) -> int:
    """The GIF of `records` replayed from `start`, a frame per `step`, with a progress bar; frames written."""
    from .pictures.film import film, frame_count, write_gif

    with atomic_open(gif) as fp, click.progressbar(film(start, records, step, title),
                                                  length=frame_count(len(records), step), label="drawing frames",
                                                  file=sys.stderr) as frames:
        return write_gif(frames, fp)


def film_mouse(world: MmsWorld, mazefile: Path, program: str, gif: Path) -> None:
    from .pictures.film import Replay, default_stride

    records = world.records
    step = default_stride(len(records))

    def title(replay: Replay) -> list[str]:
        return [f"{mazefile.name}: {program}", f"{replay.applied} of {len(records)} walls sensed"]

    written = write_film(gif, Replay.start(world.truth.size, None, world.marks), records, step, title)
    click.echo(f"film:          {written} frames, one per {step} record{'s' * (step > 1)} -> {gif}")


def echo_mouse_paths(sensed: Maze, truth: Maze, objective: str, diagonal: bool, timing: MouseParams) -> None:
    """The best run the sensed walls prove, against the true maze's."""
    from .search.stepmap import pessimistic, shortest_path

    if objective == "time":
        from .fastpath import fastest_route

        echo_fastest(fastest_route(sensed, pessimistic(sensed), diagonal, timing),
                     fastest_route(truth, pessimistic(truth), diagonal, timing))
    else:
        echo_shortest(len(shortest_path(sensed, pessimistic(sensed))) - 1,
                      len(shortest_path(truth, pessimistic(truth))) - 1)


def write_mouse_logs(run: MouseRun, log_path: Path, belief_path: Path, power_cut: int | str | None) -> str:
    """The belief log, and the wall log (or the flash image a power cut leaves, at a byte or at the first reset);
    what was written."""
    world = run.world
    write_bytes(belief_path, encode_log(world.belief))
    told = " (the walls the program was told)"
    if power_cut == "reset" and not world.resets:
        never = " (no reset happened, so no power cut)"
        return write_log(world.records, world.truth.size, log_path, None, told + never)
    cut = world.records_at_first_reset * RECORD_BYTES + 1 if power_cut == "reset" else power_cut
    assert not isinstance(cut, str)
    return write_log(world.records, world.truth.size, log_path, cut, told)


def write_search_log(result: SearchResult, log_path: Path, power_cut: int | str | None) -> str:
    assert not isinstance(power_cut, str)  # 'reset' is refused without --mouse
    return write_log(result.records, result.maze.size, log_path, power_cut)


def write_log(records: list[WallRecord], size: int, log_path: Path, cut: int | None, note: str = "") -> str:
    """Write the log, or the flash image a power cut before byte `cut` leaves, and say what was written (`note`
    after the size of a whole log)."""
    data = encode_log(records)
    if cut is None:
        write_bytes(log_path, data)
        return f"{len(records)} records, {len(data)} bytes{note} -> {log_path}"
    from .log.flash import cut_log

    image, written = cut_log(records, size, cut)
    write_bytes(log_path, image)
    torn = f" and {written % RECORD_BYTES} byte of the next" if written % RECORD_BYTES else ""
    return (f"{written // RECORD_BYTES} of {len(records)} records written before the power cut at byte {cut}{torn}; "
            f"flash image {len(image)} bytes -> {log_path}")


def draw_search(result: SearchResult, truth: Maze, mazefile: Path, strategy: str, objective: str,
                png: Path) -> None:
    from .pictures.render import Overlay, cell_centres, save_png

    if objective == "time":
        route = result.found_route
        assert route is not None
        path = [(x / 2, y / 2) for x, y in route.points]
        label = f"fastest run found ({route.seconds:.3f} s)"
    else:
        path, label = cell_centres(result.found_path), f"shortest path found ({result.found_length} cells)"
    overlay = Overlay(path=path, path_label=label, visited=set(result.trace), virtual=result.virtual)
    save_png(result.maze, png, title=[f"{mazefile.name}: {strategy}, objective {objective}",
                                      f"{result.steps} steps, search {result.search.seconds:.0f} s (model)"],
             overlay=overlay)


def read_maze_or_log(path: Path, size: int | None, truth: Maze | None, strict: bool) -> tuple[Maze, str, str]:
    """A maze file (text that starts with a post, or .num / .maz), else a binary wall log of --size (or of the
    --maze's size, whose start and goal it then takes: a log records neither). Returns the maze, what the file
    was, and what was assumed ("" when nothing was)."""
    data = path.read_bytes()
    if not data:
        raise MazeError(f"{path}: empty file (neither a maze file nor a wall log with any record)")
    if is_maze_file(path, data):
        if size is not None or truth is not None:
            raise click.UsageError("--size and --maze are for a wall log; a maze file has its own")
        return load_maze(path, strict), "maze file", ""
    if truth is not None and size is not None and size != truth.size:
        raise click.UsageError(f"--size {size} but the maze is {truth.size}x{truth.size}")
    assumed = ""
    if truth is None and size is None:
        size = DEFAULT_SIZE
        assumed = (f"assumed {size}x{size} with the central goal, as no --maze or --size was given "
                   f"(a log records neither)")
    size = truth.size if truth is not None else size
    assert size is not None
    if assumed:
        outside = next((a for a in load_log(data, size).anomalies if "outside the" in a.reason), None)
        if outside is not None:
            raise MazeError(f"{path}: {outside}: not a log of a {size}x{size} maze; give --maze or --size")
    loaded = read_log(path, size, strict)
    span = 1 + max((max(r.x, r.y) for r in loaded.records), default=0)
    if assumed and span < size:
        assumed += f"; its records span only {span}x{span} cells: is it a {span}x{span} maze? (--size {span})"
    maze, _ = restore(loaded.records, size, goals=truth.goals if truth is not None else central_goals(size))
    return maze, f"wall log, {len(loaded.records)} records", assumed


@main.command()
@click.argument("source", metavar="MAZE_OR_LOG", type=MazeSource())
@size_option
@objective_option
@diagonal_option
@timing_option
@goal_option
@click.option("--maze", "truth_path", type=MazeSource(), default=None,
              help="For a wall log: the maze it was made in, for its size and goal (not its walls).")
@click.option("--png", type=OutFile, default=None, help="Draw the maze's known walls and the path.")
@strict_option
def path(source: Path, size: int | None, objective: str, diagonal: bool, timing_spec: str | None,
         goal: tuple[Cell, ...], truth_path: Path | None, png: Path | None, strict: bool) -> None:
    """The best path among the known walls of a maze file or a wall log, its time and its moves.

    Moves: S<n> n cells along the walls, D<n> n diagonal steps (wall to wall, 0.71 cell each), R/L for right and
    left turns: 90s (inside a cell), 90, 180, 45, 135, V90 (slaloms)."""
    from .fastpath import fastest_route, run_of_cells
    from .search.stepmap import pessimistic, shortest_path

    refuse_overwrite({"MAZE_OR_LOG": source, "--maze": truth_path}, {"--png": png})
    maze, kind, assumed = read_maze_or_log(source, size, load_maze(truth_path, strict) if truth_path else None, strict)
    if assumed and goal:
        assumed = assumed.replace(" with the central goal", "")
    if assumed:
        click.echo(f"note: {assumed}", err=True)
    maze = with_goals(maze, goal)
    timing = load_mouse(timing_spec, maze.size)
    known = pessimistic(maze)
    if objective == "time":
        route = fastest_route(maze, known, diagonal, timing)
    else:
        cells = [(c % maze.size, c // maze.size) for c in shortest_path(maze, known)]
        route = run_of_cells(maze, cells, diagonal, timing) if cells else None
    if route is None:
        raise MazeError("no path from the start to the goal through walls known to be open")
    click.echo(f"maze:      {source.name} ({kind}), {maze.size}x{maze.size}, start {maze.start}, "
               f"goal {goals_text(maze.goals)}"
               + (" (assumed)" if assumed else ""))
    click.echo(f"objective: {objective_words(objective, diagonal, timing)}")
    click.echo(f"time:      {route.seconds:.3f} s (fast run under the model)")
    click.echo(f"length:    {len(route.cells) - 1} cells entered, {route.length * timing.cell:.2f} m run")
    click.echo(f"moves:     {route.sequence}")
    if png is not None:
        draw_path(maze, route, source, objective, png)


def wrap_title(text: str, size: int) -> list[str]:
    """Title lines that fit the picture's width, broken between moves."""
    from .pictures.render import text_width, title_width

    lines, line = [], ""
    for word in text.split():
        candidate = f"{line} {word}" if line else word
        if line and text_width(candidate) > title_width(size):
            lines.append(line)
            candidate = word
        line = candidate
    return lines + [line] if line else lines


def draw_path(maze: Maze, route: Route, source: Path, objective: str, png: Path) -> None:
    from .pictures.render import Overlay, save_png

    label = f"{'fastest run' if objective == 'time' else 'fewest cells'}: {route.seconds:.3f} s"
    overlay = Overlay(path=[(x / 2, y / 2) for x, y in route.points], path_label=label)
    save_png(maze, png, title=[f"{source.name}: best path by {objective}", *wrap_title(route.sequence, maze.size)],
             overlay=overlay)


@main.command()
@click.argument("mazes", nargs=-1, type=click.Path(exists=True, path_type=Path))
@click.option("--mouse", "programs", multiple=True, metavar="CMD",
              help="An mms-protocol program to run (repeatable).")
@click.option("--strategy", "strategies", multiple=True, type=click.Choice(list(STRATEGIES)),
              help="A built-in strategy to run through the same world (repeatable).")
@objective_option
@diagonal_option
@click.option("--max-steps", type=click.IntRange(min=1), default=None, help="End each mouse run after this many cells.")
@timeout_option("Longest wait for a mouse's")
@click.option("--jobs", type=click.IntRange(min=1), default=None, help="Parallel processes [default: half the cores].")
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path), required=True,
              help="Folder for results.csv, summary.txt and each run's wall log.")
def bench(mazes: tuple[Path, ...], programs: tuple[str, ...], strategies: tuple[str, ...], objective: str,
          diagonal: bool, max_steps: int | None, timeout: float, jobs: int | None, out_dir: Path) -> None:
    """Run mice and built-in strategies over MAZES (files or folders; none: the built-in set) and compare them:
    one CSV row per run, totals and who is best where."""
    from multiprocessing import Pool

    from .mouse.harness import program_argv
    from .scoring.benchmark import Entrant, Job, default_jobs, entrant_folder, maze_files, run_job, summary, write_csv

    if not programs and not strategies:
        raise click.UsageError("give at least one --mouse or --strategy")
    for program in programs:
        program_argv(program)  # a command naming no program is refused before anything runs
    entrants = [Entrant(p, program=p) for p in programs] + [Entrant(f"strategy {s}", strategy=s) for s in strategies]
    files = maze_files(mazes)
    for f in files:
        load_maze(f)  # every maze checked before a worker starts: one line for a bad one, a warning for a doubtful
    os.makedirs(out_dir, exist_ok=True)
    work = [Job(e, str(f), objective, diagonal, max_steps, timeout, str(entrant_folder(out_dir, e, i)))
            for i, e in enumerate(entrants) for f in files]
    rows = []
    with Pool(min(jobs or default_jobs(), len(work))) as pool, click.progressbar(
            pool.imap_unordered(run_job, work), length=len(work), label="runs", file=sys.stderr) as results:
        for row in results:
            rows.append(row)
    write_csv(rows, out_dir / "results.csv")
    text = summary(rows, [e.name for e in entrants], objective)
    write_text(out_dir / "summary.txt", text)
    click.echo(text, nl=False)
    click.echo(f"{len(rows)} runs -> {out_dir / 'results.csv'}, {out_dir / 'summary.txt'}", err=True)
