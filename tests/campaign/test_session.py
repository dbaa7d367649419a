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
        run_campaign(p, SerialExecutor(lambda spec: CRASH), bench_info={}, test_once=None,  # type: ignore[arg-type]
                     course_folder=tmp_path)
    message = info.value.format_message()
    assert message.startswith("no parameter set succeeded: 16 of 16 scored tests ended "
                              "CRASH (program: athrill exited with status 1)")  # 4 sets, a test and 3 retries each
    assert "best: no parameter set succeeded" in capsys.readouterr().out  # the summary and report still come
    assert (tmp_path / "c" / "results.csv").is_file()


def test_a_campaign_loads_its_course_once_for_all_its_pictures(tmp_path, monkeypatch):
    """Each set that improves on the best is drawn on the course, and the best again at the end: one load of
    the course (its floor image) serves them all."""
    from hakoniwa.physics import course

    loads = []
    real = course.load_course
    monkeypatch.setattr(course, "load_course", lambda spec: loads.append(spec) or real(spec))
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    (run_dir / "trajectory.csv").write_text("time_us,x,y\n0,0.0,0.0\n10000,0.1,0.0\n")
    laps = iter(range(40, 10, -1))  # every set better than the last: each one is drawn

    def test(spec):
        return TestResult(Event.GOAL, next(laps) * 1_000_000, 0.01)

    p = plan(trials=3, init_points=2, repeats=1, seed=None, optimizer="random", batch=None, noise=None,
             space_file=None, out=tmp_path / "c", resume=None, smoke=False, penalty_s=60.0)
    run_campaign(p, SerialExecutor(test), bench_info={}, test_once=lambda spec: (test(spec), run_dir),
                 course_folder="oval")  # type: ignore[arg-type]
    assert loads == ["oval"]
    assert len(list((tmp_path / "c").rglob("*.png"))) >= 3


def test_an_improving_set_is_drawn_from_the_path_its_test_brought(tmp_path):
    """Every set improves on the last, and each is drawn from its own test's path: the campaign's own bench
    runs one test, the best set's at the end, for its film."""
    laps = iter(range(40, 10, -1))
    path = "time_us,x,y,yaw\n0,0.0,0.0,0.0\n10000,0.1,0.0,0.0\n"

    def test(spec):
        return TestResult(Event.GOAL, next(laps) * 1_000_000, 0.01, trajectory=path)

    again = []
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    (run_dir / "trajectory.csv").write_text(path)

    def test_once(spec):
        again.append(spec)
        return TestResult(Event.GOAL, 30_000_000, 0.01), run_dir

    p = plan(trials=3, init_points=2, repeats=1, seed=None, optimizer="random", batch=None, noise=None,
             space_file=None, out=tmp_path / "c", resume=None, smoke=False, penalty_s=60.0)
    run_campaign(p, SerialExecutor(test), bench_info={}, test_once=test_once, course_folder="oval")  # type: ignore[arg-type]
    assert len(list((tmp_path / "c" / "trajectories").glob("set-*.png"))) == 5
    assert [s.set_index for s in again] == [4]  # the best set, once, at the end
