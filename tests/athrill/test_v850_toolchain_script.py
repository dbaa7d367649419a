"""scripts/build_v850_toolchain.sh: its options, its one-line refusals, and its gcc configuration, which must be
the one of the toolchain ../shared ships (the compiler EV3RT's images were checked with). A full build takes
about 35 minutes and is not run here."""

import shlex
import subprocess
from pathlib import Path

import pytest

from athrill_sim.programs.third_party import EV3RT_SDK, RASPIKE_SDK
from athrill_sim.v850 import ImageError
from athrill_sim.v850.toolchain import find_sdk, find_toolchain
from tests.helpers.paths import SCRIPTS, needs_shared

SCRIPT = SCRIPTS / "build_v850_toolchain.sh"


def script(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(SCRIPT), *args], capture_output=True, text=True, timeout=60)


def test_help_names_every_option():
    r = script("--help")
    assert r.returncode == 0 and r.stdout.startswith("Usage: ")
    for option in ("--sources", "--install-deps", "--work", "--jobs", "--c-only", "--print-configure", "PREFIX"):
        assert option in r.stdout


@pytest.mark.parametrize("args, words", [
    ((), "give the PREFIX to install into"),
    (("--jobs", "0", "/tmp/p"), "--jobs needs a whole number"),
    (("--frobnicate", "/tmp/p"), "unknown option --frobnicate"),
    (("/tmp/a", "/tmp/b"), "one PREFIX only"),
    (("--sources",), "--sources needs a folder"),
])
def test_bad_arguments_are_one_line(args, words):
    r = script(*args)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and r.stderr.startswith("Error: ") and words in r.stderr


def test_missing_sources_say_where_they_come_from(tmp_path):
    r = script("--sources", str(tmp_path), str(tmp_path / "prefix"))
    assert r.returncode == 2 and r.stderr.count("\n") == 1
    assert "no binutils source tarball (binutils-2.40.tar.*)" in r.stderr
    assert "apt-get install binutils-source gcc-12-source newlib-source" in r.stderr
    assert not (tmp_path / "prefix").exists()


def configured_with(gcc: Path) -> list[str]:
    out = subprocess.run([str(gcc), "-v"], capture_output=True, text=True, timeout=60).stderr
    (line,) = [line for line in out.splitlines() if line.startswith("Configured with: ")]
    return shlex.split(line.removeprefix("Configured with: "))


def without_paths(words: list[str]) -> list[str]:
    """The options, less those that name where things were (the prefix, the assembler and linker in it)."""
    return [w for w in words[1:] if not w.startswith(("--prefix=", "--with-as=", "--with-ld="))]


def test_the_gcc_configuration_is_the_shipped_toolchains(tmp_path):
    try:
        shipped = find_toolchain(None, find_sdk(None))
    except ImageError as e:
        pytest.skip(f"no v850 toolchain to compare with: {e}")
    r = script("--print-configure", str(tmp_path / "prefix"))
    assert r.returncode == 0, r.stderr
    binutils, gcc = r.stdout.splitlines()
    assert binutils.startswith("../src/binutils-2.40/configure --target=v850-elf")
    ours = shlex.split(gcc)
    assert ours[0] == "../src/gcc-12.2.0/configure" and f"--prefix={tmp_path / 'prefix'}" in ours
    assert f"--with-as={tmp_path / 'prefix'}/bin/v850-elf-as" in ours
    assert without_paths(ours) == without_paths(configured_with(shipped))
    assert "gcc version 12.2.0" in subprocess.run([str(shipped), "-v"], capture_output=True, text=True).stderr


PATCHES = SCRIPT.parent / "ev3rt-patches"
SHARED = SCRIPT.parents[2] / "shared" / "third_party"


@pytest.mark.parametrize("sdk, patches", [
    ("ev3rt/ev3rt-athrill-v850e2m", ["01-ev3rt-gcc12-ruby3.diff", "02-ev3rt-cxx.diff"]),
    ("raspike/raspike-athrill-v850e2m", ["raspike-gcc12-ruby3.diff"]),
])
def test_the_shipped_sdk_patches_are_what_the_patched_sdk_holds(tmp_path, sdk, patches):
    """Undone in reverse order on a copy of ../shared's patched SDK, each applies exactly (no fuzz, no offset)."""
    import shutil

    if not (SHARED / sdk).is_dir():
        piece = EV3RT_SDK if sdk.startswith("ev3rt/") else RASPIKE_SDK
        pytest.skip(needs_shared("the patched SDK", SHARED / sdk, piece))
    copy = tmp_path / "sdk"
    shutil.copytree(SHARED / sdk, copy, symlinks=True, ignore=shutil.ignore_patterns("OBJ", "docker"))
    for patch in reversed(patches):
        r = subprocess.run(["patch", "-p1", "-R", "-F0", "-d", str(copy), "-i", str(PATCHES / patch)],
                           capture_output=True, text=True, timeout=60)
        assert r.returncode == 0 and "offset" not in r.stdout and "fuzz" not in r.stdout, r.stdout + r.stderr
