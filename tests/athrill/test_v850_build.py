"""`hako build`: v850 EV3RT images from app.c or a workspace folder, their cache, and the one-line errors for
what is missing or broken; and the checks on an image before any test is charged to it."""

import os
import shutil
import sys
from pathlib import Path

import pytest

from athrill_sim.programs.third_party import EV3RT_SAMPLE_IMAGE
from athrill_sim.v850 import ImageError, build
from athrill_sim.v850.build import app_files, build_image, cache_key, first_error, staged_sources, user_paths
from athrill_sim.v850.elf import check_image
from athrill_sim.v850.toolchain import Tools, unpack_toolchain
from tests.helpers.athrill_fixtures import ASP_IMAGE
from tests.helpers.commands import hako, one_line_error
from tests.helpers.paths import needs_shared
from tests.helpers.realemu_fixtures import BASE_PRACTICE, need_v850_tools


def fake_tools(tmp_path: Path) -> Tools:
    sdk = tmp_path / "sdk"
    (sdk / "sdk" / "workspace").mkdir(parents=True)
    (sdk / "sdk" / "common" / "x.c").parent.mkdir(parents=True)
    (sdk / "sdk" / "common" / "x.c").write_text("int x;\n")
    apl = tmp_path / "athrill" / "apl"
    apl.mkdir(parents=True)
    return Tools(sdk, Path(shutil.which("true")), tmp_path / "athrill")


def workspace(folder: Path, source: str = "void main_task(intptr_t x) {}\n") -> Path:
    folder.mkdir(parents=True)
    for name, text in (("app.c", source), ("app.h", ""), ("app.cfg", ""), ("Makefile.inc", ""), ("log.txt", "x")):
        (folder / name).write_text(text)
    return folder


def key(folder: Path, tools: Tools) -> str:
    return cache_key(*app_files(folder), tools)


def test_the_cache_key_follows_the_sources_not_where_they_are_nor_other_files(tmp_path):
    tools = fake_tools(tmp_path)
    a, b = workspace(tmp_path / "a"), workspace(tmp_path / "elsewhere" / "b")
    assert key(a, tools) == key(b, tools)
    (b / "log.txt").write_text("a run's log is not a source")
    assert key(a, tools) == key(b, tools)
    (b / "app.c").write_text("void main_task(intptr_t x) { for (;;); }\n")
    assert key(a, tools) != key(b, tools)
    before = key(a, tools)
    (tools.sdk / "sdk" / "common" / "x.c").write_text("int y;\n")
    assert key(a, tools) != before


def test_a_lone_c_file_takes_the_headers_beside_it(tmp_path):
    (tmp_path / "tracer.c").write_text("#include \"gains.h\"\n")
    (tmp_path / "gains.h").write_text("")
    root, files, lone = app_files(tmp_path / "tracer.c")
    assert lone and root == tmp_path and [f.name for f in files] == ["tracer.c", "gains.h"]


def test_the_first_error_is_the_compilers_not_makes():
    out = ("  CC      app.c\napp.c:3:5: error: 'foo' undeclared (first use in this function)\n"
           "app.c:4:1: error: expected ';' before '}' token\n"
           "make[1]: *** [Makefile:420: app.o] Error 1\nmake: *** [Makefile:12: img] Error 2\n")
    assert first_error(out) == "app.c:3:5: error: 'foo' undeclared (first use in this function)"


# what the SDK's link printed for an app.c without main_task (v850-elf gcc 12.2, ../shared's toolchain)
NO_MAIN_TASK = ("/root/.cache/hakoniwa-py/toolchain/57bad064d14e66e4/v850-elf-gcc12/bin/../lib/gcc/v850-elf/12.2.0/"
                "../../../../v850-elf/bin/ld: ./kernel_cfg.o:(.rodata+0x288): undefined reference to `main_task'\n"
                "collect2: error: ld returned 1 exit status\nmake: *** [Makefile:385: asp] Error 1\n")


