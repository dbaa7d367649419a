"""How fast mazelog is where issue 17 asks: a whole-process `mazelog explore` of a 32x32 maze with a built-in
strategy, one fastest-path query (on the whole maze known, on it all unknown, and the queries a search with the
time objective makes as it finds the walls), and the mms protocol's cost per command; printed for the built-in
mazes (development) and for held-out mazes (../shared/mazes/halfsize, or --held-out DIR) apart.

Usage: python scripts/benchmark_maze_speed.py [--repeat N] [--held-out DIR] [--held-out-count N] [--section S]...

The query section runs on an older maze package too, for a before/after table under similar load:
    git archive main maze | tar -x -C /tmp/before
    cd /tmp && PYTHONPATH=/tmp/before python /path/to/scripts/benchmark_maze_speed.py --section query
"""

from __future__ import annotations

import shutil
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import click

import maze
import maze.fastpath
from maze.fastpath import fastest_route, move_graph
from maze.files.builtin import builtin_path
from maze.files.mazefile import parse_maze
from maze.model import Maze
from maze.search.explorer import explore
from maze.search.stepmap import optimistic, pessimistic
from maze.timing.mouseparams import MouseParams, load_mouse

ROOT = Path(__file__).resolve().parents[1]
HELD_OUT = ROOT.parent / "shared" / "mazes" / "halfsize"
DEV_32 = ["japan2009hef", "japan2019hef"]
DEV_16 = ["alljapan-010-1989-fin", "alljapan-017-1996-exp-fin"]
MICE = ROOT / "tests" / "mice"


def median_ms(f, repeat: int) -> tuple[float, float]:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        times.append((time.perf_counter() - t0) * 1000)
    return statistics.median(times), min(times)


def whole_process(maze: Path, repeat: int, *extra: str) -> tuple[float, float]:
    exe = shutil.which("mazelog") or "mazelog"
    cmd = [exe, "explore", str(maze), "--log", "/dev/null", *extra]
    return median_ms(lambda: subprocess.run(cmd, check=True, capture_output=True), repeat)


def queries(maze_path: Path, repeat: int) -> dict[str, tuple[float, float]]:
    truth = parse_maze(maze_path.read_text())
    mouse = load_mouse(None, truth.size)
    out = {}
    for diagonal in (False, True):
        for label, blocked in (("known walls", pessimistic(truth)),
                               ("unknown open", optimistic(Maze.unknown(truth.size, truth.goals)))):
            fastest_route(truth, blocked, diagonal, mouse)  # the graph of this size is built once, not timed
            out[f"{'diagonal' if diagonal else 'straight'}, {label}"] = median_ms(
                lambda: fastest_route(truth, blocked, diagonal, mouse), repeat)  # noqa: B023 (timed in this turn)
    return out


def search_walls(truth: Maze, mouse: MouseParams) -> list[bytes]:
    """The walls of each query `mazelog explore MAZE --objective time --diagonal` makes, in its order."""
    seen: list[bytes] = []

    def recording(maze_: Maze, blocked: bytes, diagonal: bool, params) -> object:
        seen.append(bytes(blocked))
        return fastest_route(maze_, blocked, diagonal, params)

    maze.fastpath.fastest_route = recording  # explore imports it when it plans
    try:
        explore(truth, "stop", "time", True, mouse)
    finally:
        maze.fastpath.fastest_route = fastest_route
    return seen


def search_query_ms(truth: Maze, mouse: MouseParams, clock: Callable[[], float] = time.perf_counter) -> list[float]:
    """The queries `mazelog explore MAZE --objective time --diagonal` makes, in its order, timed one by one by
    `clock` in ms on a fresh graph (built by an untimed first query, as the search's own first query builds it)."""
    seen = search_walls(truth, mouse)
    move_graph.cache_clear()
    fastest_route(truth, seen[0], True, mouse)
    times = []
    for blocked in seen[1:]:
        t0 = clock()
        fastest_route(truth, blocked, True, mouse)
        times.append((clock() - t0) * 1000)
    return times


def search_queries(maze_path: Path) -> dict[str, tuple[float, float]]:
    """A search's queries (`search_query_ms`): median and 90th percentile, not min."""
    truth = parse_maze(maze_path.read_text())
    times = search_query_ms(truth, load_mouse(None, truth.size))
    return {f"diagonal, the {len(times)} queries of a search": (statistics.median(times),
                                                                statistics.quantiles(times, n=10)[-1])}


