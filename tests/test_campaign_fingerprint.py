"""The journal records hashes of the program's and the course's files, and `--resume` refuses when any of them
changed, naming what changed: a resumed campaign must not mix results of two programs."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from conftest import hako, one_line_error
from native_fixtures import need_cc
from hakoniwa.physics.course import COURSES_DIR
from hakoniwa.physics.options import BenchOptions
from testctl.fingerprint import FILES_KEY, changes, fingerprint
from testctl.journal import JOURNAL_FILE, read_journal

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
