"""Parameters that reach a program as it is written (define, symbol, file, source): the space file's kinds
and slots, the value texts, best.patch, and every bad input as one line before any test."""

from __future__ import annotations

import math
import shutil
import struct
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from athrill_sim.tuning.bindings import from_json
from athrill_sim.tuning.forms.define import Define
from athrill_sim.tuning.forms.file import fill_template, template_fields
from athrill_sim.tuning.forms.form import Binding, BindingError, Edit
from athrill_sim.tuning.forms.symbol import Symbol
from athrill_sim.tuning.forms.values import as_float32, value_text
from athrill_sim.tuning.tune import apply_edits
from hakoniwa.wire.params import PARAM_END, slot_size
from hakoniwa.wire.protocol import open_athrill, open_unity
from testctl.campaign.patch import unified_diff
from testctl.runner import TestRunner
from testctl.search.space import ParameterSpace, SpaceError
from tests.helpers.commands import hako, one_line_error
from tests.helpers.native_fixtures import need_cc
from tests.helpers.paths import PROGRAMS

KINDS = ("define", "symbol", "file", "source")


def space(text: str) -> ParameterSpace:
    import tomllib

    return ParameterSpace.from_dict(tomllib.loads(text))


# -- the space file -----------------------------------------------------------------------------------

@pytest.mark.parametrize("kind", KINDS)
def test_each_tracer_space_loads_round_trips_and_binds_every_parameter(kind: str) -> None:
    s = ParameterSpace.load(PROGRAMS / f"{kind}.toml")
    assert s.names == ("Kp", "Ki", "Kd") and [p.kind for p in s.every] == [kind] * 4
    assert ParameterSpace.from_dict(s.to_dict()) == s
    bindings = from_json(s.bindings())
    assert [b.name for b in bindings] == ["Kp", "Ki", "Kd", "motor_power"]
    assert [b.slot for b in bindings] == [PARAM_END - 8 * i for i in range(1, 5)]
    assert s.slot_types == {b.slot: "f64" for b in bindings}
    assert s.to_offsets([1.0, 2.0, 3.0]) == {bindings[0].slot: 1.0, bindings[1].slot: 2.0, bindings[2].slot: 3.0,
                                             bindings[3].slot: 15.0}


def test_an_all_offset_space_needs_no_bindings() -> None:
    assert ParameterSpace.default().bindings() is None and ParameterSpace.default().slot_types == {}


OFFSETS = st.sets(st.integers(135, 254), max_size=6).map(lambda s: sorted(4 * o for o in s))


@settings(max_examples=60, deadline=None)
@given(offsets=OFFSETS, others=st.integers(1, 6), f64=st.sets(st.integers(0, 5)))
def test_slots_are_disjoint_inside_the_area_and_a_function_of_the_space(offsets, others, f64) -> None:
    entries = [f'[[param]]\nname = "o{i}"\noffset = {o}\nlow = 0\nhigh = 1\n'
               + ('type = "f64"\n' if i in f64 else "") for i, o in enumerate(offsets)]
    entries += [f'[[param]]\nname = "d{i}"\ndefine = "D{i}"\nlow = 0\nhigh = 1\n' for i in range(others)]
    try:
        s = space("\n".join(entries))
    except SpaceError as e:  # two f64 offsets 4 apart overlap: refused, naming both
        assert "overlap" in str(e)
        return
    spans = sorted((s.slots[p.name], s.slots[p.name] + slot_size(p.storage)) for p in s.every)
    assert all(a_end <= b for (_, a_end), (b, _) in zip(spans, spans[1:]))
    assert spans[0][0] >= 540 and spans[-1][1] <= PARAM_END and all(start % 4 == 0 for start, _ in spans)
    assert space("\n".join(entries)).slots == s.slots


def test_integer_parameters_are_rounded_as_used_and_recorded() -> None:
    s = space('[[param]]\nname = "n"\nsymbol = "g_n"\ntype = "int"\nlow = -3\nhigh = 7\n'
              '[[param]]\nname = "x"\noffset = 540\nlow = 0\nhigh = 1\n'
              '[[param]]\nname = "k"\noffset = 544\ntype = "int"\nlow = 0\nhigh = 9\n')
    assert s.snap((2.5, 0.25, 3.6)) == (2.0, 0.25, 4.0)
    assert s.to_named((4.4, 0.5, 1.2)) == {"n": 4.0, "x": 0.5, "k": 1.0}
    assert s.slot_types == {s.slots["n"]: "f64", 544: "i32"}


