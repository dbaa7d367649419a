"""The test file: what a case may say, and the one-line error for what it may not."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hakoniwa.wire.protocol import Rx
from testctl.bench_options import BenchOptions
from testctl.search.space import ParameterSpace
from testctl.suite.cases import DEFAULT_SEEDS, SuiteError, drawn_seeds, load_suite
from testctl.suite.expect import Bound, EventExpectation

GAINS = "params = { Kp = 1.5, Ki = 4.0, Kd = 4.5 }\n"


def suite(tmp_path: Path, text: str, base: BenchOptions = BenchOptions()):
    path = tmp_path / "hako-tests.toml"
    path.write_text(text)
    return load_suite(path, base)


def test_a_case_with_defaults_and_its_own_keys(tmp_path):
    (case,) = suite(tmp_path, '[defaults]\nseeds = 3\nnoise = 0.5\n[case.fast]\napp = "line_trace_c"\n'
                    'time_limit_s = 30\n' + GAINS + 'expect = ["GOAL", "p90 < 42", "not HIT_WALL"]\n')
    assert case.name == "fast"
    assert case.bench == BenchOptions(app="line_trace_c", time_limit_s=30.0)
    assert case.params == {Rx.KP: 1.5, Rx.KI: 4.0, Rx.KD: 4.5, Rx.MOTOR_POWER: 15.0}
    assert case.seeds == drawn_seeds(3) and len(set(case.seeds)) == 3
    assert case.noise == 0.5
    assert case.expect == (EventExpectation("GOAL"), Bound("p90", "<", 42.0), EventExpectation("HIT_WALL", True))


def test_the_command_lines_bench_is_the_base_and_a_case_key_wins(tmp_path):
    base = BenchOptions(app="line_trace_c", athrill_timeout_s=3.0)
    a, b = suite(tmp_path, f'[case.a]\n{GAINS}expect = ["GOAL"]\n[case.b]\napp = "line_trace"\n{GAINS}'
                 'expect = ["GOAL"]\n', base)
    assert a.bench == base and b.bench == BenchOptions(app="line_trace", athrill_timeout_s=3.0)
    assert a.seeds == drawn_seeds(DEFAULT_SEEDS) and a.noise == 1.0


def test_paths_are_the_test_files_folders(tmp_path):
    (tmp_path / "app.c").write_text("")
    (case,) = suite(tmp_path, f'[case.c]\napp = "app.c"\nseeds = [0, 7]\n{GAINS}expect = ["GOAL"]\n')
    assert case.bench.app == str(tmp_path / "app.c") and case.seeds == (0, 7)


def test_a_case_from_a_campaign_takes_its_best_set_by_its_spaces_names(tmp_path):
    from testctl.campaign.journal import JOURNAL_FILE, Journal

    campaign = tmp_path / "runs" / "x"
    campaign.mkdir(parents=True)
    Journal.create(campaign / JOURNAL_FILE, {"space": ParameterSpace.default().to_dict(), "options": {}}).close()
    (campaign / "best.json").write_text(json.dumps({"success": True, "params": {"Kp": 1.0, "Ki": 2.0, "Kd": 3.0},
                                                    "fixed": {"motor_power": 15.0}}))
    (case,) = suite(tmp_path, '[case.best]\nfrom = "runs/x"\nparams = { motor_power = 20 }\nexpect = ["GOAL"]\n')
    assert case.named == {"Kp": 1.0, "Ki": 2.0, "Kd": 3.0, "motor_power": 20.0}
    assert case.params == {Rx.KP: 1.0, Rx.KI: 2.0, Rx.KD: 3.0, Rx.MOTOR_POWER: 20.0}


@pytest.mark.parametrize("text, words", [
    (f'[case.a]\nspeed = 3\n{GAINS}expect = ["GOAL"]\n', ["case 'a'", "unknown key(s) speed", "known:"]),
    (f'[case.a]\n{GAINS}', ["case 'a'", "no expectations"]),
    (f'[case.a]\n{GAINS}expect = []\n', ["no expectations"]),
    (f'[case.a]\n{GAINS}expect = ["speed < 3"]\n', ["case 'a'", "no value 'speed'"]),
    (f'[case.a]\nseeds = 0\n{GAINS}expect = ["GOAL"]\n', ["seeds", "at least 1, got 0"]),
    (f'[case.a]\nseeds = []\n{GAINS}expect = ["GOAL"]\n', ["seeds", "non-empty list"]),
    (f'[case.a]\nseeds = [-1]\n{GAINS}expect = ["GOAL"]\n', ["seeds", "0..4294967295"]),
    (f'[case.a]\nseeds = true\n{GAINS}expect = ["GOAL"]\n', ["seeds"]),
    ('[case.a]\nfrom = "runs/none"\nexpect = ["GOAL"]\n', ["from", "best.json does not exist"]),
    ('[case.a]\nparams = { Kp = 1.0 }\nexpect = ["GOAL"]\n', ["no value for Ki, Kd"]),
    ('[case.a]\nparams = { Kq = 1.0 }\nexpect = ["GOAL"]\n', ["no parameter 'Kq'"]),
    ('[case.a]\nparams = { Kp = "x", Ki = 1, Kd = 1 }\nexpect = ["GOAL"]\n', ["Kp = 'x' is not a number"]),
    (f'[case.a]\ntime_limit_s = 0\n{GAINS}expect = ["GOAL"]\n', ["time_limit_s", "outside"]),
    (f'[case.a]\nnoise = 1000\n{GAINS}expect = ["GOAL"]\n', ["noise", "outside"]),
    (f'[case.a]\nathrill2 = "/x"\n{GAINS}expect = ["GOAL"]\n', ["unknown key(s) athrill2"]),
    (f'[case.a_b]\n{GAINS}expect = ["GOAL"]\n[case."a b"]\n{GAINS}expect = ["GOAL"]\n', ["share the folder"]),
    ('[cases.a]\n', ["unknown top-level key(s) cases"]),
    ('[defaults]\nseeds = 3\n', ["no cases"]),
    ('case = 3\n', ["[case] must be a table"]),
    ('this = = not toml', ["not valid TOML"]),
])
def test_bad_input_is_one_line_naming_the_problem(tmp_path, text, words):
    with pytest.raises(SuiteError) as e:
        suite(tmp_path, text)
    assert "\n" not in str(e.value) and str(tmp_path / "hako-tests.toml") in str(e.value)
    for w in words:
        assert w in str(e.value)


KEYS = st.sampled_from(["app", "course", "time_limit_s", "params", "from", "space", "seeds", "noise", "expect",
                        "speed", "seed", "robot"])
VALUES = st.one_of(st.integers(-3, 3), st.floats(allow_nan=True), st.text(max_size=8), st.booleans(),
                   st.lists(st.integers(-1, 3), max_size=3), st.just(["GOAL"]), st.just(["lap_s < x"]))


def toml_value(v) -> str:
    return json.dumps(v) if not isinstance(v, float) or v == v and abs(v) != float("inf") else "nan"


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture], max_examples=60, deadline=None)
@given(st.dictionaries(KEYS, VALUES, max_size=5))
def test_any_case_is_loaded_or_refused_in_one_line(tmp_path, keys):
    body = "".join(f"{k} = {toml_value(v)}\n" for k, v in keys.items() if k != "params")
    try:
        cases = suite(tmp_path, f"[case.a]\n{GAINS if 'params' in keys else ''}{body}")
    except SuiteError as e:
        assert "\n" not in str(e)
    else:
        assert cases[0].expect and cases[0].seeds
