"""`hako`: the user's entry point to the test bench.

It parses, checks and launches benches (`testctl.bench.Bench`: the physics and the program run in processes of
their own), and controls their tests: `hako try` its one test on one bench, as a campaign does on many.
Nothing heavy (NumPy, MuJoCo, GPyOpt, matplotlib) is imported here except where a command draws, so
`hako --help` and a bad option answer at once.
"""

from __future__ import annotations

import copy
import dataclasses
import datetime as dt
import functools
import json
import os
import sys
import tempfile
import threading
from pathlib import Path
from typing import TYPE_CHECKING, NoReturn

import click

from hakoniwa.conventions import HELP, Float32, OneLineErrorsGroup, option_group, writable_file
from hakoniwa.pictures.video_options import VideoOptions, check_video_path, film_options
from hakoniwa.wire.exits import exit_status
from hakoniwa.wire.processes import describe_exit
from hakoniwa.wire.protocol import Event
from hakoniwa.wire.rundir import TRAJECTORY_FILE, diagnose
from hakoniwa.wire.timebase import CLOCK_EPOCH_S
from testctl import paper
from testctl.bench_options import BenchOptions, bench_options, pop_bench
from testctl.campaign.benches import (
    RECORDED_BENCH,
    absolute,
    bench_info,
    campaign_bench,
    campaign_benches,
    recorded_files,
    repeatable_bench,
    usable_cores,
)
from testctl.cluster_address import ClusterAddress, cluster_address
from testctl.hako.course import course
from testctl.hako.patch import patch
from testctl.options import (
    DEFAULT_DRAWS,
    MAX_DRAWS,
    RUN_HELP,
    SMOKE_DRAWS,
    campaign_options,
    make_out_dir,
    noise_options,
    plan,
)
from testctl.suite.cases import DEFAULT_FILE

if TYPE_CHECKING:
    from hakoniwa.wire.result import TestResult
    from testctl.executor import TestSpec

POWER = Float32(-100.0, 100.0)


def report_death(code: int, run_dir: Path) -> NoReturn:
    """Exit like the bench's physics process did (`code`, non-zero), saying what killed it where a signal did:
    otherwise it said why itself."""
    if code < 0:
        damaged = diagnose(run_dir)
        click.echo(f"hako: the physics process {describe_exit(code)}"
                   + (f" ({damaged})" if damaged else ""), err=True)
    raise SystemExit(exit_status(code))


@click.group(cls=OneLineErrorsGroup, context_settings=HELP)
@click.version_option(package_name="hakoniwa-py")
def main() -> None:
    """Hakoniwa-style robot test bench: MuJoCo physics, an Athrill (our mock, or the real TOPPERS emulator)
    running the robot program, and a test controller: three processes over memory-mapped files."""


main.add_command(course)
main.add_command(patch)


@main.command("try", context_settings=HELP)
@click.option("--kp", type=Float32(), default=paper.BEST_GAINS[0], show_default=True, help="Proportional gain.")
@click.option("--ki", type=Float32(), default=paper.BEST_GAINS[1], show_default=True, help="Integral gain.")
@click.option("--kd", type=Float32(), default=paper.BEST_GAINS[2], show_default=True, help="Derivative gain.")
@click.option("--power", type=POWER, default=paper.MOTOR_POWER, show_default=True,
              help="Base motor power [%], -100..100.")
