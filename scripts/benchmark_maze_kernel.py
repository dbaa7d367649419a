"""Issues 40's and 49's figures in one run: mazelog's fastest-path queries and whole processes, this checkout against an
older copy of the maze package (--before) and against kerikun11/micromouse-maze-library (--kerikun, the
maze_timing driver scripts/build_maze_library.sh builds), on the same 32x32 mazes, run by run so that all three
meet the same machine load.

Usage: git worktree add --detach /tmp/before main            # the version to compare with
       scripts/build_maze_library.sh SOURCE build/kerikun     # the compared library, from source
       python scripts/benchmark_maze_kernel.py --before /tmp/before --kerikun build/kerikun/maze_timing \\
           --held-out ../shared/mazes/halfsize

Per maze: (a) a fastest-path query, diagonal, every wall known: the median of --repeat, in process (kerikun:
Agent::calcShortestDirections(true), the same); (b) the mean CPU of the queries `explore --objective time
--diagonal` makes, replayed in order on a fresh graph (its first query, which builds the graph, untimed);
(c) that whole process, wall (CPU), median of --runs, and kerikun's whole search as a process (its search run
and four shortest paths). With --rounds N, (a) and (b) are each version's lowest over N runs, the versions
taking turns: on a machine shared with others' work the lowest is the run least disturbed. Then (d)
whole-process `mazelog --help` and `mazelog replay`. Each maze's row ends with the load average when it began
(the machine is shared: compare CPU times, and the columns of one row). The targets (issue 49): (a) at most
1.0x kerikun's, (b) at most 0.5 ms, (c) no more CPU than kerikun's whole search, (d) at most 0.15 s.
"""

from __future__ import annotations

import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import click
from benchmark_maze_explore import ENTRY

DEV = ["japan2009hef", "japan2019hef"]
HELD_OUT = ["japan2008hef", "japan2011hef", "japan2014hef", "japan2017hef"]  # measured, never tuned on
# Every other maze of the --held-out folder is "fresh": measured for the first time once issue 49's changes were done.
ROOT = Path(__file__).resolve().parents[1]


def worker(maze_path: Path, repeat: int) -> dict[str, float]:
    """(a) and (b) with the maze package first on sys.path (PYTHONPATH), as JSON."""
    from benchmark_maze_speed import search_query_ms

    import maze
    from maze.fastpath import fastest_route
    from maze.files.mazefile import parse_maze
    from maze.search.stepmap import pessimistic
    from maze.timing.mouseparams import load_mouse

    truth = parse_maze(maze_path.read_text())
    mouse = load_mouse(None, truth.size)
    known = pessimistic(truth)
    fastest_route(truth, known, True, mouse)  # builds the graph: not timed
    query = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fastest_route(truth, known, True, mouse)
        query.append((time.perf_counter() - t0) * 1000)
    cpu = search_query_ms(truth, mouse, time.process_time)
    return {"query_ms": statistics.median(query), "search_mean_ms": statistics.mean(cpu), "queries": len(cpu),
            "package": str(Path(maze.__file__).parent)}


def in_process(root: Path, maze_path: Path, repeat: int) -> dict[str, float]:
    env = dict(os.environ, PYTHONPATH=str(root))
    out = subprocess.run([sys.executable, __file__, "--worker", str(maze_path), "--repeat", str(repeat)],
                         check=True, capture_output=True, text=True, env=env, cwd=tempfile.gettempdir()).stdout
    found = json.loads(out)
    if Path(found["package"]).resolve() != (root / "maze").resolve():
        raise click.ClickException(f"the worker for {root} imported {found['package']}")
    return found


def lowest(rounds: list[dict[str, dict[str, float]]]) -> dict[str, dict[str, float]]:
    """Per version, its lowest (a) and (b) over the rounds."""
    return {v: dict(found, **{k: min(r[v][k] for r in rounds) for k in ("query_ms", "search_mean_ms")})
            for v, found in rounds[0].items()}


