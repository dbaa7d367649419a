"""Valid float32 gains whose products overflow (Kp = 3e38): the Python tracer rounds to ±inf as C float
arithmetic does, and gives the C tracer's result instead of crashing with OverflowError."""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from athrill_sim.apps.line_trace import INT_MIN, c_int, f32
from tests.helpers.commands import hako
from tests.helpers.native_fixtures import need_cc


@given(st.floats(allow_nan=False))
def test_f32_rounds_like_a_c_float_assignment(x: float):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # numpy warns on the overflow C does silently
        assert f32(x) == float(np.float32(x))


def test_c_int_is_x86_64s_conversion():
    assert [c_int(v) for v in (2.9, -2.9, math.nan, math.inf, -math.inf, 3e9, -3e9)] == \
        [2, -2, INT_MIN, INT_MIN, INT_MIN, INT_MIN, INT_MIN]


def test_overflowing_gains_give_the_c_tracers_result():
    need_cc()
    args = ("try", "--kp", "3e38", "--kd", "-3e38", "--noise", "0", "--time-limit", "5", "--json")
    python, native = hako(*args, "--app", "line_trace"), hako(*args, "--app", "line_trace_c")
    assert python.returncode == 0 and native.returncode == 0, python.stderr + native.stderr
    assert json.loads(python.stdout) == json.loads(native.stdout)
    assert json.loads(python.stdout)["event"] == "TIME_OVER"
