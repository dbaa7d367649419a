import shutil

import pytest

from hakoniwa.physics.course import COURSES_DIR, CourseError, load_course
from hakoniwa.physics.noise import DEFAULT_NOISE


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
    (lambda t: t.replace("[[checkpoint]]", "[[wall]]"), "at least one"),
    (lambda t: t.replace("hx = 0.05", "hx = 0"), "half sizes"),
    (lambda t: t.replace("origin = [-1.5, -0.9]", "origin = 3"), "origin"),
    (lambda t: t.replace("reflect_sd = 0.5", 'reflect_sd = "loud"'), r"\[noise\]: 'reflect_sd' must be a number"),
    (lambda t: t.replace("ultrasonic_sd_mm = 5.0", "ultrasonic_sd_mm = -1"), "'ultrasonic_sd_mm' must not be negative"),
    (lambda t: t.replace("[noise]\n", "[noise]\nsonar_sd = 1\n"), "unknown key 'sonar_sd'"),
    (lambda t: without_noise_table(t).replace("wall_height = 0.1", "wall_height = 0.1\nnoise = 3"),
     r"\[noise\]: must be a table"),
])
def test_bad_course_files_are_clear_errors(tmp_path, edit, message):
    folder = copy_oval(tmp_path)
    toml = folder / "course.toml"
    toml.write_text(edit(toml.read_text()))
    with pytest.raises(CourseError, match=message):
        load_course(folder)


@pytest.mark.parametrize("edit, where, key", [
    (lambda t: t.replace("yaw_deg = 0", "yaw_deg = 0\nheading = 90"), "[start]", "heading"),
    (lambda t: t.replace("wall_height = 0.1", "walll_height = 0.1"), "", "walll_height"),
    (lambda t: t.replace("[[checkpoint]]\n", "[[checkpoint]]\ncolour = \"red\"\n", 1), "[[checkpoint]] 0", "colour"),
    (lambda t: t.replace("[[wall]]\n", "[[wall]]\nheight = 1\n", 1), "[[wall]] 0", "height"),
    (lambda t: t + "[robot]\nleft_motor = \"A\"\nright = \"B\"\n", "[robot]", "right"),
    (lambda t: t + "[etroboc]\ncard = 1\n", "[etroboc]", "card"),
    (lambda t: t + "[[area]]\nx = 0\ny = 0\nhx = 0.1\nhy = 0.1\ncolor = \"red\"\nname = \"a\"\nshade = 1\n",
     "[[area]] 0", "shade"),
])
def test_an_unknown_key_is_one_line_naming_it_and_the_file(tmp_path, edit, where, key):
    """A misspelt key changed nothing and the run went on; scenario files refuse theirs."""
    folder = copy_oval(tmp_path)
    toml = folder / "course.toml"
    toml.write_text(edit(toml.read_text()))
    with pytest.raises(CourseError) as e:
        load_course(folder)
    assert str(e.value).startswith(f"{toml} {where}".rstrip() + f": unknown key {key!r} (known: "), str(e.value)


def test_unreadable_floor_image(tmp_path):
    folder = copy_oval(tmp_path)
    (folder / "floor.png").write_bytes(b"not a png")
    with pytest.raises(CourseError, match="not a readable image"):
        load_course(folder)


def test_unknown_course_lists_the_builtin_ones(tmp_path):
    with pytest.raises(CourseError, match="built-in courses: etrobocon-l, etrobocon-r, oval"):
        load_course(tmp_path / "missing")


def without_noise_table(text: str) -> str:
    return text[: text.index("[noise]")]


def test_the_oval_writes_out_the_default_noise_levels():
    assert load_course("oval").noise == DEFAULT_NOISE


