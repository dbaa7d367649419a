"""The package layout is a stack: each package of the bench may import itself and the packages below it, never
one above it, and two peers never import each other (the physics side and the robot programs share only the
wire). `maze` stands apart. The imports are read from the source (ast), including those inside functions, so a
lazy import cannot hide a cycle."""

from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

import pytest

from tests.helpers.paths import REPO

OURS = ("hakoniwa", "athrill_sim", "testctl", "maze")

# The packages of the bench, bottom to top, each with the packages below it that it may import. A module
# belongs to the longest of these names it starts with.
WIRE, CONVENTIONS, PHYSICS, OBJECTIVES, PICTURES, ATHRILL, CONTROLLER, CLI = (
    "hakoniwa.wire", "hakoniwa.conventions", "hakoniwa.physics", "hakoniwa.objectives", "hakoniwa.pictures",
    "athrill_sim", "testctl", "testctl.hako")
PACKAGES: dict[str, tuple[str, ...]] = {
    WIRE: (),  # the contract every process shares: stdlib only
    CONVENTIONS: (WIRE,),  # what every command line shares
    PHYSICS: (WIRE, CONVENTIONS),  # the "Unity" side: given the program's launch (`hakoniwa.wire.launch`)
    OBJECTIVES: (WIRE, CONVENTIONS, PHYSICS),  # what ends and scores a test: the physics' task and its judging
    PICTURES: (WIRE, CONVENTIONS, PHYSICS),  # what the physics looks like: drawn from it, never stepping it
    ATHRILL: (WIRE, CONVENTIONS),  # the robot programs, the physics' peer: resolving, building and running them
    # benches (where the peers meet), tests, campaigns
    CONTROLLER: (WIRE, CONVENTIONS, PHYSICS, OBJECTIVES, PICTURES, ATHRILL),
    CLI: (WIRE, CONVENTIONS, PHYSICS, OBJECTIVES, PICTURES, ATHRILL, CONTROLLER),  # the user's `hako`: imported by none
}
ROOTS = ("hakoniwa", "hakoniwa.physics")  # folders of the bench that are no package of their own
STANDALONE = ("maze",)  # imports nothing of the bench, and nothing of the bench imports it
# What maze may use of the bench, standard library only: the capped copy of a child's output, so that a
# user's mouse and a test's Athrill are logged by one piece of code, and the exit statuses.
SHARED_WITH_STANDALONE = ("hakoniwa.wire.output", "hakoniwa.wire.exits")


def modules() -> dict[str, Path]:
    found = {}
    for pkg in OURS:
        for path in (REPO / pkg).rglob("*.py"):
            parts = path.relative_to(REPO).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            found[name] = path
    return found


def imports(name: str, path: Path) -> list[tuple[int, str]]:
    tree = ast.parse(path.read_text(), str(path))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join([*base, node.module] if node.module else base)
            else:
                target = node.module or ""
            # `from pkg import mod` imports pkg.mod when that is a module of ours
            out += [(node.lineno, f"{target}.{alias.name}") for alias in node.names]
    return out


def package_of(module: str) -> str | None:
    found = [p for p in PACKAGES if module == p or module.startswith(p + ".")]
    return max(found, key=len) if found else None


def is_ours(module: str) -> bool:
    return module.split(".")[0] in OURS


def test_every_module_of_the_bench_has_a_package() -> None:
    homeless = [m for m in modules() if package_of(m) is None and m.split(".")[0] not in STANDALONE
                and m not in ROOTS]
    assert homeless == []


def test_each_package_may_import_only_packages_below_it() -> None:
    """The table itself is a stack: what a package may import, the packages it may import may not import back."""
    for package, below in PACKAGES.items():
        assert all(package not in PACKAGES[b] and list(PACKAGES).index(b) < list(PACKAGES).index(package)
                   for b in below), package


def violations() -> list[str]:
    found = modules()
    bad = []
    for name, path in found.items():
        mine = package_of(name)
        for line, target in imports(name, path):
            if not is_ours(target):
                continue
            where = f"{name}:{line} imports {target}"
            if name.split(".")[0] in STANDALONE or target.split(".")[0] in STANDALONE:
                shared = target in SHARED_WITH_STANDALONE or target.rpartition(".")[0] in SHARED_WITH_STANDALONE
                if name.split(".")[0] != target.split(".")[0] and not shared:
                    bad.append(f"{where}: maze stands apart from the bench")
                continue
            theirs = package_of(target)
            if theirs is None:  # a folder itself (`from hakoniwa.physics import robot` names the module)
                continue
            if mine is not None and theirs != mine and theirs not in PACKAGES[mine]:
                how = "a package above it" if mine in PACKAGES[theirs] else "a peer"
                bad.append(f"{where}: {mine} may not import {theirs}, {how}")
    return sorted(bad)


def test_no_module_imports_a_package_above_its_own_or_a_peer() -> None:
    assert violations() == []


