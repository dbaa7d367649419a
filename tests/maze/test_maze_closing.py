from maze.files.mazefile import parse_maze
from maze.search.closing import close_dead_ends, nearest_branch

# (1,1)-(2,1) is a pocket whose only way in is the open east side of (0,1); the wall between them is unknown
POCKET = """\
o---o---o---o
| G         |
o   o---o---o
|       .   |
o   o---o---o
| S |       |
o---o---o---o
"""


def run(text: str, here: tuple[int, int]):
    maze = parse_maze(text)
    virtual = bytearray(maze.topo.wall_count)
    h = maze.cell_index(here)
    branch = nearest_branch(maze, virtual, h)
    return maze, virtual, branch, close_dead_ends(maze, virtual, h, branch)


def test_pocket_behind_the_nearest_branch_is_closed():
    maze, virtual, branch, closed = run(POCKET, (0, 0))
    assert branch[0] == maze.cell_index((0, 1))
    assert closed == [maze.wid(0, 1, 0)] and virtual[closed[0]] == 1


def test_area_with_a_second_way_in_stays_open():
    second_door = POCKET.replace("o   o---o---o\n|       .", "o   o . o---o\n|       .", 1)
    maze, virtual, _, closed = run(second_door, (0, 0))
    assert closed == [] and not any(virtual)


def test_mouse_inside_the_pocket_is_not_sealed_in():
    maze, virtual, branch, closed = run(POCKET, (1, 1))
    assert branch is not None and closed == [] and not any(virtual)


def test_no_branch_when_everything_is_known():
    known = parse_maze(POCKET.replace("|       .   |", "|           |"))
    assert nearest_branch(known, bytearray(known.topo.wall_count), 0) is None