def whole(argv: list[str], env: dict[str, str] | None = None, cwd: Path | None = None) -> tuple[float, float]:
    """Wall and CPU seconds of one process (its children's CPU included)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(argv, check=True, capture_output=True, env=env, cwd=cwd)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime


def mazelog(args: list[str]) -> list[str]:
    """A whole-process mazelog, with the maze package PYTHONPATH names (run from an empty folder, as
    scripts/benchmark_maze_explore.py runs it, so that no checkout shadows it)."""
    return [sys.executable, "-c", ENTRY, *args]


def median_of(runs: int, argv: list[str], env: dict[str, str] | None, cwd: Path) -> tuple[float, float]:
    whole(argv, env, cwd)  # the first run builds and caches the kernel, warms the disk cache: not timed
    times = [whole(argv, env, cwd) for _ in range(runs)]
    return statistics.median(t[0] for t in times), statistics.median(t[1] for t in times)


def kerikun_query(exe: Path, maze_path: Path, repeat: int) -> float:
    out = subprocess.run([str(exe), "query", str(maze_path), str(repeat)], check=True, capture_output=True,
                         text=True).stdout.split()
    return float(out[out.index("query_ms") + 1])


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--worker", "worker_maze", type=click.Path(exists=True, dir_okay=False, path_type=Path), hidden=True)
@click.option("--before", type=click.Path(exists=True, file_okay=False, path_type=Path), default=None,
              help="A folder holding an older maze/ package to compare with.")
@click.option("--kerikun", type=click.Path(exists=True, dir_okay=False, path_type=Path), default=None,
              help="The maze_timing driver scripts/build_maze_library.sh built.")
@click.option("--held-out", "held_out", type=click.Path(exists=True, file_okay=False, path_type=Path), default=None,
              help="A folder with the held-out mazes (../shared/mazes/halfsize); its others are measured too.")
@click.option("--repeat", type=click.IntRange(min=1), default=21, show_default=True, help="Queries per median.")
@click.option("--runs", type=click.IntRange(min=1), default=3, show_default=True, help="Processes per median.")
@click.option("--rounds", type=click.IntRange(min=1), default=1, show_default=True,
              help="In-process runs per version, taking turns; (a) and (b) are the lowest.")
def main(worker_maze: Path | None, before: Path | None, kerikun: Path | None, held_out: Path | None, repeat: int,
         runs: int, rounds: int) -> None:
    """Print the figures; no pass/fail."""
    if worker_maze is not None:
        print(json.dumps(worker(worker_maze, repeat)))
        return
    from maze.files.builtin import builtin_path

    kerikun, held_out = (p.resolve() if p else None for p in (kerikun, held_out))  # the runs are from a temp folder
    mazes = [(builtin_path(n), "dev") for n in DEV]
    mazes += [(held_out / f"{n}.txt", "held out") for n in HELD_OUT if held_out and (held_out / f"{n}.txt").is_file()]
    if held_out:
        mazes += [(p, "fresh") for p in sorted(held_out.glob("*.txt")) if p.stem not in {*DEV, *HELD_OUT}]
    versions = {"before": before.resolve()} if before else {}
    versions["after"] = ROOT
    envs = {v: dict(os.environ, PYTHONPATH=str(root)) for v, root in versions.items()}
    names = " / ".join(versions) + (" / kerikun" if kerikun else "")
    with open("/proc/loadavg") as fp:
        print(f"load average at start: {fp.read().split()[0]}; columns: {names}")
    print(f"{'32x32 maze':22} | (a) query, diagonal, known walls, ms | (b) a search's queries, mean CPU ms"
          f" | (c) explore --objective time --diagonal, s wall (CPU) | load")
    with tempfile.TemporaryDirectory() as tmp:
        cwd = Path(tmp)
        for path, kind in mazes:
            load = os.getloadavg()[0]
            found = lowest([{v: in_process(root, path, repeat) for v, root in versions.items()}
                            for _ in range(rounds)])
            query = [f"{found[v]['query_ms']:.3f}" for v in versions]
            search = [f"{found[v]['search_mean_ms']:.3f}" for v in versions]
            process = [median_of(runs, mazelog(["explore", str(path), "--log", "x.bin", "--objective", "time",
                                                "--diagonal"]), envs[v], cwd)
                       for v, root in versions.items()]
            shown = [f"{w:.2f} ({c:.2f})" for w, c in process]
            if kerikun:
                theirs = kerikun_query(kerikun, path, repeat)
                query.append(f"{theirs:.3f} (after {found['after']['query_ms'] / theirs:.1f}x)")
                w, c = median_of(runs, [str(kerikun), "search", str(path)], None, cwd)
                shown.append(f"{w:.2f} ({c:.2f})")
            print(f"{path.stem + ' (' + kind + ')':22} | {' / '.join(query)} | {' / '.join(search)} "
                  f"({found['after']['queries']} queries) | {' / '.join(shown)} | load {load:.1f}")
        log = cwd / "run.bin"
        subprocess.run(mazelog(["explore", "japan2019hef", "--log", str(log)]), check=True,
                       capture_output=True, env=envs["after"], cwd=cwd)
        for label, args in (("mazelog --help", ["--help"]), ("mazelog replay LOG (japan2019hef's search)",
                                                             ["replay", str(log)])):
            shown = [f"{w:.3f} ({c:.3f})" for w, c in (median_of(runs * 3, mazelog(args), envs[v], cwd)
                                                       for v in versions)]
            print(f"(d) {label}, s wall (CPU): {' / '.join(shown)}")


if __name__ == "__main__":
    main()