@pytest.mark.parametrize("text, problem", [
    ('define = "KP"\noffset = 540', "offset and define: a parameter reaches the program one way"),
    ('source = { file = "a.h" }', "source must be { file ="),
    ('symbol = ""', "symbol must be a non-empty string"),
    ('define = "KP"\ntemplate = "x"', "template belongs to a file parameter"),
    ('define = "KP"\ntype = "int8"', "type 'int8' is none of"),
    ('define = "KP"\ntype = "int"\nlow = 0.5', "low 0.5 is not an integer of i32"),
    ('symbol = "g"\ntype = "u8"\nhigh = 300', "high 300.0 is not an integer of u8"),
    ('offset = 1020\ntype = "f64"', "an f64 at offset 1020 runs past the parameter area's end"),
    ('definee = "KP"', "unknown key(s): definee"),
])
def test_a_bad_parameter_is_one_line(text: str, problem: str) -> None:
    base = {"low": "low = 0\n", "high": "high = 5\n"}
    body = text + "\n" + "".join(v for k, v in base.items() if f"{k} =" not in text)
    with pytest.raises(SpaceError, match=None) as info:
        space(f'[[param]]\nname = "Kp"\n{body}')
    assert problem in str(info.value) and "\n" not in str(info.value)


@pytest.mark.parametrize("a, b", [('define = "KP"', 'define = "KP"'), ('symbol = "g"', 'symbol = "g"'),
                                  ('source = { file = "p.h", match = "K = (.*);" }',
                                   'source = { file = "p.h", match = "K = (.*);" }')])
def test_two_parameters_on_one_target_are_one_line(a: str, b: str) -> None:
    with pytest.raises(SpaceError, match="'Kp' and 'Ki' are two parameters on one target"):
        space(f'[[param]]\nname = "Kp"\n{a}\nlow = 0\nhigh = 1\n[[param]]\nname = "Ki"\n{b}\nlow = 0\nhigh = 1\n')


def test_a_journal_whose_slots_another_version_allocated_is_refused() -> None:
    s = ParameterSpace.load(PROGRAMS / "define.toml")
    data = s.to_dict()
    data["param"][0]["slot"] = 540
    with pytest.raises(SpaceError, match="recorded in slot 540"):
        ParameterSpace.from_dict(data)


def test_the_slots_go_through_the_wire_with_their_types(tmp_path: Path) -> None:
    s = space('[[param]]\nname = "d"\ndefine = "D"\nlow = 0\nhigh = 1\n'
              '[[param]]\nname = "k"\noffset = 544\ntype = "int"\nlow = -9\nhigh = 9\n'
              '[[param]]\nname = "w"\noffset = 548\ntype = "f64"\nlow = 0\nhigh = 1\n')
    open_unity(tmp_path, create=True).close()
    open_athrill(tmp_path, create=True).close()
    runner = TestRunner(tmp_path)
    x = (0.1, -3.0, 0.3)
    runner.write_params(s.to_offsets(x), s.slot_types)
    u = runner.unity
    assert (u.read("d", s.slots["d"]), u.read("i", 544), u.read("d", 548)) == x
    runner.close()


# -- values as C reads them ---------------------------------------------------------------------------

FLOAT32 = st.integers(0, 2**32 - 1).map(lambda b: struct.unpack("<f", struct.pack("<I", b))[0]).filter(
    math.isfinite)


@settings(max_examples=400, deadline=None)
@given(f=FLOAT32)
@example(f=2.524354896707238e-29)  # a power of two: the gap below is half the gap above
def test_a_float32_text_reads_back_exactly_as_a_double_literal_and_as_strtof(f: float) -> None:
    text = value_text(f, "f32")
    assert as_float32(float(text)) == f or (f == 0 and float(text) == 0)
    x, here = Fraction(text), Fraction(f)
    bits = struct.unpack("<I", struct.pack("<f", f))[0]
    for b in (bits - 1, bits + 1):  # nearer to f than to the neighbour on its side: strtof gives f
        if 0 <= b < 2**32 and math.isfinite(n := struct.unpack("<f", struct.pack("<I", b))[0]) \
                and (Fraction(n) - here) * (x - here) > 0:
            assert abs(x - here) <= abs(Fraction(n) - here) / 2
    assert any(c in text for c in ".en"), text  # a floating literal: KP / 2 stays a float division


