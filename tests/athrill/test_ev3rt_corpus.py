"""EV3RT's own sample programs, unmodified, from a copy of their folders: each builds natively and runs one test
without CRASH, doing what `ev3rt_corpus.CORPUS` expects of it; and our headers declare all that EV3RT's do."""

import json
import re
import shutil

import pytest

from athrill_sim.native.build import RUNTIME_INCLUDE
from tests.helpers.commands import hako
from tests.helpers.ev3rt_corpus import CORPUS, EV3API, NEEDS_SHARED, SKIPPED, WORKSPACE
from tests.helpers.native_fixtures import need_cc


def test_every_sample_is_in_the_corpus_or_skipped_with_a_reason():
    if not WORKSPACE.is_dir():
        pytest.skip(NEEDS_SHARED)
    samples = {p.name for p in WORKSPACE.iterdir() if (p / "app.c").is_file()}
    assert samples == set(CORPUS) | set(SKIPPED)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(CORPUS))
def test_the_sample_runs_unmodified(name, tmp_path):
    if not WORKSPACE.is_dir():
        pytest.skip(NEEDS_SHARED)
    need_cc()
    expect = CORPUS[name]
    app = shutil.copytree(WORKSPACE / name, tmp_path / name)
    args = ["try", "--app", str(app), "--json", "--run-dir", str(tmp_path / "run"),
            "--time-limit", str(expect.time_limit_s)]
    if expect.scenario is not None:
        (tmp_path / "scenario.toml").write_text(expect.scenario)
        args += ["--scenario", str(tmp_path / "scenario.toml")]
    out = hako(*args)
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout)
    log = (tmp_path / "run" / "athrill.log").read_text()
    assert result["event"] != "CRASH", log[-2000:]
    assert result["distance_m"] >= expect.min_distance_m
    for line in expect.log:
        assert line in log
    if expect.lcd:
        assert (tmp_path / "run" / "lcd.txt").read_text().strip() and (tmp_path / "run" / "lcd.png").is_file()
    if expect.serial_out is not None:
        assert (tmp_path / "run" / f"serial-{expect.serial_out}.log").read_text()


_DECLARATION = re.compile(r"^\s*(?:extern\s+)?([A-Za-z_][\w\s\*]*?[\s\*])(\w+)\s*\(([^;{]*)\)\s*;", re.M)


def declarations(text: str) -> dict[str, str]:
    """{function: normalized signature} of the live declarations (`#if 0` blocks left out)."""
    text = re.sub(r"/\*.*?\*/|//[^\n]*", "", text, flags=re.S)
    text = re.sub(r"^#if 0\b.*?^#endif", "", text, flags=re.S | re.M)
    found = {}
    for ret, name, params in _DECLARATION.findall(text):
        params = " ".join(params.split()) or "void"
        signature = f"{' '.join(ret.split())} {name}({params})"
        found[name] = re.sub(r"\s*\*\s*", "*", signature)
    return found


def test_our_headers_declare_every_function_ev3rt_declares_with_its_signature():
    if not EV3API.is_dir():
        pytest.skip(NEEDS_SHARED)
    theirs = {}
    for header in sorted((EV3API / "src").glob("ev3api_*.h")):
        theirs.update(declarations(header.read_text()))
    ours = declarations((RUNTIME_INCLUDE / "ev3api.h").read_text())
    assert len(theirs) >= 50
    assert {n: s for n, s in theirs.items() if ours.get(n) != s} == {}
