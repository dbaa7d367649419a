"""The built-in mazes, and the maze sets other maze tests run on (imported from here).

Tests run on the mazes shipped in the package, so they pass on a fresh clone. The large set in ../shared/mazes
(beside the clone) is used for the large checks only; without it they skip, saying so.
"""


import pytest

from athrill_sim.programs.third_party import MAZES
from maze.files.builtin import builtin_dir, builtin_names, builtin_path
from maze.files.mazefile import parse_maze
from tests.helpers.commands import mazelog
from tests.helpers.paths import SHARED, needs_shared

SHARED_MAZES = SHARED / "mazes"
NO_SHARED = needs_shared("the large maze set", SHARED_MAZES, MAZES)
BUILTIN = sorted(builtin_dir().glob("*.txt"))


def large_maze_params() -> list:
    """Every maze of ../shared/mazes as a test parameter, or one parameter that skips with the reason."""
    files = sorted(SHARED_MAZES.rglob("*.txt"))
    return ([pytest.param(p, id=f"{p.parent.name}/{p.stem}") for p in files]
            or [pytest.param(None, id="shared-mazes", marks=pytest.mark.skip(reason=NO_SHARED))])


def builtin_maze_params() -> list:
    return [pytest.param(p, id=f"builtin/{p.stem}") for p in BUILTIN]


def test_the_package_ships_real_mazes_of_both_sizes_with_their_source():
    sizes = {parse_maze(p.read_text()).size for p in BUILTIN}
    assert sizes == {16, 32} and "japan2019hef" in builtin_names()
    readme = (builtin_dir() / "README.md").read_text()
    assert "a71f846897fdd2193e726a1276c6774c9ce9ac67" in readme and "Licence" in readme


def test_names_resolve_with_or_without_suffix_and_never_outside_the_folder():
    assert builtin_path("japan2019hef") == builtin_path("japan2019hef.txt") == builtin_dir() / "japan2019hef.txt"
    assert builtin_path("nosuch") is None and builtin_path("../data/mazes/japan2019hef") is None


def test_builtin_mazes_are_copies_of_the_shared_ones():
    if not SHARED_MAZES.is_dir():
        pytest.skip(NO_SHARED)
    for path in BUILTIN:
        (shared,) = SHARED_MAZES.rglob(path.name)
        assert path.read_bytes() == shared.read_bytes(), path.name


def test_commands_take_a_builtin_name(tmp_path):
    log = tmp_path / "run.bin"
    result = mazelog("explore", "alljapan-001-1980", "--log", str(log))
    assert result.exit_code == 0 and "shortest path: found" in result.output
    listing = mazelog("mazes")
    assert all(name in listing.output for name in builtin_names())


def test_an_unknown_maze_name_is_a_one_line_error():
    result = mazelog("show", "nosuchmaze")
    assert result.exit_code == 2 and "neither a file nor a built-in maze" in result.output
    assert "Traceback" not in result.output
