"""A test's result as the physics process sends it (`TestResult.encode`) and the controller reads it back
(`decode`): every field survives, and what is not a result is refused, never taken for one."""

from __future__ import annotations

import json

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hakoniwa.wire.etrobocon_rules import CLASSES, Score
from hakoniwa.wire.objective import BUILT_IN, objective_named
from hakoniwa.wire.protocol import BenchCause, CrashKind, Event, SyncMode
from hakoniwa.wire.result import TestResult

U64 = st.integers(0, (1 << 64) - 1)
I32 = st.integers(-(1 << 31), (1 << 31) - 1)
scores = st.builds(Score.of, st.sampled_from(sorted(CLASSES)), st.none() | st.integers(0, 120_000_000),
                   st.integers(0, 10), st.booleans(), st.none() | st.booleans())
results = st.builds(
    TestResult, st.sampled_from(Event), U64, st.floats(0, 1e6, allow_nan=False), st.integers(0, 1000), U64, U64,
    st.sampled_from(SyncMode), st.sampled_from(CrashKind), I32, st.text(max_size=200), U64,
    st.sampled_from(sorted(BUILT_IN)).map(objective_named), st.sampled_from(BenchCause), st.none() | scores, U64,
    st.tuples(I32, I32), st.text(max_size=500))


@given(results)
def test_every_field_survives_the_trip(result):
    back = TestResult.decode(result.encode())
    assert back == result and back.trajectory == result.trajectory  # the one field equality leaves out


@pytest.mark.parametrize("text", ["", "[]", "{}", '{"event": "GOAL"}'])
def test_what_is_not_a_result_is_refused(text):
    with pytest.raises((ValueError, KeyError, TypeError)):
        TestResult.decode(text)


def test_a_field_of_the_wrong_type_is_refused():
    good = json.loads(TestResult(Event.GOAL, 1, 0.0).encode())
    for field, bad in (("goal_time_us", "1"), ("event", "LAPPED"), ("checkpoints", 1.5), ("objective", "fastest")):
        with pytest.raises((ValueError, KeyError, TypeError)):
            TestResult.decode(json.dumps({**good, field: bad}))