def test_a_missing_main_task_is_said_as_the_native_build_says_it():
    from athrill_sim.native.build import first_error as native_first_error

    native = native_first_error("app.o: undefined reference to `main_task'\n", entries=["main_task"])
    assert first_error(NO_MAIN_TASK) == native
    assert native.startswith("the program defines no function main_task, a task or handler function")
    assert first_error(NO_MAIN_TASK, cxx=True).endswith('in C++ it must be extern "C", as EV3RT\'s app.h declares it')
    other = "ld: app.o: in function `main_task':\napp.c:(.text+0x8): undefined reference to `helper'\n"
    assert "undefined reference to `helper'" in first_error(other)  # the program's own call: the linker's words


def test_a_compile_error_names_the_users_file_not_the_scratch_copy(tmp_path):
    (tmp_path / "tracer.c").write_text("")
    (tmp_path / "gains.h").write_text("")
    lone = staged_sources(*app_files(tmp_path / "tracer.c"))
    assert user_paths("../workspace/hako_app/app.c:2:38: error: expected expression", lone) == \
        f"{tmp_path / 'tracer.c'}:2:38: error: expected expression"
    assert user_paths("In file included from /scratch/x/sdk/workspace/hako_app/gains.h:1,", lone) == \
        f"In file included from {tmp_path / 'gains.h'}:1,"
    assert user_paths("../workspace/hako_app/app.cfg:7: error", lone) == "app.cfg:7: error"  # one we wrote
    folder = workspace(tmp_path / "ws")
    (folder / "src").mkdir()
    (folder / "src" / "pid.c").write_text("")
    assert user_paths("../workspace/hako_app/src/pid.c:1:1: error: x", staged_sources(*app_files(folder))) == \
        f"{folder / 'src' / 'pid.c'}:1:1: error: x"


def sdk_whose_make(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, rules: str) -> None:
    """`build_image` against a stand-in SDK whose workspace Makefile includes the program's Makefile.inc, as
    EV3RT's does, and then runs `rules`: what the bench stages for make is seen without the real SDK."""
    tools = fake_tools(tmp_path)
    (tools.sdk / "sdk" / "workspace" / "Makefile").write_text(f"include $(img)/Makefile.inc\n{rules}")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setattr(build, "find_tools", lambda *args, **kwargs: tools)
    monkeypatch.setattr(build, "check_build_tools", lambda: None)


def test_a_workspace_folder_without_makefile_inc_builds_with_an_empty_one(tmp_path, monkeypatch):
    sdk_whose_make(tmp_path, monkeypatch, "all:\n\tcp $(img)/Makefile.inc asp\n")
    folder = workspace(tmp_path / "app")
    (folder / "Makefile.inc").unlink()  # app.c, app.h and app.cfg only: `hako try` takes the same folder
    image = build_image(folder)
    assert image.read_text() == "" and not (folder / "Makefile.inc").exists()  # staged in the copy, not written here


def test_a_file_make_has_no_rule_for_is_one_sentence_not_makes_words(tmp_path, monkeypatch):
    sdk_whose_make(tmp_path, monkeypatch, "all: motor.o\n")
    with pytest.raises(ImageError) as info:
        build_image(workspace(tmp_path / "app"))
    message = str(info.value)
    assert message == (f"{tmp_path / 'app'} does not build: no file motor.o, which all needs, and the SDK's make "
                       "has no rule to make it")
    assert "\n" not in message and "***" not in message


def test_an_elf_for_another_cpu_is_named(tmp_path):
    with pytest.raises(ImageError, match="ELF for .+, not a v850 image"):
        check_image(Path(sys.executable).resolve())


def test_a_truncated_image_is_refused_before_athrill2_sees_it(tmp_path):
    if not ASP_IMAGE.is_file():
        pytest.skip(needs_shared("the real EV3RT image", ASP_IMAGE, EV3RT_SAMPLE_IMAGE))
    check_image(ASP_IMAGE)
    cut = tmp_path / "asp"
    cut.write_bytes(ASP_IMAGE.read_bytes()[:100_000])
    with pytest.raises(ImageError, match="truncated"):
        check_image(cut)
    r = hako("try", "--app", str(cut), "--json", timeout=120)
    one_line_error(r, "truncated")