def protocol_in_process(repeat: int) -> float:
    """Parsing and answering, per command, on the mms-python template's command stream."""
    from maze.mouse.mms import parse_command
    from maze.mouse.mmsworld import MmsWorld

    truth = parse_maze(builtin_path("japan2019hef").read_text())
    lines = ["wallLeft", "turnLeft", "wallFront", "turnRight", "wallFront", "moveForward", "setColor 1 1 r",
             "getStat score", "wallRight 3"] * 1000
    best = float("inf")
    for _ in range(repeat):
        world = MmsWorld(truth, load_mouse(None, truth.size))
        t0 = time.perf_counter()
        for line in lines:
            world.handle(parse_command(line))
        best = min(best, (time.perf_counter() - t0) / len(lines) * 1e6)
    return best


def print_rows(title: str | None, rows: dict[str, tuple[float, float]], second: str = "min") -> None:
    if title is not None:
        print(title)
    for name, (med, other) in rows.items():
        print(f"  {name:55} median {med:8.2f} ms   {second} {other:8.2f} ms")


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--repeat", type=click.IntRange(min=1), default=5, show_default=True)
@click.option("--held-out", "held_out", type=click.Path(file_okay=False, path_type=Path), default=HELD_OUT,
              show_default="../shared/mazes/halfsize")
@click.option("--held-out-count", type=click.IntRange(min=1), default=4, show_default=True,
              help="How many held-out mazes (every k-th of the folder, sorted).")
@click.option("--section", "sections", type=click.Choice(["explore", "query", "protocol"]), multiple=True,
              help="Only these parts (repeatable) [all].")
def main(repeat: int, held_out: Path, held_out_count: int, sections: tuple[str, ...]) -> None:
    """Print the figures; no pass/fail (the issue's targets: 0.5 s, 2 ms, 20 us)."""
    sections = sections or ("explore", "query", "protocol")
    with open("/proc/loadavg") as fp:
        print(f"maze package {Path(maze.__file__).parent}; load average at start: {fp.read().split()[0]}")
    held = sorted(held_out.glob("*.txt")) if held_out.is_dir() else []
    held = held[:: max(1, len(held) // held_out_count)][:held_out_count]
    sets = {"development (built-in)": [builtin_path(n) for n in DEV_32], "held out": held}
    for name, mazes in sets.items():
        if not mazes:
            print(f"{name}: no mazes (give --held-out DIR)")
            continue
        if "explore" in sections:
            print_rows(f"\nwhole-process `mazelog explore MAZE --log /dev/null`, {name}:",
                       {f"{m.stem} (stop, cells)": whole_process(m, repeat) for m in mazes})
            print_rows(f"\nwhole-process with --objective time --diagonal, {name}:",
                       {f"{m.stem}": whole_process(m, max(1, repeat // 2), "--objective", "time", "--diagonal")
                        for m in mazes})
        if "query" in sections:
            print(f"\nfastest-path query (in process), {name}:")
            for m in mazes:
                print_rows(f" {m.stem}", queries(m, repeat * 4))
                print_rows(None, search_queries(m), second="p90")
    if "query" in sections:
        print_rows("\nfastest-path query, 16x16 (development):", {
            f"{n}, {k}": v for n in DEV_16 for k, v in queries(builtin_path(n), repeat * 4).items()})
    if "protocol" not in sections:
        return
    print(f"\nmms protocol, parse + answer in process: {protocol_in_process(repeat):.2f} us per command")
    for label, mouse in (("mms-python template, 2000 steps", f"{sys.executable} {MICE / 'mms_python' / 'Main.py'}"),):
        exe = shutil.which("mazelog") or "mazelog"
        t0 = time.perf_counter()
        out = subprocess.run([exe, "explore", "japan2019hef", "--mouse", mouse, "--max-steps", "2000", "--log",
                              "/dev/null"], check=True, capture_output=True, text=True).stdout
        wall = time.perf_counter() - t0
        commands = next(line for line in out.splitlines() if line.startswith("commands:"))
        print(f"{label}: {commands.split(':', 1)[1].strip()} ({wall:.2f} s whole process)")
    ff = f"{sys.executable} {MICE / 'floodfill.py'}"
    print_rows("\nPython floodfill mouse, to the goal and back, whole process:", {
        n: median_ms(lambda n=n: subprocess.run([shutil.which("mazelog") or "mazelog", "explore", n, "--mouse", ff,
                                                 "--log", "/dev/null"], check=True, capture_output=True), repeat)
        for n in DEV_16})


if __name__ == "__main__":
    main()
