"""The source files a Python robot program is made of: its module and the user's own modules it imports, at any
depth, found by reading their import statements. A campaign hashes them into its journal, so that `--resume`
notices an edited helper module as it notices an edited main module (results of two programs under one name).

Nothing is run to find them: the controller must not execute a user's module (its top level may start motors
or loop), so packages are searched with `PathFinder`, which never imports a parent package as
`importlib.util.find_spec` does. The standard library, installed packages and this bench's own packages are
not the program's: their versions belong to the environment.
"""

from __future__ import annotations

import ast
import sysconfig
from functools import cache
from importlib.machinery import PathFinder
from pathlib import Path

import athrill_sim

BENCH_ROOT = Path(athrill_sim.__file__).resolve().parent.parent  # hakoniwa-py's packages lie side by side here
BENCH_PACKAGES = ("athrill_sim", "hakoniwa", "testctl", "maze")


def program_sources(module: str) -> tuple[Path, ...]:
    """The module's file, its packages' and those of the user's modules they import; () if the module's file
    is not found (the program check then says why it cannot load)."""
    first = locate(module)
    if first is None:
        return ()
    seen: set[Path] = set()
    parts = module.split(".")
    packages = [".".join(parts[:i]) for i in range(1, len(parts))]  # imported before the module, so run too
    queue = [(module, first)] + [(name, found) for name in packages
                                 if (found := locate(name)) is not None and is_users(found)]
    while queue:
        name, path = queue.pop()
        if path in seen:
            continue
        seen.add(path)
        for imported in imports_of(name, path):
            found = locate(imported)
            if found is not None and is_users(found):
                queue.append((imported, found))
    return tuple(sorted(seen))


def locate(name: str) -> Path | None:
    """The .py file of module `name` on sys.path (a package's __init__.py), without importing anything."""
    search = None
    spec = None
    parts = name.split(".")
    for i in range(len(parts)):
        spec = PathFinder.find_spec(".".join(parts[: i + 1]), search)
        if spec is None:
            return None
        search = spec.submodule_search_locations
        if search is None and i < len(parts) - 1:
            return None
    origin = spec.origin if spec is not None else None
    if not origin or not origin.endswith(".py") or not Path(origin).is_file():
        return None
    return Path(origin).resolve()


def imports_of(name: str, path: Path) -> list[str]:
    """Every module name an import statement of the module names, its parent packages included: for `from
    a import b`, both `a` and `a.b` (b may be a module or a name in a). A file that does not parse imports
    nothing here (it fails when the program loads)."""
    try:
        tree = ast.parse(path.read_bytes(), filename=str(path))
    except (SyntaxError, ValueError):
        return []
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    names: list[str] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parent = package.split(".") if package else []
                if node.level - 1 > len(parent):
                    continue  # beyond the top-level package: fails when the program loads
                parent = parent[: len(parent) - (node.level - 1)]
                base = ".".join(parent + ([node.module] if node.module else []))
            if base:
                names.append(base)
            names += [f"{base}.{alias.name}" if base else alias.name for alias in node.names if alias.name != "*"]
    with_parents = []
    for full in names:
        parts = full.split(".")
        with_parents += [".".join(parts[: i + 1]) for i in range(len(parts))]
    return list(dict.fromkeys(with_parents))


def is_users(path: Path) -> bool:
    """Neither the standard library, nor an installed package, nor one of this bench's packages."""
    return not any(path.is_relative_to(root) for root in not_users_roots())


@cache
def not_users_roots() -> tuple[Path, ...]:
    environment = {sysconfig.get_paths()[key] for key in ("stdlib", "platstdlib", "purelib", "platlib")}
    return tuple(Path(p).resolve() for p in environment) + tuple(BENCH_ROOT / package for package in BENCH_PACKAGES)
