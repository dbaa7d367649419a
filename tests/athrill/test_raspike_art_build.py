"""`hako build --raspike-art`: a team's RasPike-ART workspace folder into RasPike-ART's aarch64 `asp`, by
RasPike-ART's own make, cached; and the one-line errors for what is missing."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from athrill_sim.programs.third_party import RASPIKE_ART
from athrill_sim.raspike_art import AspError
from athrill_sim.raspike_art.build import (
    ASP,
    DEFAULT_FOLDER,
    DEVICE_CONFIG,
    EXPECTED_VERSION,
    MARKS,
    SETJMP,
    Tools,
    app_files,
    build_asp,
    cache_key,
    find_raspike_art,
    find_tools,
)
from athrill_sim.v850 import ImageError
from tests.helpers.commands import hako, one_line_error
from tests.helpers.paths import needs_shared

SAMPLE = DEFAULT_FOLDER / "sdk" / "workspace" / "sample_c5_spike"  # RasPike-ART's own sample
ELF_MACHINE_AARCH64 = 183  # EM_AARCH64, the ELF header's e_machine


def need_raspike_art() -> Tools:
    """RasPike-ART and the cross toolchain, or a skip that says which is missing."""
    if not DEFAULT_FOLDER.is_dir():
        pytest.skip(needs_shared("RasPike-ART", DEFAULT_FOLDER, RASPIKE_ART))
    try:
        return find_tools(None)
    except AspError as e:
        pytest.skip(f"cannot build RasPike-ART's asp: {e}")


def workspace(folder: Path) -> Path:
    folder.mkdir(parents=True)
    for name, text in (("app.c", "void main_task(intptr_t x) {}\n"), ("app.h", ""), ("app.cfg", ""),
                       ("Makefile.inc", "USE_RASPIKE_ART=1\n"), ("log.txt", "x")):
        (folder / name).write_text(text)
    return folder


def fake_tools(tmp_path: Path) -> Tools:
    tree = tmp_path / "RasPike-ART"
    (tree / "sdk" / "workspace").mkdir(parents=True)
    (tree / "configure.rb").write_text("require 'optparse'\n")
    return Tools(tree, Path(str(shutil.which("true"))))


def test_the_cache_key_follows_the_sources_and_raspike_art_not_other_files(tmp_path):
    tools = fake_tools(tmp_path)
    a, b = workspace(tmp_path / "a"), workspace(tmp_path / "elsewhere" / "b")
    assert cache_key(*app_files(a), tools) == cache_key(*app_files(b), tools)
    (b / "log.txt").write_text("a run's log is not a source")
    assert cache_key(*app_files(a), tools) == cache_key(*app_files(b), tools)
    (b / "app.c").write_text("void main_task(intptr_t x) { for (;;); }\n")
    assert cache_key(*app_files(a), tools) != cache_key(*app_files(b), tools)
    before = cache_key(*app_files(a), tools)
    (tools.raspike_art / "configure.rb").write_text("require 'fileutils'\n")
    assert cache_key(*app_files(a), tools) != before


def test_a_folder_without_the_workspace_files_is_refused_in_one_line(tmp_path):
    (tmp_path / "app.c").write_text("")
    r = hako("build", "--raspike-art", str(tmp_path))
    one_line_error(r, str(tmp_path), "app.cfg", "Makefile.inc")


def test_without_raspike_art_the_error_says_where_it_comes_from(tmp_path):
    r = hako("build", "--raspike-art", "--sdk", str(tmp_path), str(workspace(tmp_path / "app")))
    one_line_error(r, "no RasPike-ART", "https://github.com/ETrobocon/RasPike-ART", RASPIKE_ART.commit)


def test_without_the_cross_compiler_the_error_says_what_to_install(tmp_path):
    if not DEFAULT_FOLDER.is_dir():
        pytest.skip(needs_shared("RasPike-ART", DEFAULT_FOLDER, RASPIKE_ART))
    bare = tmp_path / "bin"  # a PATH with nothing on it but this Python
    bare.mkdir()
    env = {**os.environ, "PATH": str(bare)}
    r = hako("build", "--raspike-art", str(workspace(tmp_path / "app")), env=env)
    one_line_error(r, "apt-get install gcc-aarch64-linux-gnu g++-aarch64-linux-gnu qemu-user")


def test_a_v850_toolchain_is_refused_with_raspike_art(tmp_path):
    r = hako("build", "--raspike-art", "--toolchain", str(tmp_path), str(workspace(tmp_path / "app")))
    one_line_error(r, "--toolchain", "aarch64")


@pytest.mark.slow
def test_raspike_arts_own_sample_builds_into_an_aarch64_asp_without_writing_its_sources(tmp_path):
    need_raspike_art()
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache")}
    r = hako("build", "--raspike-art", str(SAMPLE), env=env)
    assert r.returncode == 0, r.stderr
    asp = Path(r.stdout.strip())
    assert asp.name == ASP and asp.is_relative_to(tmp_path / "cache")
    header = asp.read_bytes()[:20]
    assert header[:4] == b"\x7fELF" and int.from_bytes(header[18:20], "little") == ELF_MACHINE_AARCH64
    assert (asp.parent / SETJMP.name).is_file() and (asp.parent / DEVICE_CONFIG.name).is_file()
    assert not (SAMPLE.parents[1] / "workspace" / ASP).exists()  # RasPike-ART's own make leaves it there
    assert not (DEFAULT_FOLDER / "libraspike-art" / "lib" / "libraspike-art.a").exists()
    again = hako("build", "--raspike-art", str(SAMPLE), env=env)  # cached: the same product, no second build
    assert again.returncode == 0 and again.stdout == r.stdout


@pytest.mark.slow
def test_a_compile_error_names_the_teams_own_file(tmp_path, monkeypatch):
    need_raspike_art()
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    app = workspace(tmp_path / "team")
    (app / "app.c").write_text("#include <stdint.h>\nvoid main_task(intptr_t x) { undeclared_thing = 1; }\n")
    with pytest.raises(ImageError, match=str(app / "app.c")):
        build_asp(app)


def test_a_raspike_art_that_expects_another_hub_is_refused_in_one_line(tmp_path):
    """Its asp would print "SPIKE version mismatched" and stop at every test's handshake: said before a build."""
    tree = tmp_path / "RasPike-ART"
    for mark in MARKS:
        (tree / mark).parent.mkdir(parents=True, exist_ok=True)
        (tree / mark).write_text("")
    (tree / EXPECTED_VERSION).parent.mkdir(parents=True)
    (tree / EXPECTED_VERSION).write_text("0.1.0\n")
    r = hako("build", "--raspike-art", "--sdk", str(tree), str(workspace(tmp_path / "app")))
    one_line_error(r, "expects the hub's protocol 0.1.0", "speaks 0.0.6")
    (tree / EXPECTED_VERSION).write_text("0.0.6\n")
    assert find_raspike_art(tree) == tree.resolve()
