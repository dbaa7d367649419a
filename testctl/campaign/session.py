"""Running a campaign for a person: the progress line, the report files, the best set's trajectory, and a
clear word when it stops early (how it stopped, and how to continue it)."""

from __future__ import annotations

import functools
import queue
import sys
import threading
from collections import Counter
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import click

from hakoniwa.wire.result import TestResult
from testctl.campaign.journal import JOURNAL_FILE
from testctl.campaign.loop import BenchBroken, Campaign, CampaignConfig, CampaignSummary, SetResult
from testctl.campaign.progress import ProgressLine
from testctl.executor import Executor, TestSpec
from testctl.interrupts import on_stop_say, stopped_by
from testctl.options import VALIDATE_KEY, CampaignPlan
from testctl.runner import PhysicsGone
from testctl.time_left import Countdown

if TYPE_CHECKING:
    from hakoniwa.physics.course import Course
    from testctl.campaign.patch import PatchInfo

BEST_TRAJECTORY_PNG = "best_trajectory.png"
# Runs one test on a local bench and returns its result and the run directory holding its trajectory.
TestOnce = Callable[[TestSpec], tuple[TestResult, Path]]
CourseOnce = Callable[[], "Course"]  # the campaign's course, loaded at its first picture and kept
# Writes best.patch for the best set's values ({name: value}) and says what it sets (testctl.campaign.patch.PatchInfo).
PatchWriter = Callable[[Path, dict[str, float]], "PatchInfo"]


class InBackground:
    """Runs the calls of `fn` in order on a thread of its own, so that the campaign's loop never waits for them.
    The study mirror draws each set that improves on the best (a picture; a test too on the campaign's own bench
    for a resumed campaign's earlier sets, about a second); with one set proposed at a time, every bench sat
    idle meanwhile.
    An exception there is raised in the caller's thread, at its next call or at `join`. The thread lives as
    long as the process: the bench's physics process it may start dies with the thread that started it
    (`PR_SET_PDEATHSIG` follows the thread), and the campaign's end reruns the best set on that bench."""

    def __init__(self, fn: Callable[..., None]) -> None:
        self._fn = fn
        self._calls: queue.Queue[tuple] = queue.Queue()
        self._error: BaseException | None = None
        threading.Thread(target=self._work, name="study-mirror", daemon=True).start()

    def _work(self) -> None:
        while True:
            args = self._calls.get()
            try:
                if self._error is None:
                    self._fn(*args)
            except BaseException as e:  # noqa: B036  # handed to the caller's thread, which raises it
                self._error = e
            finally:
                self._calls.task_done()

    def _raise(self) -> None:
        if self._error is not None:
            raise self._error

    def __call__(self, *args) -> None:
        self._raise()
        self._calls.put(args)

    def join(self) -> None:
        """Wait for the calls made so far; raise what one of them raised."""
        self._calls.join()
        self._raise()


def resume_hint(out_dir: Path) -> str:
    return f"every finished test is in {out_dir / JOURNAL_FILE}; continue with: hako run --resume {out_dir}"


