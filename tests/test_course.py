import shutil

import pytest

from hakoniwa.course import COURSES_DIR, CourseError, load_course


def copy_oval(tmp_path):
    dst = tmp_path / "mycourse"
    shutil.copytree(COURSES_DIR / "oval", dst)
    return dst


def test_builtin_oval_is_the_papers_course():
    c = load_course("oval")
    assert len(c.checkpoints) == 4
    assert c.time_limit_us == 60_000_000
    assert c.floor.min() >= 50 and c.floor.max() == pytest.approx(100)


def test_a_copied_folder_is_a_course(tmp_path):
    folder = copy_oval(tmp_path)
    (folder / "course.toml").write_text((folder / "course.toml").read_text().replace("time_limit_s = 60",
                                                                                      "time_limit_s = 90"))
    assert load_course(folder).time_limit_us == 90_000_000
    assert load_course(folder / "course.toml").name == "oval"


@pytest.mark.parametrize("edit, message", [
    (lambda t: t + "\n[[[broken", "not valid TOML"),
    (lambda t: t.replace('floor_image = "floor.png"', 'floor_image = "nope.png"'), "not found"),
    (lambda t: t.replace("time_limit_s = 60", 'time_limit_s = "soon"'), "must be a number"),
    (lambda t: t.replace("time_limit_s = 60", "time_limit_s = -1"), "positive"),
    (lambda t: t.replace("[[checkpoint]]", "[[unused]]"), "at least one"),
    (lambda t: t.replace("hx = 0.05", "hx = 0"), "half sizes"),
    (lambda t: t.replace("origin = [-1.5, -0.9]", "origin = 3"), "origin"),
])
def test_bad_course_files_are_clear_errors(tmp_path, edit, message):
    folder = copy_oval(tmp_path)
    toml = folder / "course.toml"
    toml.write_text(edit(toml.read_text()))
    with pytest.raises(CourseError, match=message):
        load_course(folder)


def test_unreadable_floor_image(tmp_path):
    folder = copy_oval(tmp_path)
    (folder / "floor.png").write_bytes(b"not a png")
    with pytest.raises(CourseError, match="not a readable image"):
        load_course(folder)


def test_unknown_course_lists_the_builtin_ones(tmp_path):
    with pytest.raises(CourseError, match="built-in courses: oval"):
        load_course(tmp_path / "missing")