@noise_options
@bench_options
@click.option("--run-dir", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Keep the run's files here (default: a temporary folder).")
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@click.option("--trajectory", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="Draw the course and the robot's path into this PNG.")
@click.option("--video", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="Film the test into this .mp4 or .gif after it ran (MuJoCo renders it from the run's replay).")
@click.option("--view", is_flag=True,
              help="Watch the test live in MuJoCo's viewer, paced at --speed (needs a display).")
@film_options
def try_once(kp: float, ki: float, kd: float, power: float, seed: int, noise: float, run_dir: Path | None,
             as_json: bool, trajectory: Path | None, video: Path | None, view: bool, camera: str, fps: int,
             speed: float, **bench) -> None:
    """Run one test with the given parameters and print the event and lap time."""
    from testctl.interrupts import stopped_by

    film = None
    if video is not None:
        film = VideoOptions(video, camera, fps, speed)
        check_film(film)
    if view:
        check_display()
    options = pop_bench(bench)
    ctx = click.get_current_context()
    given = any(ctx.get_parameter_source(g) == click.core.ParameterSource.COMMANDLINE for g in GAINS)
    try:
        _try_once(kp, ki, kd, power, seed, noise, run_dir, as_json, trajectory, options, film,
                  speed if view else None, gains_read=given or reads_paper_gains(options.app))
    except KeyboardInterrupt as e:
        stopped_by(e)


# `hako trial` was this command's name until "trial" came to mean one thing only: a set the search tries
# (`--trials`, Optuna's trials; docs/GLOSSARY.md). The old name still works, hidden and deprecated.
renamed = copy.copy(try_once)
renamed.name, renamed.hidden, renamed.deprecated = "trial", True, "use hako try"
main.add_command(renamed)


def check_display() -> None:
    """--view needs a window: without a display, one line and exit 1 before anything starts."""
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        raise click.ClickException("--view needs a display (DISPLAY is not set); film the test with --video "
                                   "FILE instead")


def check_film(film: VideoOptions) -> None:
    """A video that cannot be made is one line before the test runs, not after."""
    check_video_path(film.path, film.fps)
    from hakoniwa.pictures.video import gl_problem, writer_problem

    problem = writer_problem(film.path) or gl_problem()
    if problem:
        raise click.ClickException(f"--video: {problem}")


def make_film(run_dir: Path, film: VideoOptions, title: str = "") -> int:
    """The film of the run in `run_dir`; how many frames it has.

    Raises:
        ReplayError: the run left no readable replay.
        VideoError: the film cannot be made (no encoder, no OpenGL).
        click.ClickException: the film cannot be written.
    """
    from hakoniwa.physics.replay import read_replay
    from hakoniwa.pictures.video import film as shoot

    try:
        return shoot(read_replay(run_dir), film, title=title)
    except OSError as e:
        raise click.ClickException(f"cannot write {film.path}: {e.strerror or e}") from None


GAINS = ("kp", "ki", "kd", "power")  # the paper's parameters, which `hako try` writes into their slots


def reads_paper_gains(app: str) -> bool:
    """Whether the program reads the paper's gains from their slots, as far as the bench knows: its own
    tracers do; a team's program, which keeps its gains where it likes (a CSV, a #define), does not unless
    the gains were given for it on the command line."""
    from athrill_sim.apps import BUILTIN, C_BUILTIN

    return app in (*BUILTIN, *C_BUILTIN)


def _try_once(kp: float, ki: float, kd: float, power: float, seed: int, noise: float, run_dir: Path | None,
              as_json: bool, trajectory: Path | None, options: BenchOptions, film: VideoOptions | None = None,
              view_speed: float | None = None, gains_read: bool = True) -> None:
    from hakoniwa.wire.protocol import LayoutError
    from testctl.bench import Bench
    from testctl.executor import TestSpec

    if trajectory is not None:
        writable_file(trajectory, "--trajectory")
    with tempfile.TemporaryDirectory(prefix="hako-") as tmp:
        rd = run_dir or Path(tmp)
        try:
            rd.mkdir(parents=True, exist_ok=True)
        except OSError as e:
            raise click.ClickException(f"--run-dir {rd}: {e.strerror}") from None
        # The paper's single test, on the bench a campaign tests on: this process is its controller.
        bench = Bench(options, rd, physics_args=() if view_speed is None else ("--view", repr(view_speed)))
        spec = TestSpec(0, 1, paper.line_trace_params(kp, ki, kd, power), seed, noise)
        try:
            result = bench.run(spec)
        except LayoutError:  # the physics process ended before it made its files, having said why
            report_death(bench.exit_status or 1, rd)
        except KeyboardInterrupt:
            bench.stop()
            raise
        finally:
            bench.close()
        if result.bench_fault and bench.exit_status:  # the physics process died under the test
            report_death(bench.exit_status, rd)
        # Only what reached the program: the paper's gains, written into their slots, mean nothing to a program
        # that never reads them.
        params = dict(zip(GAINS, (kp, ki, kd, power), strict=True)) if gains_read else {}
        # The date a native program's wall clock (system_clock, time()) reads at the test's start: its logs'
        # timestamps repeat from it (docs/NATIVE.md).
        epoch = dt.datetime.fromtimestamp(CLOCK_EPOCH_S, dt.UTC).isoformat().replace("+00:00", "Z")
        shown = {**result.to_dict(), "params": params, "seed": seed, "noise": noise, "clock_epoch": epoch}
        if film is not None:
            make_film(rd, film)  # as `hako replay` films the run folder
        if trajectory is not None:
            from hakoniwa.physics.course import load_course
            from hakoniwa.pictures.plot import draw_trajectory, read_trajectory

            lap = f"lap {result.lap_time_s:.2f} s" if result.lap_time_s is not None else result.event.name
            draw_trajectory(load_course(options.course), read_trajectory(rd / TRAJECTORY_FILE), trajectory,
                            title=f"{' '.join(f'{k}={v:g}' for k, v in params.items()) or options.app}: {lap}")
    if result.program_output:  # the program's own error, which the run folder's log alone would hold
        click.echo(f"hako: the program's last lines:\n{result.program_output}", err=True)
    if as_json:
        click.echo(json.dumps(shown, sort_keys=True))
    else:
        lap = f"{result.lap_time_s:.3f} s" if result.lap_time_s is not None else "-"
        reason = result.crash_reason()
        why = f" ({reason})" if reason else ""
        done = f"  completed at: {result.completed_time_us / 1e6:.3f} s" if result.completed_time_us else ""
        if result.event == Event.COURSE_OUT:
            x, y = (v / 1000 for v in result.out_xy_mm)
            done += f"  left the course at: {result.out_time_us / 1e6:.3f} s, ({x:.3f}, {y:.3f}) m"
        click.echo(f"event: {result.event.name}{why}  lap time: {lap}  distance: {result.distance_m:.2f} m  "
                   f"checkpoints: {result.checkpoints}{done}")
        if result.score is not None:
            click.echo(result.score.describe())
    if result.bench_fault:
        raise click.ClickException(f"the bench spoiled the test ({result.crash_reason()}), which says nothing "
                                   f"of the parameters: run it again")


def benches_options(default: str):
    """--benches, or --scheduler with its TLS files; the command gets them as `benches` and `scheduler`, a
    checked `ClusterAddress` (or None for a local cluster)."""
    tls_file = click.Path(exists=True, dir_okay=False, path_type=Path)
    options = option_group([
        click.option("--benches", type=click.IntRange(min=1), default=None,
                     help=f"Benches run in parallel (Dask workers of a local cluster) [{default}]."),
        click.option("--scheduler", default=None, metavar="tls://HOST:PORT",
                     help="Run on the workers of this Dask cluster instead (each needs only hakoniwa-py installed); "
                          "tcp:// is plaintext, for this machine or a network you trust (docs/CLUSTER.md)."),
        click.option("--tls-ca", type=tls_file, default=None,
                     help="With a tls:// scheduler: the CA certificate that signed the scheduler's [Dask's "
                          "distributed.comm.tls.ca-file]."),
        click.option("--tls-cert", type=tls_file, default=None,
                     help="With a tls:// scheduler: this client's certificate [distributed.comm.tls.client.cert]."),
        click.option("--tls-key", type=tls_file, default=None,
                     help="With a tls:// scheduler: this client's key, unless --tls-cert holds it "
                          "[distributed.comm.tls.client.key]."),
    ])

    def decorate(f):
        @functools.wraps(f)
        def command(*args, scheduler: str | None, tls_ca: Path | None, tls_cert: Path | None, tls_key: Path | None,
                    **kwargs):
            return f(*args, scheduler=cluster_address(scheduler, tls_ca, tls_cert, tls_key), **kwargs)

        return options(command)

    return decorate


def refuse_benches_with_scheduler(benches: int | None, scheduler: ClusterAddress | None) -> None:
    if benches is not None and scheduler is not None:
        raise click.UsageError("--benches starts a local cluster; with --scheduler the cluster's workers are the "
                               "benches")


@main.command(context_settings=HELP, help=RUN_HELP)
@bench_options
@benches_options("the CPU cores this process may use; on two or more, at least the tests of a set that run at once")
@campaign_options
@click.option("--validate", type=click.IntRange(min=0), default=None, callback=lambda ctx, param, n: _draws(n),
              help=f"Test the best set on this many fresh noise draws (at most {MAX_DRAWS}): its success rate "
                   f"and lap quantiles; 0 skips [{DEFAULT_DRAWS}; {SMOKE_DRAWS} with --smoke; 1 with --noise 0, "
                   f"where every draw is the same test; on --resume, the campaign's].")
def run(benches: int | None, scheduler: ClusterAddress | None, validate: int | None, **options) -> None:
    from testctl.interrupts import interrupts, stopped_by

    with interrupts():
        try:
            _run(benches, scheduler, validate, options)
        except KeyboardInterrupt as e:  # before the campaign started or after it ended: nothing to resume
            stopped_by(e)


def _draws(n: int | None) -> int | None:
    if n is not None and n > MAX_DRAWS:
        raise click.BadParameter(f"{n} draws is more than {MAX_DRAWS}, past which the estimates hardly move; for a "
                                 "longer look at a set, give `hako test` a case with `from` and `seeds`")
    return n


def _run(benches: int | None, scheduler: ClusterAddress | None, validate: int | None, options: dict) -> None:
    refuse_benches_with_scheduler(benches, scheduler)  # before anything starts
    given = pop_bench(options)
    if options["repeats"] is None and options["noise"] == 0 and options["resume"] is None and repeatable_bench(given):
        options["repeats"] = 1  # every repetition of a set would be the very same test
    p = plan(**options, penalty_s=time_limit_s(given), objective=given.objective)
    ctx = click.get_current_context()
    on_command_line = {field for field in RECORDED_BENCH
                       if ctx.get_parameter_source(field) == click.core.ParameterSource.COMMANDLINE}
    if validate is None:
        validate = (p.validate if p.validate is not None else 1 if p.config.noise == 0
                    else SMOKE_DRAWS if options["smoke"] else DEFAULT_DRAWS)
    try:
        bench = dataclasses.replace(campaign_bench(p.bench, given, on_command_line), bindings=p.config.space.bindings())
        n = benches or campaign_benches(bench, p.config.rule.still_needed([]))
        program = check_bench(bench, benches=None if scheduler else n)
        files = recorded_files(p.bench, bench)
        from testctl.cluster import DaskExecutor

        executor = DaskExecutor(bench, benches=None if scheduler else n, scheduler=scheduler)
    except BaseException:
        p.abandon()
        raise
    run_dir = p.out_dir / "run"
    from testctl.bench import Bench
    from testctl.campaign.fingerprint import FILES_KEY
    from testctl.campaign.session import run_campaign
    from testctl.cluster import ClusterError
    local = Bench(bench, run_dir)
    last: list = []  # [spec, (result, run_dir)] of the local bench's last sound test

    def test_once(spec: TestSpec) -> tuple[TestResult, Path]:
        """The best set is drawn twice in a row (as an improvement, then at the end, with its film): the run
        folder still holds that very test, which would come out the same, so it runs once."""
        if not last or last[0] != spec:
            result = local.run(spec)
            if result.bench_fault:
                last.clear()
                return result, run_dir
            last[:] = [spec, (result, run_dir)]
        return last[1]

    # The cluster takes a second or two to close: that happens while the best lap is drawn and filmed.
    closing = threading.Thread(target=executor.close, name="cluster-close")
    try:
        run_campaign(p, executor, bench_info={**bench_info(bench), FILES_KEY: files},
                     test_once=test_once, course_folder=Path(bench.course),
                     failures=(ClusterError,), validate=validate, write_patch=patch_writer(program),
                     benches_done=closing.start)
    finally:
        local.close()
        if closing.ident is None:
            executor.close()
        else:
            closing.join()


@main.command("test", context_settings=HELP)
@click.argument("test_file", type=click.Path(dir_okay=False, path_type=Path), default=DEFAULT_FILE, required=False)
@bench_options
@benches_options("half the CPU cores this process may use, at least 1")
@click.option("--out", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Output folder: each case's lap distribution, a failing case's trajectory and run folder, "
                   "the bench's run folder [runs/test-TIME].")
@click.option("--junit", "junit_file", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="Write JUnit XML here (one testcase per case), for GitHub Actions, GitLab or Jenkins.")
@click.option("--json", "json_file", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="Write the full results (every run of every case) here as JSON.")
def test_command(test_file: Path, benches: int | None, scheduler: ClusterAddress | None, out: Path | None,
                 junit_file: Path | None, json_file: Path | None, **bench) -> None:
    """Run the cases of TEST_FILE [hako-tests.toml] on the benches and check what each must show (events,
    checkpoints, lap bounds on every run or as a quantile, success rate). Exit 0: every case passed; 1: a
    case failed; 2: bad input or the run itself broke (a bench fault, a bench that died). See docs/CI.md."""
    from testctl.interrupts import interrupts, stopped_by

    with interrupts():
        try:
            _test(test_file, benches, scheduler, out, junit_file, json_file, pop_bench(bench))
        except KeyboardInterrupt as e:  # before any test ran: run_suite says its own line once tests run
            stopped_by(e)


def _test(test_file: Path, benches: int | None, scheduler: ClusterAddress | None, out: Path | None,
          junit_file: Path | None, json_file: Path | None, base: BenchOptions) -> None:
    import datetime as dt

    from hakoniwa.wire.errors import HakoError
    from testctl.suite.cases import load_suite
    from testctl.suite.session import RunBroken, run_suite

    refuse_benches_with_scheduler(benches, scheduler)
    n = benches or max(1, usable_cores() // 2)
    try:
        cases = load_suite(test_file, dataclasses.replace(base, course=absolute(base.course), app=absolute(base.app)))
        out_dir = out or Path("runs") / f"test-{dt.datetime.now():%Y%m%d-%H%M%S}"
        for path, option in ((junit_file, "--junit"), (json_file, "--json")):
            if path is not None and path.parent.resolve() != out_dir.resolve():  # the output folder: made below
                writable_file(path, option)
        for options in dict.fromkeys(c.bench for c in cases):
            check_bench(options, benches=None if scheduler else n)
        make_out_dir(out_dir)
    except HakoError as e:  # a bad suite, course or program: the run is broken before it starts (exit 2)
        raise RunBroken(str(e)) from None
    except click.ClickException as e:
        raise RunBroken(e.message) from None
    run_suite(test_file, cases, out_dir, benches=n, scheduler=scheduler, junit_file=junit_file,
              json_file=json_file)


@main.command(context_settings=HELP)
@click.argument("app", type=click.Path(exists=True, path_type=Path))
@click.option("--sdk", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="The EV3RT SDK (ev3rt-athrill-v850e2m, or a folder holding it) [default: $EV3RT_SDK, else "
                   "../shared/third_party/ev3rt beside the project].")
@click.option("--toolchain", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="A folder with v850-elf-gcc (or its bin/) [default: on PATH, else the SDK's toolchain tarball, "
                   "unpacked once into the cache].")
@click.option("--raspike-art", "raspike_art", is_flag=True,
              help="Build APP (a RasPike-ART workspace folder) into RasPike-ART's aarch64 asp, with RasPike-ART's "
                   "own make; --sdk names the RasPike-ART folder [default: $RASPIKE_ART, else "
                   "../shared/third_party/raspike-art/RasPike-ART]. Needs Debian's gcc-aarch64-linux-gnu, "
                   "g++-aarch64-linux-gnu and qemu-user.")
def build(app: Path, sdk: Path | None, toolchain: Path | None, raspike_art: bool) -> None:
    """Build APP (an EV3RT app.c or workspace folder) into a v850 image for the real athrill2 and print its
    path. Images are cached by their sources, the SDK and the compiler; `hako try --app APP --emulator
    athrill2` builds and runs in one go. With --raspike-art, APP is a team's RasPike-ART workspace folder and
    the product is its asp."""
    announce = (lambda what: click.echo(what + " ...", err=True)) if sys.stderr.isatty() else None
    if raspike_art:
        from athrill_sim.raspike_art.build import build_asp

        if toolchain is not None:
            raise click.UsageError("--toolchain names a v850 toolchain; --raspike-art builds with Debian's "
                                   "aarch64-linux-gnu-gcc on PATH")
        click.echo(str(build_asp(app, sdk=sdk, announce=announce)))
        return
    from athrill_sim.v850.build import build_image

    image = build_image(app, sdk=sdk, toolchain=toolchain, announce=announce)
    click.echo(str(image))


@main.command(context_settings=HELP)
@click.argument("run_dir", type=click.Path(file_okay=False, path_type=Path))
@click.option("--video", type=click.Path(dir_okay=False, path_type=Path), required=True,
              help="The .mp4 or .gif to film the run's last test into.")
@film_options
def replay(run_dir: Path, video: Path, camera: str, fps: int, speed: float) -> None:
    """Film the last test of RUN_DIR: hako try's --run-dir, a campaign folder (its best set's run), or a
    failing case's folder of hako test (its worst run), from the replay the test left there."""
    from hakoniwa.physics.replay import REPLAY_FILE

    film = VideoOptions(video, camera, fps, speed)
    check_film(film)
    for folder in (run_dir, run_dir / "run"):  # a campaign's or a failing case's run folder is beside its report
        if (folder / REPLAY_FILE).is_file():
            run_dir = folder
            break
    click.echo(f"wrote {video} ({make_film(run_dir, film)} frames)")


@main.command(context_settings=HELP)
@click.argument("run_dirs", nargs=-1, required=True, type=click.Path(path_type=Path), metavar="RUN_DIR...")
@click.option("--host", default="127.0.0.1", show_default=True,
              help="Address to serve on (0.0.0.0 shows the campaigns to every machine that reaches this one).")
@click.option("--port", type=click.IntRange(0, 65535), default=8080, show_default=True,
              help="Port to serve on (0: any free one).")
def dashboard(run_dirs: tuple[Path, ...], host: str, port: int) -> None:
    """Serve optuna-dashboard on the campaigns in RUN_DIR... (each one's optuna.log): their history,
    parameter importances, slice and contour plots, every set's tests and the trajectories of the sets that
    improved on the best. Live: a campaign still running shows each set as it is decided. Needs the
    dashboard extra: pip install -e '.[dashboard]'."""
    from testctl.campaign.dashboard import make_app, make_server
    from testctl.interrupts import interrupts, stopped_by

    server = make_server(make_app(run_dirs), host, port)
    shown = host if ":" not in host else f"[{host}]"
    click.echo(f"hako dashboard: {len(run_dirs)} campaign{'s' * (len(run_dirs) > 1)} on "
               f"http://{shown}:{server.server_port}/dashboard (Ctrl-C stops)", err=True)
    with interrupts():
        try:
            server.serve_forever()
        except KeyboardInterrupt as e:
            stopped_by(e)
        finally:
            server.server_close()


def time_limit_s(bench: BenchOptions) -> float:
    """The bench's time limit: what a failed test scores in a campaign.

    Raises:
        CourseError: the course cannot be loaded.
    """
    from hakoniwa.physics.course import load_course
    from hakoniwa.wire.timebase import US_PER_S

    return bench.time_limit_us(load_course(bench.course).time_limit_us) / US_PER_S


def patch_writer(program):
    """best.patch's writer for a program tuned as it is written; None for one that reads its parameters at
    their offsets (nothing of it to patch)."""
    if program.tuning is None:
        return None
    from testctl.campaign.patch import write_patch

    return lambda path, values: write_patch(path, program.tuning, values)


def check_bench(bench: BenchOptions, benches: int | None = 1):
    """Load the course and check the program here, once, so that a bad one is one line before any worker
    starts (and a C program is built once, into the cache every local worker then hits); the program.
    `benches` is how many run on this machine at once (None: a cluster's, elsewhere).

    Raises:
        CourseError, RobotError, ScenarioError: the course, robot or scenario cannot be loaded.
        ProgramError: the program cannot run (or build).
        LinkError: its UDP ports are taken.
        click.ClickException: fixed UDP ports and several benches.
    """
    from hakoniwa.wire.vdev_udp import RX_PORT_KEY, TX_PORT_KEY, check_free
    from testctl.bench_options import load_bench

    load_bench(bench)
    program = bench.program()
    if program.udp is not None and program.udp.fixed:
        if benches is not None and benches > 1:
            raise click.ClickException(
                f"--device-config {bench.device_config} fixes athrill2's UDP ports ({program.udp.physics}, "
                f"{program.udp.athrill}), which {benches} benches cannot share: use --benches 1, or delete "
                f"its {TX_PORT_KEY} and {RX_PORT_KEY} lines (each bench then adds ports of its own)")
        check_free(program.udp)
    program.finish_check(program.start_check())
    return program