def module_imports() -> dict[str, set[str]]:
    """{module: the modules of ours it imports}: `from pkg import name` is pkg.name where that is a module."""
    found = modules()

    def module(target: str) -> str:
        while target and target not in found:
            target = target.rpartition(".")[0]
        return target

    return {name: {module(t) for _, t in imports(name, path) if is_ours(t)} - {name, ""}
            for name, path in found.items()}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The groups of modules that import each other, each sorted (Tarjan's strongly connected components)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while not group or group[-1] != v:
                group.append(stack.pop())
            if len(group) > 1:
                out.append(sorted(group))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_no_modules_import_each_other() -> None:
    """No circle of imports, lazy ones included: a module that needs another's names and is needed by it
    is one module, or two that share a third below them."""
    assert cycles(module_imports()) == []


def test_the_cycle_finder_finds_a_circle() -> None:
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_the_wire_package_needs_only_the_standard_library() -> None:
    bad = []
    for name, path in modules().items():
        if package_of(name) != WIRE:
            continue
        for line, target in imports(name, path):
            top = target.split(".")[0]
            if top == "__future__":
                continue
            if is_ours(target) and package_of(target) == WIRE:
                continue
            if top not in sys.stdlib_module_names:
                bad.append(f"{name}:{line} imports {target}")
    assert bad == []


ROOT_MAY_IMPORT = {"hakoniwa": "hakoniwa.wire.numerics."}


def test_the_package_roots_import_nothing() -> None:
    """Importing a package must not drag in its layers (hakoniwa/__init__ would otherwise pull MuJoCo into
    a process that needs only the wire contract). One exception: `hakoniwa` pins the floating-point kernels
    (stdlib only), which must happen before anything imports numpy."""
    for name in ("hakoniwa", "hakoniwa.physics", "hakoniwa.pictures", "hakoniwa.wire", "testctl.hako", "testctl",
                 "testctl.suite", "testctl.search", "testctl.campaign", "athrill_sim", "athrill_sim.mock",
                 "athrill_sim.programs", "athrill_sim.programs.kinds", "athrill_sim.tuning",
                 "athrill_sim.tuning.forms", "maze", "maze.log", "maze.files", "maze.search", "maze.timing",
                 "maze.mouse", "maze.pictures", "maze.scoring"):
        path = modules()[name]
        allowed = ROOT_MAY_IMPORT.get(name)
        found = [t for _, t in imports(name, path) if is_ours(t)]
        assert [t for t in found if allowed is None or not t.startswith(allowed)] == [], name


def test_the_athrill_side_root_holds_folders_only() -> None:
    """`athrill_sim/` is its concepts' folders (the mock, the programs, the tuning, the builders), so no module
    at its root mixes two of them."""
    assert [p.name for p in (REPO / "athrill_sim").glob("*.py")] == ["__init__.py"]


def test_the_maze_root_holds_only_what_its_folders_share() -> None:
    """`maze/` is its concepts' folders (the log, the files, the search, the fast path, the time model, a user's
    mouse, the pictures, the scoring); its root keeps only the maze, its directions, the errors and writing a file
    whole, which the folders share, and the `mazelog` command that joins them, so no module there mixes two of them."""
    assert sorted(p.name for p in (REPO / "maze").glob("*.py")) == [
        "__init__.py", "cli.py", "direction.py", "errors.py", "model.py", "outputs.py"]


def test_the_design_notes_draw_these_packages() -> None:
    """docs/DESIGN-NOTES.md's diagram names the packages' folders in PACKAGES' order, so it cannot drift."""
    page = (REPO / "docs" / "DESIGN-NOTES.md").read_text()
    diagram = page.split("## Layers", 1)[1].split("```", 2)[1]
    folders = re.findall(r"^  ([\w/]+?)(?:/|\.py)? ", diagram, re.MULTILINE)
    drawn = [f.replace("/", ".") for f in folders if f not in STANDALONE]
    assert drawn == list(PACKAGES)


@pytest.mark.parametrize("module, source, expected", [
    ("hakoniwa.physics.bad", "from testctl.hako.main import main\n",
     ["hakoniwa.physics may not import testctl.hako, a package above it"]),
    ("hakoniwa.physics.bad", "import testctl.campaign.loop\n",
     ["hakoniwa.physics may not import testctl, a package above it"]),
    ("hakoniwa.physics.bad", "from maze import model\n", ["maze stands apart"]),
    ("hakoniwa.physics.bad", "from hakoniwa.wire.protocol import Rx\nfrom athrill_sim import programs\n",
     ["hakoniwa.physics may not import athrill_sim, a peer"]),
    ("athrill_sim.bad", "from hakoniwa.physics.world import World\n",
     ["athrill_sim may not import hakoniwa.physics, a peer"]),
    ("testctl.campaign.bad", "from testctl.hako.main import main\n",
     ["testctl may not import testctl.hako, a package above it"]),
    ("testctl.hako.bad", "from hakoniwa.wire.protocol import Rx\nfrom testctl.campaign import loop\n", []),
])
def test_the_checker_catches_an_upward_import(tmp_path: Path, monkeypatch, module: str, source: str,
                                              expected: list[str]) -> None:
    """The checker itself: a module that imports upwards or its peer is reported (so the test above can fail)."""
    fake = tmp_path.joinpath(*module.split(".")).with_suffix(".py")
    fake.parent.mkdir(parents=True)
    fake.write_text(source)
    real = modules()
    monkeypatch.setattr(sys.modules[__name__], "modules", lambda: {**real, module: fake})
    found = [v for v in violations() if v.startswith(f"{module}:")]
    assert len(found) == len(expected)
    for v, words in zip(found, expected):
        assert words in v