def run_campaign(p: CampaignPlan, executor: Executor, *, bench_info: dict, test_once: TestOnce,
                 course_folder: Path, failures: tuple[type[Exception], ...] = (), validate: int = 0,
                 write_patch: PatchWriter | None = None, benches_done: Callable[[], None] | None = None) -> None:
    """Run the campaign `p` on `executor`, write the report (and, with `write_patch`, best.patch: the best
    values in the program's own files), validate the best set on `validate` fresh noise draws, draw the
    best set, and print the summary. `benches_done` is called once `executor` has run its last test (the
    best set is drawn and filmed on the local bench of `test_once`). Every way it can stop short is a
    one-line error with a non-zero exit and the command that continues it."""
    from testctl.campaign.patch import BEST_PATCH
    from testctl.campaign.report import BEST_JSON, format_summary, write_best_json, write_report
    from testctl.campaign.study import STUDY_FILE, StudyMirror, attach
    from testctl.campaign.validate import VALIDATION_PNG, draw_validation, validate_best
    from testctl.executor import BenchFault

    on_stop_say(resume_hint(p.out_dir))
    course = functools.cache(functools.partial(_load_course, course_folder))
    validation = None
    label = f"campaign {p.out_dir}"
    try:
        with click.progressbar(length=p.config.total_sets, label=label, show_eta=False,
                               item_show_func=lambda s: s, file=sys.stderr) as bar:
            plain = None if sys.stderr.isatty() else lambda line: click.echo(f"{label}: {line}", err=True)
            mirror = StudyMirror(p.out_dir, lambda s, png: draw_set(p.config, s, test_once, course, png))
            mirror_update = InBackground(mirror.update)
            progress = ProgressLine(bar, plain=plain, measure=p.config.measure, repeats=p.config.repeats)
            summary = Campaign(p.config, p.out_dir, executor, on_progress=progress,
                               on_sets=mirror_update, resume=p.resume, bench_info=bench_info,
                               header={VALIDATE_KEY: validate}).run()
            mirror_update.join()
        patch = None
        if summary.best is not None and write_patch is not None:
            space = summary.config.space
            patch = write_patch(p.out_dir / BEST_PATCH, {**space.to_named(summary.best.x),
                                                         **{f.name: f.value for f in space.fixed}})
        files = write_report(p.out_dir, summary, patch.to_dict() if patch is not None else None)
        if patch is not None:
            files.append(p.out_dir / BEST_PATCH)
        if summary.best is not None and validate:
            countdown = Countdown(validate)
            with click.progressbar(length=validate, label=f"validating the best set on {validate} fresh draws",
                                   item_show_func=lambda s: s, show_eta=False, file=sys.stderr) as bar:
                validation = validate_best(summary, executor, validate, p.out_dir,
                                           lambda spec, result: bar.update(1, countdown.finished()))
            write_best_json(p.out_dir / BEST_JSON, summary, validation.to_dict(),
                            patch.to_dict() if patch is not None else None)
            files.append(draw_validation(p.out_dir / VALIDATION_PNG, summary, validation))
        if benches_done is not None:
            benches_done()
        if summary.best is not None:
            from testctl.film import LAP_VIDEO

            png, lap = draw_best(summary, test_once, course, p.out_dir / BEST_TRAJECTORY_PNG,
                                 p.out_dir / LAP_VIDEO)
            for f in (png, lap):
                if f is not None:
                    files.append(f)
                    attach(p.out_dir, f)
        files.append(p.out_dir / STUDY_FILE)
    except (BenchBroken, BenchFault, PhysicsGone, *failures) as e:  # type: ignore[misc]  # mypy#13442: a starred tuple of exception types
        raise click.ClickException(f"{e}; {resume_hint(p.out_dir)}") from None
    except OSError as e:
        raise click.ClickException(f"cannot write {e.filename or 'the campaign files'}: {e.strerror or e}; "
                                   f"{resume_hint(p.out_dir)}") from None
    except KeyboardInterrupt as e:
        stopped_by(e, resume_hint(p.out_dir))
    finally:
        p.lock.release()
    if p.resume and len(summary.sets) > p.config.total_sets:
        click.echo(f"note: the campaign already has {len(summary.sets)} sets, more than the "
                   f"{p.config.total_sets} its options ask for; nothing was run, the report was rewritten", err=True)
    click.echo(format_summary(summary))
    if patch is not None:
        click.echo(patch.describe(p.out_dir / BEST_PATCH))
    if validation is not None:
        click.echo(validation.describe())
    click.echo("wrote " + ", ".join(str(f) for f in files))
    if summary.sets and summary.best is None:
        raise click.ClickException(no_success(summary, p.out_dir))