def test_noise_levels_left_out_keep_their_defaults(tmp_path):
    folder = copy_oval(tmp_path)
    toml = folder / "course.toml"
    toml.write_text(without_noise_table(toml.read_text()))
    assert load_course(folder).noise == DEFAULT_NOISE
    toml.write_text(toml.read_text() + "[noise]\nstart_yaw_sd_deg = 0\nmotor_gain_sd = 0.05\n")
    noise = load_course(folder).noise
    assert (noise.start_yaw_sd_deg, noise.motor_gain_sd) == (0.0, 0.05)
    assert noise.reflect_sd == DEFAULT_NOISE.reflect_sd


def test_colour_id_black_line_white_floor_grey_edge():
    from hakoniwa.wire.protocol import ColorId

    c = load_course("oval")
    assert c.color_at(0.0, -0.5, c.reflect_at(0.0, -0.5))[0] == ColorId.BLACK  # line centre
    assert c.color_at(0.0, -0.3, c.reflect_at(0.0, -0.3)) == (ColorId.WHITE, (255, 255, 255))
    assert c.color_at(0.0, -0.5, 75.0)[0] == ColorId.NONE  # the grey edge: half way from black to white


def test_coloured_areas_and_wiring_come_from_the_toml(tmp_path):
    from hakoniwa.wire.protocol import ColorId

    folder = copy_oval(tmp_path)
    toml = folder / "course.toml"
    toml.write_text(toml.read_text() + '\n[[area]]\ncolor = "red"\nx = 1.25\ny = 0.0\nhx = 0.05\nhy = 0.05\n'
                    '\n[robot]\nleft_motor = "C"\nright_motor = "B"\n')
    c = load_course(folder)
    assert c.color_at(1.25, 0.0, 50.0) == (ColorId.RED, (220, 0, 0))
    assert (c.wiring.left, c.wiring.right) == (2, 1)
    assert (load_course("oval").wiring.left, load_course("oval").wiring.right) == (0, 1)  # A and B


@pytest.mark.parametrize("extra, message", [
    ('\n[[area]]\ncolor = "plaid"\nx = 0\ny = 0\nhx = 1\nhy = 1\n', "'color' must be one of"),
    ('\n[robot]\nleft_motor = "E"\n', "motor port A..D"),
    ('\n[robot]\nleft_motor = "B"\nright_motor = "B"\n', "must be different"),
])
def test_bad_areas_and_wiring_are_clear_errors(tmp_path, extra, message):
    folder = copy_oval(tmp_path)
    toml = folder / "course.toml"
    toml.write_text(toml.read_text() + extra)
    with pytest.raises(CourseError, match=message):
        load_course(folder)


@pytest.mark.parametrize("shadow", ["file", "folder"])
def test_a_file_or_folder_named_oval_does_not_shadow_the_builtin_course(tmp_path, monkeypatch, shadow):
    local = tmp_path / "oval"
    local.mkdir() if shadow == "folder" else local.write_text("not a course")
    monkeypatch.chdir(tmp_path)
    assert load_course("oval").folder == COURSES_DIR / "oval"
    with pytest.raises(CourseError, match="oval"):
        load_course("./oval")  # the local one, named as a path


def test_hako_try_takes_the_builtin_course_beside_a_folder_named_oval(tmp_path):
    import json

    from tests.helpers.commands import hako

    (tmp_path / "oval").mkdir()
    (tmp_path / "line_trace").write_text("")  # nor does a file shadow a built-in app
    r = hako("try", "--course", "oval", "--time-limit", "1", "--noise", "0", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["event"] == "TIME_OVER"


def test_a_picture_for_a_figure_has_at_most_the_pixels_asked_for():
    """`hako course show` of a 96 Mpx mat took 22 s and 5.6 GB: the figure draws every n-th pixel."""
    course = load_course("etrobocon-l")
    whole = course.picture()
    assert whole.shape[:2] == course.floor.shape
    small = course.picture(100_000)
    step = 4  # ceil(sqrt(1365 * 910 / 100_000))
    assert small.shape[0] * small.shape[1] <= 100_000
    assert (small == whole[::step, ::step]).mean() > 0.99  # the colour areas' edges land on the nearest pixel
