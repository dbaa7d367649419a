"""The journal records hashes of the program's and the course's files, and `--resume` refuses when any of them
changed, naming what changed: a resumed campaign must not mix results of two programs."""

from __future__ import annotations

import shutil
import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from athrill_sim.programs.python_sources import program_sources
from hakoniwa.physics.course import COURSES_DIR
from testctl.bench_options import BenchOptions
from testctl.campaign.fingerprint import FILES_KEY, WORKSPACE, changes, fingerprint
from testctl.campaign.journal import JOURNAL_FILE, read_journal
from tests.helpers.commands import hako, one_line_error
from tests.helpers.native_fixtures import need_cc

IDLE_C = '#include "ev3api.h"\nvoid main_task(intptr_t unused) { while (1) tslp_tsk(100000); }\n'
FIELDS = ("course", "app")


def test_a_changed_python_module_or_course_file_is_named(tmp_path, monkeypatch):
    (tmp_path / "myapp.py").write_text("def main_task(api):\n    pass\n")
    course = tmp_path / "course"
    shutil.copytree(COURSES_DIR / "oval", course)
    monkeypatch.syspath_prepend(str(tmp_path))
    bench = BenchOptions(app="myapp:main_task", course=str(course))
    before = fingerprint(bench, FIELDS)
    assert set(before) == {"app", "course"} and set(before["app"]) == {"myapp.py"}
    assert changes(before, fingerprint(bench, FIELDS), bench) == []
    (tmp_path / "myapp.py").write_text("def main_task(api):\n    api.tslp_tsk(1)\n")
    with open(course / "course.toml", "a") as f:
        f.write("# edited\n")
    assert changes(before, fingerprint(bench, FIELDS), bench) == [
        "--app myapp:main_task: myapp.py changed", f"--course {course}: course.toml changed"]


def test_the_builtin_programs_and_course_are_hashed_too():
    hashes = fingerprint(BenchOptions(), FIELDS)
    assert set(hashes["app"]) == {"line_trace.py"}
    assert {"course.toml", "floor.png"} <= set(hashes["course"])


@pytest.mark.slow
def test_resume_refuses_a_changed_program_or_course_naming_it(tmp_path):
    need_cc()
    app = tmp_path / "idle.c"
    app.write_text(IDLE_C)
    course = tmp_path / "course"
    shutil.copytree(COURSES_DIR / "oval", course)
    out = tmp_path / "c"
    first = hako("run", "--smoke", "--app", str(app), "--course", str(course), "--time-limit", "1", "--out", str(out))
    assert "no parameter set succeeded" in first.stderr, first.stderr  # the idle program never laps
    header, records = read_journal(out / JOURNAL_FILE)
    assert set(header["bench"][FILES_KEY]) == {"app", "course"} and len(records) > 0
    app.write_text(IDLE_C.replace("100000", "50000"))
    one_line_error(hako("run", "--resume", str(out)), "--resume", f"--app {app}: idle.c changed")
    app.write_text(IDLE_C)
    (course / "course.toml").write_text((course / "course.toml").read_text() + "# edited\n")
    one_line_error(hako("run", "--resume", str(out)), f"--course {course}: course.toml changed")
    assert read_journal(out / JOURNAL_FILE)[1] == records  # nothing was run


