"""The package layout is a stack of layers: a module may import its own layer and the layers below it, never
one above it, and `maze` stands apart. The imports are read from the source (ast), including those inside
functions, so a lazy import cannot hide a cycle."""

from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

import pytest

from tests.helpers.paths import REPO

OURS = ("hakoniwa", "athrill_sim", "testctl", "maze")

# Bottom to top. A module belongs to the first entry whose prefix it starts with.
LAYERS: list[tuple[str, tuple[str, ...]]] = [
    ("wire", ("hakoniwa.wire",)),  # the contract every process shares: stdlib only
    ("conventions", ("hakoniwa.conventions",)),  # what every command line shares
    ("athrill", ("athrill_sim",)),  # the robot program: resolving, building and running it
    ("physics", ("hakoniwa.physics",)),  # the "Unity" side, which starts Athrill for each test
    ("controller", ("testctl",)),  # tests, campaigns, benches
    ("cli", ("hakoniwa.cli",)),  # the user's `hako`: imported by nothing
]
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


def layer_of(module: str) -> int | None:
    for i, (_, prefixes) in enumerate(LAYERS):
        if any(module == p or module.startswith(p + ".") for p in prefixes):
            return i
    return None


def is_ours(module: str) -> bool:
    return module.split(".")[0] in OURS


def test_every_module_of_the_bench_has_a_layer() -> None:
    homeless = [m for m in modules() if layer_of(m) is None and m.split(".")[0] not in STANDALONE
                and m not in ("hakoniwa", "hakoniwa.physics")]
    assert homeless == []


def violations() -> list[str]:
    found = modules()
    bad = []
    for name, path in found.items():
        mine = layer_of(name)
        for line, target in imports(name, path):
            if not is_ours(target):
                continue
            where = f"{name}:{line} imports {target}"
            if name.split(".")[0] in STANDALONE or target.split(".")[0] in STANDALONE:
                shared = target in SHARED_WITH_STANDALONE or target.rpartition(".")[0] in SHARED_WITH_STANDALONE
                if name.split(".")[0] != target.split(".")[0] and not shared:
                    bad.append(f"{where}: maze stands apart from the bench")
                continue
            theirs = layer_of(target)
            if theirs is None:  # a package itself (`from hakoniwa.physics import robot` names the module)
                continue
            if mine is not None and theirs > mine:
                bad.append(f"{where}: {LAYERS[mine][0]} may not import {LAYERS[theirs][0]}, a layer above it")
    return sorted(bad)


def test_no_module_imports_a_layer_above_its_own() -> None:
    assert violations() == []


def test_the_wire_package_needs_only_the_standard_library() -> None:
    bad = []
    for name, path in modules().items():
        if layer_of(name) != 0:
            continue
        for line, target in imports(name, path):
            top = target.split(".")[0]
            if top == "__future__":
                continue
            if is_ours(target) and layer_of(target) == 0:
                continue
            if top not in sys.stdlib_module_names:
                bad.append(f"{name}:{line} imports {target}")
    assert bad == []


ROOT_MAY_IMPORT = {"hakoniwa": "hakoniwa.wire.numerics."}


def test_the_package_roots_import_nothing() -> None:
    """Importing a package must not drag in its layers (hakoniwa/__init__ would otherwise pull MuJoCo into
    a process that needs only the wire contract). One exception: `hakoniwa` pins the floating-point kernels
    (stdlib only), which must happen before anything imports numpy."""
    for name in ("hakoniwa", "hakoniwa.physics", "hakoniwa.wire", "hakoniwa.cli", "testctl", "testctl.suite",
                 "testctl.search", "testctl.campaign", "athrill_sim"):
        path = modules()[name]
        allowed = ROOT_MAY_IMPORT.get(name)
        found = [t for _, t in imports(name, path) if is_ours(t)]
        assert [t for t in found if allowed is None or not t.startswith(allowed)] == [], name


def test_the_design_notes_draw_these_layers() -> None:
    """docs/DESIGN-NOTES.md's diagram names the layers' folders in LAYERS' order, so it cannot drift."""
    page = (REPO / "docs" / "DESIGN-NOTES.md").read_text()
    diagram = page.split("## Layers", 1)[1].split("```", 2)[1]
    folders = re.findall(r"^  ([\w/]+?)(?:/|\.py)? ", diagram, re.MULTILINE)
    drawn = [f.replace("/", ".") for f in folders if f not in STANDALONE]
    assert drawn == [prefixes[0] for _, prefixes in LAYERS]


@pytest.mark.parametrize("source, expected", [
    ("from hakoniwa.cli.main import main\n", ["physics may not import cli"]),
    ("import testctl.campaign.loop\n", ["physics may not import controller"]),
    ("from maze import model\n", ["maze stands apart"]),
    ("from hakoniwa.wire.protocol import Rx\nfrom athrill_sim import programs\n", []),
])
def test_the_checker_catches_an_upward_import(tmp_path: Path, monkeypatch, source: str, expected: list[str]) -> None:
    """The checker itself: a physics module that imports upwards is reported (so the test above can fail)."""
    fake = tmp_path / "hakoniwa" / "physics" / "bad.py"
    fake.parent.mkdir(parents=True)
    fake.write_text(source)
    real = modules()
    monkeypatch.setattr(sys.modules[__name__], "modules", lambda: {**real, "hakoniwa.physics.bad": fake})
    found = [v for v in violations() if v.startswith("hakoniwa.physics.bad:")]
    assert len(found) == len(expected)
    for v, words in zip(found, expected):
        assert words in v
