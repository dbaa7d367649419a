"""The compiled fastest-path kernel (maze/fastpath/kernel.c, its graph built in C: maze/fastpath/native.py) against
the numpy and scipy path it replaces: the same routes to the bit, query after query on one graph (so that the bound,
the limits and the edges priced from the last query's walls all come into play); and how it is built: cached, and
the scipy path, said once, where no compiler works; and which commands import numpy or scipy."""

import subprocess
import sys
from unittest import mock

import pytest
from hypothesis import given, settings

from maze.fastpath import Graph, MoveGraph, Route, compiled, move_graph
from maze.fastpath.native import NativeGraph
from maze.files.builtin import builtin_names, builtin_path
from maze.files.mazefile import parse_maze
from maze.model import Maze
from maze.search.explorer import explore
from maze.search.stepmap import optimistic, pessimistic
from maze.timing.mouseparams import load_mouse
from tests.maze.test_maze_fastpath import maze_series

pytestmark = pytest.mark.skipif(compiled.kernel() is None, reason="no C compiler to build the kernel")


def routes(graph: Graph, mazes: list[Maze]) -> list[Route | None]:
    return [graph.fastest(blocked, maze.start, maze.goals) for maze in mazes
            for blocked in (optimistic(maze), pessimistic(maze))]


def same_routes(mazes: list[Maze], diagonal: bool) -> None:
    """The kernel's routes (its graph, its searches and its decoding) and the numpy and scipy path's, query after
    query."""
    size, mouse = mazes[0].size, load_mouse(None, mazes[0].size)
    native = NativeGraph(compiled.kernel(), size, diagonal, mouse)
    assert routes(native, mazes) == routes(MoveGraph(size, diagonal, mouse), mazes)


def test_queries_search_with_the_kernel():
    move_graph.cache_clear()
    assert isinstance(move_graph(4, True, load_mouse(None, 4)), NativeGraph)


@settings(max_examples=60, deadline=None)
@given(maze_series())
def test_kernel_routes_equal_scipy_routes_on_random_mazes(series):
    same_routes(series, diagonal=True)
    same_routes(series, diagonal=False)


@pytest.mark.slow
@pytest.mark.parametrize("name", builtin_names())
def test_kernel_routes_equal_scipy_routes_on_builtin_mazes(name):
    """The true maze, all unknown, and the walls a time-objective search found, one query after another."""
    truth = parse_maze(builtin_path(name).read_text())
    found = explore(truth, "stop", "time", True, load_mouse(None, truth.size)).maze
    same_routes([Maze.unknown(truth.size, truth.goals), found, truth], diagonal=True)


def fallback_notes(cc: str, tmp_path, monkeypatch, capsys) -> list[str]:
    """What stderr says over two workspaces asked for with compiler `cc` (both must be the scipy path's)."""
    monkeypatch.setenv("CC", cc)
    monkeypatch.setenv("PATH", str(tmp_path))  # no cc or gcc
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    compiled.kernel.cache_clear()
    try:
        assert compiled.kernel() is None
        assert move_graph.__wrapped__(4, True, load_mouse(None, 4)).fastest(bytes(40), (0, 0), ((1, 1),))
    finally:
        compiled.kernel.cache_clear()
    return capsys.readouterr().err.splitlines()


def test_no_compiler_takes_the_scipy_path_and_says_so_once(tmp_path, monkeypatch, capsys):
    assert fallback_notes("/nonexistent", tmp_path, monkeypatch, capsys) == [compiled.NO_COMPILER]
    assert not (tmp_path / "cache").exists()


def test_a_compiler_that_fails_is_named_once_and_the_scipy_path_taken(tmp_path, monkeypatch, capsys):
    failing = tmp_path / "failing-cc"
    failing.write_text("#!/bin/sh\necho 'kernel.c:1: error: this compiler is broken' >&2\nexit 1\n")
    failing.chmod(0o755)
    err = fallback_notes(str(failing), tmp_path, monkeypatch, capsys)
    assert len(err) == 1 and "kernel.c:1: error: this compiler is broken" in err[0]
    assert err[0].endswith(compiled.FALLBACK)


def test_the_built_kernel_is_cached_and_reused(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    compiled.kernel.cache_clear()
    try:
        assert compiled.kernel() is not None
        built = list((tmp_path / "mazelog").iterdir())
        assert len(built) == 1 and built[0].suffix == ".so"
        compiled.kernel.cache_clear()
        with mock.patch.object(compiled, "_build", side_effect=AssertionError("built again")):
            assert compiled.kernel() is not None
        assert list((tmp_path / "mazelog").iterdir()) == built
    finally:
        compiled.kernel.cache_clear()


PROBE = ("import sys; from maze.cli import main\n"
         "try:\n    main(sys.argv[1:])\nexcept SystemExit:\n    pass\n"
         "print(sorted(m for m in ('numpy', 'scipy') if m in sys.modules), file=sys.stderr)")


def heavy_modules(*args: str, cwd) -> str:
    run = subprocess.run([sys.executable, "-c", PROBE, *args], capture_output=True, text=True, cwd=cwd, check=True)
    return run.stderr.strip().splitlines()[-1]


def test_with_the_kernel_no_command_loads_numpy_or_scipy(tmp_path):
    """numpy and scipy took 0.4-0.5 s of CPU to import, and the move graph 0.05 s more to build in numpy; with the
    kernel the graph is built in C, and no command needs either."""
    heavy_modules("explore", "japan2019hef", "--log", "run.log", cwd=tmp_path)
    assert heavy_modules("--help", cwd=tmp_path) == "[]"
    assert heavy_modules("replay", "run.log", cwd=tmp_path) == "[]"
    assert heavy_modules("explore", "japan2019hef", "--log", "again.log", cwd=tmp_path) == "[]"
    assert heavy_modules("path", "run.log", cwd=tmp_path) == "[]"
    assert heavy_modules("path", "japan2019hef", "--objective", "time", "--diagonal", cwd=tmp_path) == "[]"
    assert heavy_modules("explore", "japan2019hef", "--log", "t.log", "--objective", "time", "--diagonal",
                         cwd=tmp_path) == "[]"