def test_a_changed_helper_module_the_program_imports_is_named_and_nothing_is_run(tmp_path, monkeypatch):
    """A user's program split over modules: an edited helper changes the program's hash as its main module
    does. The modules are read, never run (a top-level side effect would show), and the standard library,
    installed packages and the bench's own modules are not the program's."""
    ran = tmp_path / "ran"
    (tmp_path / "tracer").mkdir()
    (tmp_path / "tracer" / "__init__.py").write_text(f"open({str(ran)!r}, 'w').close()\n")
    (tmp_path / "tracer" / "main.py").write_text(
        "import json, numpy\nfrom athrill_sim.mock.ev3api import Ev3Api\nfrom . import gains\n"
        "from .steer import steer\n"
        "def main_task(api):\n    steer(api, gains.KP)\n")
    (tmp_path / "tracer" / "gains.py").write_text("from tracer.filters import smooth\nKP = 1.0\n")
    (tmp_path / "tracer" / "steer.py").write_text("def steer(api, kp):\n    pass\n")
    (tmp_path / "tracer" / "filters.py").write_text("import helpers\ndef smooth(x):\n    return x\n")
    (tmp_path / "helpers.py").write_text("X = 1\n")
    (tmp_path / "unused.py").write_text("Y = 2\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    bench = BenchOptions(app="tracer.main:main_task")
    before = fingerprint(bench, ("app",))
    assert set(before["app"]) == {"helpers.py", "tracer/__init__.py", "tracer/main.py", "tracer/gains.py",
                                  "tracer/steer.py", "tracer/filters.py"}
    assert not ran.exists()
    (tmp_path / "helpers.py").write_text("X = 2\n")
    (tmp_path / "unused.py").write_text("Y = 3\n")
    assert changes(before, fingerprint(bench, ("app",)), bench) == [
        "--app tracer.main:main_task: helpers.py changed"]


@st.composite
def module_graphs(draw) -> tuple[dict[str, list[tuple[str, str]]], str]:
    """Modules m0..mN, some in package p, each importing others in one of the styles a user writes."""
    count = draw(st.integers(1, 6))
    names = [f"p.m{i}" if draw(st.booleans()) else f"m{i}" for i in range(count)]
    edges = {name: [(draw(st.sampled_from(names)), draw(st.sampled_from(STYLES)))
                    for _ in range(draw(st.integers(0, 3)))] for name in names}
    return edges, names[0]


STYLES = ("import", "from", "relative", "inside a function")


def import_line(importer: str, imported: str, style: str) -> str:
    package, _, leaf = imported.rpartition(".")
    if style == "relative" and importer.startswith("p.") and package == "p":
        return f"from . import {leaf}\n"
    if style == "from":
        return f"from {package} import {leaf}\n" if package else f"from {leaf} import X\n"
    if style == "inside a function":
        return f"def f():\n    import {imported}\n"
    return f"import {imported}\n"


@settings(max_examples=40, deadline=None)
@given(module_graphs())
def test_the_program_files_are_exactly_the_modules_its_imports_reach(tmp_path_factory, graph):
    edges, main = graph
    root = tmp_path_factory.mktemp("prog")
    (root / "p").mkdir()
    (root / "p" / "__init__.py").write_text("")
    for name, imports in edges.items():
        body = "import json\nX = 1\n" + "".join(import_line(name, other, style) for other, style in imports)
        (root / (name.replace(".", "/") + ".py")).write_text(body)
    reached, todo = set(), [main]
    while todo:
        name = todo.pop()
        if name not in reached:
            reached.add(name)
            todo += [other for other, _ in edges[name]]
    expected = {root / (n.replace(".", "/") + ".py") for n in reached}
    if any(n.startswith("p.") for n in reached):
        expected.add(root / "p" / "__init__.py")
    sys.path.insert(0, str(root))
    try:
        assert set(program_sources(main)) == {p.resolve() for p in expected}
    finally:
        sys.path.remove(str(root))


def test_every_file_a_tests_workspace_copy_holds_is_hashed(tmp_path):
    """A native program's tests each start from a copy of its workspace (athrill_sim/programs/working_folder.py): the
    command file no parameter names, a file in the workspace beside the app folder and the SD card's are what
    the program reads at run time, so an edit of any of them between a kill and `--resume` is named."""
    need_cc()
    app = tmp_path / "workspace" / "tracer"
    (app / "datafiles").mkdir(parents=True)
    (app / "sdcard").mkdir()
    (app / "app.c").write_text(IDLE_C)
    (app / "app.cfg").write_text('#include "app.h"\nCRE_TSK(MAIN_TASK, { TA_ACT, 0, main_task, TMIN_APP_TPRI + 1, '
                                 '4096, NULL });\n')
    (app / "app.h").write_text('#include "ev3api.h"\nvoid main_task(intptr_t exinf);\n')
    edited = [app / "datafiles" / "commands.txt", app.parent / "tracer.ini", app / "sdcard" / "course.txt"]
    for f in edited:
        f.write_text("1\n")
    bench = BenchOptions(app=str(app))
    before = fingerprint(bench, ("app",))
    for f in edited:
        f.write_text("2\n")
        changed = changes(before, fingerprint(bench, ("app",)), bench)
        assert len(changed) == 1 and changed[0].startswith(f"--app {app}"), changed
        assert changed[0].endswith(f"{f.name} changed"), changed
        f.write_text("1\n")
    without = {k: v for k, v in before.items() if k != WORKSPACE}  # a journal from before the workspace counted
    edited[0].write_text("3\n")
    assert changes(without, fingerprint(bench, ("app",)), bench) == []
