"""`hako try --json`'s `params` holds only what reached the program: it showed the paper's gains (kp 1.539,
...) for a team's program that reads its gains from a CSV and never saw them."""

from __future__ import annotations

import json

import pytest

from testctl import paper
from tests.helpers.commands import hako
from tests.helpers.native_fixtures import need_cc

IDLE_C = '#include "ev3api.h"\nvoid main_task(intptr_t unused) { while (1) tslp_tsk(100000); }\n'


def trial_params(*args: str) -> dict:
    r = hako("try", "--noise", "0", "--time-limit", "0.5", "--json", *args, timeout=300)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)["params"]


@pytest.mark.parametrize("gains", [(), ("--kp", "2")])
def test_params_are_the_gains_only_where_the_program_reads_them(tmp_path, gains):
    need_cc()
    app = tmp_path / "team.c"
    app.write_text(IDLE_C)
    shown = trial_params("--app", str(app), *gains)
    assert shown == ({} if not gains else {"kp": 2.0, "ki": paper.BEST_GAINS[1], "kd": paper.BEST_GAINS[2],
                                           "power": paper.MOTOR_POWER})
    assert trial_params("--app", "line_trace_c") == dict(zip(("kp", "ki", "kd"), paper.BEST_GAINS)) | {
        "power": paper.MOTOR_POWER}