def test_another_cpus_elf_as_app_is_one_line():
    one_line_error(hako("try", "--app", "/bin/ls", "--json", timeout=120), "ELF for", "not a v850 image")


def test_no_sdk_is_one_line_naming_it(tmp_path):
    workspace(tmp_path / "app")
    one_line_error(hako("build", str(tmp_path / "app"), "--sdk", str(tmp_path)), "no EV3RT SDK", "--sdk")


def test_no_toolchain_is_one_line_naming_it(tmp_path):
    need_v850_tools()
    workspace(tmp_path / "app")
    one_line_error(hako("build", str(tmp_path / "app"), "--toolchain", str(tmp_path)), "v850-elf-gcc")


def test_a_toolchain_tarball_that_is_no_tarball_is_one_line(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    bad = tmp_path / "v850-elf-gcc.tar.xz"
    bad.write_bytes(b"a download that stopped at an error page\n")
    with pytest.raises(ImageError) as info:
        unpack_toolchain(bad)
    assert str(info.value) == f"the toolchain {bad} is not a tar archive (plain, gz, bz2 or xz)"


def test_no_ruby_is_one_line_naming_it(tmp_path):
    need_v850_tools()
    workspace(tmp_path / "app", "/* not built before: no cached image */\n")
    bin_dir = tmp_path / "bin"  # make and the toolchain, no ruby
    bin_dir.mkdir()
    (bin_dir / "make").symlink_to(shutil.which("make"))
    r = hako("build", str(tmp_path / "app"), env={"PATH": str(bin_dir), "HOME": str(Path.home())})
    one_line_error(r, "Ruby", "apt-get install ruby")


@pytest.mark.slow
def test_a_compile_error_is_one_line_with_the_compilers_message(tmp_path):
    need_v850_tools()
    (tmp_path / "broken").mkdir()  # app.c alone: app.cfg and app.h are written for it
    (tmp_path / "broken" / "app.c").write_text('#include "ev3api.h"\n'
                                               'void main_task(intptr_t x) { undeclared_thing = 1; }\n')
    r = hako("build", str(tmp_path / "broken"), timeout=900)
    one_line_error(r, "does not build", f"{tmp_path / 'broken' / 'app.c'}:2:", "error:", "undeclared_thing")
    assert "workspace" not in r.stderr  # the user's file, not the scratch copy's


@pytest.mark.slow
def test_a_v850_program_without_main_task_is_told_so_in_a_sentence(tmp_path):
    need_v850_tools()
    (tmp_path / "app.c").write_text('#include "ev3api.h"\nvoid other_task(intptr_t x) { }\n')
    r = hako("build", str(tmp_path / "app.c"), timeout=900)
    one_line_error(r, "does not build: the program defines no function main_task, a task or handler function")


@pytest.mark.slow
def test_base_practice_builds_into_a_v850_image_cached_and_leaves_the_sdk_alone(tmp_path):
    need_v850_tools()
    sdk_files = sorted(p.relative_to(BASE_PRACTICE.parents[2]) for p in BASE_PRACTICE.parents[2].rglob("*"))
    env = {"XDG_CACHE_HOME": str(tmp_path / "cache")}  # a fresh cache: a real build, as on a fresh clone

    first = hako("build", str(BASE_PRACTICE), timeout=900, env={**os.environ, **env})
    assert first.returncode == 0, first.stderr
    image = Path(first.stdout.strip())
    check_image(image)
    built = image.stat().st_mtime_ns
    again = hako("build", str(BASE_PRACTICE), timeout=900, env={**os.environ, **env})
    assert again.returncode == 0 and again.stdout == first.stdout and image.stat().st_mtime_ns == built
    assert sorted(p.relative_to(BASE_PRACTICE.parents[2]) for p in BASE_PRACTICE.parents[2].rglob("*")) == sdk_files
