"""The contracts between the pieces, held by tests: what the sync loops may use of the physics server, the
one error base of each program, and the exit statuses defined in one module."""

from __future__ import annotations

import ast
import importlib
import inspect
import os
import re
from pathlib import Path

import pytest

from hakoniwa.physics.sync import SyncServer
from hakoniwa.wire import exits
from hakoniwa.wire.errors import HakoError
from maze.errors import MazelogError
from tests.helpers.paths import REPO

PHYSICS = REPO / "hakoniwa" / "physics"
# Exceptions that steer a loop rather than report an error to the user (see hakoniwa/wire/errors.py).
SIGNALS = {"AthrillCrash", "ControllerGone", "KernelExit", "PowerCut", "Terminated", "RunBroken"}


def protocol_members(protocol: type) -> set[str]:
    return {name for name in vars(protocol) if not name.startswith("_")}


def server_members() -> set[str]:
    """PhysicsServer's methods and properties, and the attributes its __init__ sets."""
    tree = ast.parse((PHYSICS / "server.py").read_text())
    cls = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "PhysicsServer")
    names = {n.name for n in cls.body if isinstance(n, ast.FunctionDef)}
    init = next(n for n in cls.body if isinstance(n, ast.FunctionDef) and n.name == "__init__")
    names |= {t.attr for n in ast.walk(init) if isinstance(n, ast.Assign) for t in n.targets
              if isinstance(t, ast.Attribute) and isinstance(t.value, ast.Name) and t.value.id == "self"}
    return names


def test_the_physics_server_has_what_the_sync_loops_need():
    needed = protocol_members(SyncServer)
    assert {"slots", "advance_to", "apply_actuators", "publish_sensors"} <= needed
    assert needed - server_members() == set()


def test_the_sync_loops_read_athrill_only_through_slots():
    source = (PHYSICS / "sync.py").read_text()
    tree = ast.parse(source)
    imported = {alias.name for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) for alias in n.names}
    assert not imported & {"Tx", "Header", "HEADER_SIZE", "MappedFile"}
    assert not re.search(r"\.athrill\b", source), "a loop reads the TX file itself"


def our_exceptions() -> list[type[BaseException]]:
    found = []
    for pkg in ("hakoniwa", "athrill_sim", "testctl", "maze"):
        for path in sorted((REPO / pkg).rglob("*.py")):
            text = path.read_text()
            if not re.search(r"^class \w+\(.*(Error|Exception|Interrupt)\b", text, re.M):
                continue
            parts = path.relative_to(REPO).with_suffix("").parts
            module = importlib.import_module(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
            found += [c for c in vars(module).values() if inspect.isclass(c) and issubclass(c, BaseException)
                      and c.__module__ == module.__name__]
    return found


def test_every_error_derives_from_its_programs_base():
    classes = our_exceptions()
    assert len(classes) > 25
    wrong = [f"{c.__module__}.{c.__name__}" for c in classes if c.__name__ not in SIGNALS
             and not issubclass(c, MazelogError if c.__module__.startswith("maze.") else HakoError)]
    assert wrong == []
    names = [c.__name__ for c in classes]
    assert len(names) == len(set(names)), "two errors of one name"


def constant(node: ast.expr) -> object:
    return node.value if isinstance(node, ast.Constant) else None


def literal_statuses(path: Path) -> list[str]:
    """Where `path` writes an exit status as a number: a signal's status (130, 143, 128 + N), or an exit,
    SystemExit or `exit_code` other than 0 and 1 (success and click's error)."""
    hits = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub)) and constant(node.left) == 128:
            hits.append(node)
        elif isinstance(node, ast.Call) and getattr(node.func, "attr", getattr(node.func, "id", "")) in \
                {"exit", "Exit", "SystemExit"} and node.args and constant(node.args[0]) not in (None, 0, 1):
            hits.append(node)
        elif isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "exit_code" for t in node.targets) \
                and isinstance(node.value, ast.Constant):
            hits.append(node)
        elif isinstance(node, ast.IfExp) and {constant(node.body), constant(node.orelse)} & {130, 143}:
            hits.append(node)
    return [f"{path.relative_to(REPO)}:{node.lineno}" for node in hits]


@pytest.mark.parametrize("pkg", ["hakoniwa", "athrill_sim", "testctl", "maze"])
def test_exit_statuses_are_named_in_one_module(pkg):
    hits = [hit for path in sorted((REPO / pkg).rglob("*.py")) if path.name != "exits.py"
            for hit in literal_statuses(path)]
    assert hits == []


def test_the_exit_statuses_are_a_shells():
    assert (exits.EXIT_INTERRUPTED, exits.EXIT_TERMINATED) == (130, 143)
    assert exits.exit_status(-9) == 137 and exits.exit_status(3) == 3


class FakeAthrill:
    """Slots and transport at once: Athrill's clock moves 7 ms each time the loop receives."""

    def __init__(self) -> None:
        self.clock_us = 0

    def athrill_time_us(self) -> int:
        return self.clock_us

    def receive(self) -> None:
        self.clock_us += 7000

    def wait_for(self, ready, on_idle) -> None:
        while not ready():
            self.receive()


class FakeServer:
    """A SyncServer without MuJoCo: what `run_hakoniwa` does is read off the steps it asks for."""

    def __init__(self, end_us: int) -> None:
        self.slots = self.transport = FakeAthrill()
        self.scheduler = type("Ticks", (), {"next_tick": staticmethod(lambda: 10**12)})()
        self.now_us, self.end_us, self.answer_before_start = 0, end_us, 0
        self.run_dir, self.athrill_timeout_s = REPO, 10.0
        self.ahead_us: list[int] = []

    def advance_to(self, target_us: int) -> bool:
        self.now_us = target_us
        self.ahead_us.append(target_us - self.slots.clock_us)
        return target_us >= self.end_us

    def check_ceiling(self) -> None: ...
    def note_time_diff(self, diff_us: int) -> None: ...
    def publish_sensors(self) -> None: ...
    def apply_actuators(self) -> None: ...


def test_a_sync_loop_runs_against_the_protocol_alone():
    from hakoniwa.physics.sync import run_hakoniwa
    from hakoniwa.wire.timebase import ALLOWED_TIME_DIFF_US, PHYSICS_STEP_US

    server = FakeServer(end_us=100_000)
    proc = type("Proc", (), {"pid": os.getpid(), "poll": staticmethod(lambda: None)})()
    run_hakoniwa(server, proc)
    assert server.now_us >= server.end_us and server.now_us % PHYSICS_STEP_US == 0
    assert max(server.ahead_us) <= ALLOWED_TIME_DIFF_US