def outcome(result: TestResult) -> str:
    reason = result.crash_reason()
    return f"{result.event.name} ({reason})" if reason else result.event.name


def no_success(summary: CampaignSummary, out_dir: Path) -> str:
    """Why no set succeeded, in one line: the outcome most of the scored tests had."""
    outcomes = Counter(outcome(t.result) for s in summary.sets for t in s.tests)
    (most, n), = outcomes.most_common(1)
    return (f"no parameter set succeeded: {n} of {sum(outcomes.values())} scored tests ended {most}; "
            f"the report is in {out_dir}")


def set_spec(config: CampaignConfig, s: SetResult) -> TestSpec:
    """A successful set as one test: with the noise of its first successful repetition, so its lap is one of
    the laps the campaign measured."""
    first = next(t for t in s.tests if t.result.success)
    space = config.space
    return TestSpec(s.index, first.rep, space.to_offsets(s.x), first.noise_seed, config.noise, space.slot_types)


def test_for_picture(test_once: TestOnce, spec: TestSpec, tries: int = 2) -> tuple[TestResult, Path]:
    """The campaign's own bench reruns a set for its picture; a bench fault there (its physics process killed,
    a damaged file) says nothing of the set, so the test runs again on the rebuilt bench before the campaign
    gives up with one line."""
    from hakoniwa.wire.protocol import LayoutError
    from testctl.executor import BenchFault

    for attempt in range(1, tries + 1):
        try:
            result, run_dir = test_once(spec)
        except (LayoutError, PhysicsGone) as e:
            if attempt == tries:
                raise PhysicsGone(f"the campaign's own bench, rerunning set {spec.set_index} for its picture: "
                                  f"{e}") from e
            continue
        if not result.bench_fault or attempt == tries:
            break
    if result.bench_fault:
        raise BenchFault(f"the campaign's own bench spoiled set {spec.set_index}'s picture twice "
                         f"({result.crash_reason()})")
    return result, run_dir


def _load_course(folder: Path) -> Course:
    from hakoniwa.physics.course import load_course

    return load_course(folder)


def draw_set(config: CampaignConfig, s: SetResult, test_once: TestOnce, course: CourseOnce, out: Path,
             what: str = "", film: Path | None = None) -> Path:
    """Draw set `s`'s test (its first success) into `out` on the campaign's `course`, loaded once for all its
    pictures: from the path its result brought where it has one, else (a resumed campaign's earlier set, or
    with `film`, which needs the test's replay) by running the test again, and filming it there."""
    from hakoniwa.pictures.plot import draw_trajectory, read_trajectory, trajectory_points
    from hakoniwa.wire.rundir import TRAJECTORY_FILE

    result = next(t.result for t in s.tests if t.result.success)
    run_dir = None
    if result.trajectory and film is None:
        points = trajectory_points(result.trajectory.splitlines())
    else:
        result, run_dir = test_for_picture(test_once, set_spec(config, s))
        points = read_trajectory(run_dir / TRAJECTORY_FILE)
    m = config.measure
    test = m.format(result.cost) if result.cost is not None else result.event.name
    names = " ".join(f"{k}={v:.3f}" for k, v in config.space.to_named(s.x).items())
    draw_trajectory(course(), points, out,
                    title=f"{what}set {s.number}, {names}: {test} (mean of the set {m.format(s.value)})")
    if film is not None:
        from testctl.film import film_run

        assert run_dir is not None
        film_run(run_dir, film, f"{what}set {s.number}, {names}")
    return out


def draw_best(summary: CampaignSummary, test_once: TestOnce, course: CourseOnce, out: Path,
              film: Path) -> tuple[Path, Path | None]:
    """The best set's trajectory, and its film (None where none can be made here)."""
    assert summary.best is not None
    png = draw_set(summary.config, summary.best, test_once, course, out, what="best: ", film=film)
    return png, film if film.is_file() else None
