"""A campaign in which no set succeeded is a failure of the command: non-zero, saying the most common outcome."""

from __future__ import annotations

import click
import pytest

from hakoniwa.wire.protocol import CrashKind, Event
from hakoniwa.wire.result import TestResult
from testctl.campaign.session import run_campaign
from testctl.executor import SerialExecutor
from testctl.options import plan

CRASH = TestResult(Event.CRASH, 0, 0.01, crash_kind=CrashKind.PROGRAM, crash_detail=1)


def test_no_success_exits_non_zero_naming_the_most_common_outcome(tmp_path, capsys):
    p = plan(trials=2, init_points=2, repeats=1, seed=None, optimizer="random", batch=None, noise=None,
             space_file=None, out=tmp_path / "c", resume=None, smoke=False, penalty_s=60.0)
    with pytest.raises(click.ClickException) as info:
        run_campaign(p, SerialExecutor(lambda spec: CRASH), bench_info={}, trial_once=None,  # type: ignore[arg-type]
                     course_folder=tmp_path)
    message = info.value.format_message()
    assert message.startswith("no parameter set succeeded: 16 of 16 scored tests ended "
                              "CRASH (program: athrill exited with status 1)")  # 4 sets, a test and 3 retries each
    assert "best: no parameter set succeeded" in capsys.readouterr().out  # the summary and report still come
    assert (tmp_path / "c" / "results.csv").is_file()