@settings(max_examples=200, deadline=None)
@given(v=st.floats(allow_nan=False, allow_infinity=False))
def test_a_double_text_reads_back_exactly(v: float) -> None:
    assert float(value_text(v, "f64")) == v
    assert value_text(round(v) if abs(v) < 1e15 else 3, "i32") == str(int(round(v) if abs(v) < 1e15 else 3))


def test_templates_name_their_placeholders_and_refuse_format_specs() -> None:
    assert template_fields("a,{Kp}\n{{x}},{Ki}") == ["Kp", "Ki"]
    assert fill_template("a,{Kp}\n{{x}}", {"Kp": "1.5"}) == "a,1.5\n{x}"
    for bad in ("{Kp:.3f}", "{0}", "{Kp!r}", "{"):
        with pytest.raises(BindingError):
            template_fields(bad)


def test_bindings_that_are_not_bindings_are_one_line() -> None:
    for text in ("{", '[{"name": "a"}]', '[{"name": "a", "kind": "offsetx", "target": "t", "slot": 1000, '
                                          '"low": 0, "high": 1}]'):
        with pytest.raises(BindingError, match="--bindings"):
            from_json(text)
    b = Binding("a", Define("A"), 1016, 0, 1)
    assert b.text_type == "f32" and Binding("n", Symbol("g"), 1016, 0, 1, "int").integer


# -- best.patch -----------------------------------------------------------------------------------------

def git_apply(folder: Path, patch: str) -> subprocess.CompletedProcess:
    (folder.parent / "p.patch").write_text(patch)
    return subprocess.run(["git", "apply", str(folder.parent / "p.patch")], cwd=folder, capture_output=True,
                          text=True)


LINES = st.lists(st.text(st.characters(codec="ascii", exclude_characters="\r\n\x00"), max_size=12), max_size=12)


@settings(max_examples=40, deadline=None)
@given(old=LINES, new=LINES, old_nl=st.booleans(), new_nl=st.booleans())
def test_a_diff_applies_with_git_apply_and_gives_the_new_text(tmp_path_factory, old, new, old_nl, new_nl) -> None:
    if shutil.which("git") is None:
        pytest.skip("needs git")
    folder = tmp_path_factory.mktemp("app") / "app"
    folder.mkdir()
    before = "\n".join(old) + ("\n" if old_nl and old else "")
    after = "\n".join(new) + ("\n" if new_nl and new else "")
    (folder / "gains.h").write_text(before)
    diff = unified_diff(before, after, "gains.h")
    if diff:
        r = git_apply(folder, diff)
        assert r.returncode == 0, r.stderr + diff
    assert (folder / "gains.h").read_text() == after


def test_a_new_data_file_is_a_new_file_in_the_diff(tmp_path: Path) -> None:
    if shutil.which("git") is None:
        pytest.skip("needs git")
    (tmp_path / "app").mkdir()
    r = git_apply(tmp_path / "app", unified_diff(None, "kp\n1.5\n", "sdcard/gains.csv"))
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "app" / "sdcard" / "gains.csv").read_text() == "kp\n1.5\n"


def test_edits_apply_by_their_spans() -> None:
    text = "#define KP 1.0f\n#define KI 0.5f\n"
    assert apply_edits(text, [(11, 15, "2.5f"), (27, 31, "0.25f")]) == "#define KP 2.5f\n#define KI 0.25f\n"
    assert Edit(Path("a"), 0, 1, "x", "w").what == "w"


# -- bad input: one line, a non-zero exit, before any test ---------------------------------------------

def tracers(tmp_path: Path) -> Path:
    folder = tmp_path / "programs"
    shutil.copytree(PROGRAMS, folder)
    return folder


def run(folder: Path, app: str, kind: str, edits: list[tuple[str, str]], file: str | None):
    """`hako run` on a copy of a tracer and its space, with `edits` made to the space or to the program's
    `file`."""
    target = folder / app / file if file is not None else folder / f"{kind}.toml"
    text = target.read_text()
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new)
    target.write_text(text)
    return hako("run", "--app", str(folder / app), "--space", str(folder / f"{kind}.toml"), "--smoke", "--noise",
                "0", "--validate", "0", "--out", str(folder / "out"), timeout=300)


