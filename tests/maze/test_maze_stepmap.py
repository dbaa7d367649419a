"""The bit-mask step maps the explorer walks on agree with the plain breadth-first ones, on any maze."""

from hypothesis import given, settings
from hypothesis import strategies as st

from maze.model import Maze
from maze.search.stepmap import (
    UNREACHED,
    bit,
    cells_of,
    known_cells,
    layers,
    mask_of,
    open_sides,
    optimistic,
    pessimistic,
    step_map,
)


@st.composite
def mazes(draw) -> Maze:
    size = draw(st.integers(1, 12))
    maze = Maze(size)
    for x, y, d in maze.inner_walls():
        state = draw(st.sampled_from([True, False, None]))
        if state is not None:
            maze.set(x, y, d, state)
    return maze


@settings(max_examples=80, deadline=None)
@given(mazes(), st.data())
def test_layers_are_the_step_map(maze: Maze, data) -> None:
    n2 = maze.size ** 2
    sources = data.draw(st.lists(st.integers(0, n2 - 1), min_size=1, max_size=3))
    for blocked in (optimistic(maze), pessimistic(maze)):
        dist = step_map(maze.topo, blocked, sources)
        got = layers(maze.topo, open_sides(maze.topo, blocked), mask_of(sources, maze.size))
        expected = [sorted(c for c in range(n2) if dist[c] == d) for d in range(len(got))]
        assert [cells_of(layer, maze.size) for layer in got] == expected
        assert max(d for d in dist if d < UNREACHED) == len(got) - 1
        until = data.draw(st.integers(0, n2 - 1))
        short = layers(maze.topo, open_sides(maze.topo, blocked), mask_of(sources, maze.size), until=until)
        assert short == got[:len(short)]
        if dist[until] < UNREACHED:
            assert len(short) == dist[until] + 1 and short[-1] >> bit(until, maze.size) & 1


@settings(max_examples=60, deadline=None)
@given(mazes())
def test_known_cells(maze: Maze) -> None:
    assert cells_of(known_cells(maze.topo, maze.known), maze.size) == [
        c for c in range(maze.size ** 2) if maze.cell_known(c)]