BAD = {
    "missing symbol": ("tracer_symbol", "symbol", [('"g_kp"', '"g_nope"')], None,
                       ["symbol g_nope", "no global variable"]),
    "const symbol": ("tracer_symbol", "symbol", [("float g_kp = 1.0f;", "const float g_kp = 1.0f;")], "app.c",
                     ["symbol g_kp", "make it a non-const global"]),
    "uninitialized symbol": ("tracer_symbol", "symbol", [("float g_kp = 1.0f;", "float g_kp;")], "app.c",
                             ["symbol g_kp", "give it an initializer"]),
    "unread symbol": ("tracer_symbol", "symbol", [("trace(g_kp,", "trace(1.0f,")], "app.c",
                      ["symbol g_kp", "nothing in the program reads it"]),
    "match twice": ("tracer_source", "source", [("KP_GAIN = (.*);", "_GAIN = (.*);")], None,
                    ["matches 3 times", "line 2", "line 4"]),
    "match never": ("tracer_source", "source", [("KP_GAIN = (.*);", "KP_NOPE = (.*);")], None, ["matches 0 times"]),
    "stray placeholder": ("tracer_file", "file", [("{motor_power}", "{power}")], None,
                          ["placeholder {power} is no parameter"]),
    "file outside": ("tracer_file", "file", [('file = "sdcard/gains.csv"\ntemplate', 'file = "../x.csv"\ntemplate')],
                     None, ["../x.csv is outside the program's folders"]),
    "two on one target": ("tracer_define", "define", [('define = "KI"', 'define = "KP"')], None,
                          ["'Kp' and 'Ki' are two parameters on one target"]),
    "define without effect": ("tracer_define", "define", [("#ifndef KD\n#define KD 0.5f\n#endif",
                                                           "#undef KD\n#define KD 0.5f")], "gains.h",
                              ["define KD has no effect", "KD=0.0", "KD=5.0"]),
}


@pytest.mark.parametrize("case", BAD)
def test_a_binding_the_program_cannot_take_is_one_line_before_any_test(tmp_path: Path, case: str) -> None:
    need_cc()
    app, kind, edits, file, words = BAD[case]
    folder = tracers(tmp_path)
    r = run(folder, app, kind, edits, file)
    one_line_error(r, *words)
    assert not (folder / "out").exists()  # no empty --out left behind, as if a campaign had run there


def test_a_refused_campaign_leaves_a_given_folder_that_was_there_as_it_was(tmp_path: Path) -> None:
    need_cc()
    folder = tracers(tmp_path)
    (folder / "out").mkdir()
    (folder / "out" / "notes.txt").write_text("mine\n")
    one_line_error(run(folder, *BAD["missing symbol"][:4]), "symbol g_nope")
    assert [p.name for p in (folder / "out").iterdir()] == ["notes.txt"]


def test_a_python_program_takes_only_offsets(tmp_path: Path) -> None:
    r = hako("run", "--app", "line_trace", "--space", str(PROGRAMS / "define.toml"), "--smoke", "--out",
             str(tmp_path / "out"))
    one_line_error(r, "a Python program reads its parameters at their offsets")


def test_resume_refuses_a_campaign_whose_data_file_changed(tmp_path: Path) -> None:
    """The journal's hash covers every file a kind reads or rewrites: here the data file's original."""
    need_cc()
    folder = tracers(tmp_path)
    out = folder / "out"
    r = hako("run", "--app", str(folder / "tracer_file"), "--space", str(folder / "file.toml"), "--smoke",
             "--noise", "0", "--validate", "0", "--out", str(out), timeout=300)
    assert r.returncode == 0, r.stderr
    (folder / "tracer_file" / "sdcard" / "gains.csv").write_text("kp,ki,kd,power\n2,0,0,15\n")
    one_line_error(hako("run", "--resume", str(out), "--trials", "3", timeout=300), "gains.csv changed")


def test_a_bench_that_was_not_told_the_bindings_refuses_them(tmp_path: Path) -> None:
    from tests.helpers.commands import run_module

    controller = [sys.executable, "-m", "testctl.cli", "campaign", "--space", str(PROGRAMS / "define.toml"), "--smoke",
                  "--out", str(tmp_path / "out")]
    r = run_module("testctl.physics_process", "--run-dir", str(tmp_path / "run"), "--", *controller, timeout=300)
    assert r.returncode != 0 and "run the campaign with hako run" in r.stderr, r.stderr
