"""Native runs against the real emulator, side by side: does a program mean the same on both?

Each program runs once natively (compiled for this machine against our EV3RT runtime, lockstep) and once as a
v850 image in the real TOPPERS athrill2 (repeatable mode), on the same course and robot, with the same noise
draw (none by default: the two sides draw sensor noise at different instants, so only a noise-free pair
compares the programs alone). Programs: each EV3RT sample in the SDK's workspace that builds both ways (one
that does not move the robot natively is listed as such and not run in the real emulator, where a CPU-bound
sample emulates at a few simulated ms per wall second), RasPike-ART's official samples (`sample_c5_spike` on
HackSPi, started by its force sensor; `sample_c5`, the EV3 API, on HackEV), the C and C++ programs written for
the tests in ET Robocon teams' style (`tests/programs/`: each on its robot, started by the press it waits for),
and the built-in C tracer (the paper's Fig. 7 law) at `--sets` seeded random gain sets.

Per program it prints the event, lap and distance on each side and the largest difference in the motor-power
sequence (the i-th command each side sent its wheel motors, compared in order; the first index where they
part is shown too), and marks a pair that misses the target: the same event, laps and distances within 2%.
Each side's simulated seconds per wall second is printed at the end; `--sync-cost` adds the tracer at the
paper's gains under the unmodified protocol (`--sync hakoniwa`) to show what waiting at each sync point costs.

The physics server runs in this process, so that the motor commands it applies can be recorded as they are.
"""

from __future__ import annotations

import random
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import click

from athrill_sim.programs.athrill2 import RealSync
from athrill_sim.programs.kinds.kind import Emulator
from athrill_sim.programs.launcher import AthrillLauncher
from athrill_sim.programs.program import Program, ProgramError
from athrill_sim.programs.resolve import resolve_program
from hakoniwa.physics import spike_hub
from hakoniwa.physics.course import load_course
from hakoniwa.physics.server import PhysicsServer
from hakoniwa.wire.result import TestResult
from hakoniwa.wire.timebase import US_PER_S
from testctl.bench_options import BenchOptions, load_bench
from testctl.paper import BEST_GAINS, GAIN_RANGE, line_trace_params
from testctl.runner import TestRunner

REPO = Path(__file__).resolve().parents[1]
WORKSPACE = REPO.parent / "shared" / "third_party" / "ev3rt" / "ev3rt-athrill-v850e2m" / "sdk" / "workspace"
TEAM_PROGRAMS = REPO / "tests" / "programs"
RASPIKE = REPO.parent / "shared" / "third_party" / "raspike"
# The team-style programs: (folder, robot, the press at 0.5 s that starts it: a touch port, or the force sensor).
TEAMS = [("etrobo_cpp_tracer", None, 4), ("cpp_features", None, None), ("etrobo_hackev", "hackev", 1),
         ("etrobo_spike_cpp", "hackspi", "force")]
# RasPike-ART's official samples (ETrobocon/RasPike-ART's and the SPIKE SDK's own copy of the SPIKE one).
SPIKE_SAMPLES = [("sample_c5_spike", RASPIKE / "raspike-art-samples" / "sample_c5_spike", "hackspi", "force"),
                 ("sdk sample_c5_spike", RASPIKE / "raspike-athrill-v850e2m" / "sdk" / "workspace" / "sample_c5_spike",
                  "hackspi", "force"),
                 ("sample_c5", RASPIKE / "raspike-art-samples" / "sample_c5", "hackev", None)]
TOLERANCE = 0.02  # laps and distances within 2%
TRACER = "line_trace_c"


@dataclass(frozen=True)
class Subject:
    """A program to compare, with the robot and the start press it needs."""

    label: str
    app: str
    robot: str | None = None
    press: int | str | None = None  # a touch sensor's port, or "force"

    def scenario(self, folder: Path) -> str | None:
        if self.press is None:
            return None
        sensor = "sensor = \"force\"" if self.press == "force" else f"sensor = \"touch\"\nport = {self.press}"
        path = folder / "press.toml"
        path.write_text(f"[[press]]\n{sensor}\nat_s = 0.5\nfor_s = 0.2\n")
        return str(path)


@dataclass
class Run:
    result: TestResult
    commands: list[tuple[int, ...]] = field(default_factory=list)  # duty by port (direction applied), each change

    def lap(self) -> str:
        return f"{self.result.lap_time_s:.3f}" if self.result.lap_time_s is not None else "-"


class RecordingBench:
    """One program on an in-process physics server whose motor commands are recorded per test."""

    def __init__(self, program: Program, course: str, time_limit_s: float | None,
                 subject: Subject | None = None) -> None:
        self._tmp = tempfile.TemporaryDirectory(prefix="hako-fidelity-")
        options = BenchOptions(course=course, time_limit_s=time_limit_s, robot=subject and subject.robot,
                               scenario=subject and subject.scenario(Path(self._tmp.name)))
        loaded, robot, scenario = load_bench(options)
        self.server = PhysicsServer(Path(self._tmp.name), loaded, AthrillLauncher(Path(self._tmp.name), program),
                                    athrill_timeout_s=30.0,
                                    time_limit_us=options.time_limit_us(loaded.time_limit_us), robot=robot,
                                    scenario=scenario)
        self.commands: list[tuple[int, ...]] = []
        drive = self.server.env.drive

        def record(powers, directions) -> None:
            # as the motors get them: a native SPIKE program writes its power and the direction it set up, ET
            # Robocon's SDK in the image the power already negated for a counter-clockwise motor
            duty = tuple(spike_hub.direction_sign(d) * p for p, d in zip(powers, directions))
            if not self.commands or self.commands[-1] != duty:
                self.commands.append(duty)
            drive(powers, directions)

        self.server.env.drive = record
        self._thread = threading.Thread(target=self.server.serve, daemon=True)
        self._thread.start()
        self.runner = TestRunner(Path(self._tmp.name))

    def run(self, params: dict[int, float], noise_seed: int, noise: float) -> Run:
        self.commands = []
        result = self.runner.run_test(params, noise_seed=noise_seed, noise_scale=noise)
        return Run(result, self.commands)

    def close(self) -> None:
        self.runner.end()
        self._thread.join(timeout=60)
        self.runner.close()
        self._tmp.cleanup()


def power_gap(a: list[tuple[int, ...]], b: list[tuple[int, ...]]) -> tuple[int, int | None]:
    """The largest difference between the i-th commands of the two sequences (any port), and the first index
    where they differ (a command one side sent and the other did not counts as its whole power)."""
    gap, first = 0, None
    ports = len((a or b or [()])[0])
    for i in range(max(len(a), len(b))):
        x, y = (a[i] if i < len(a) else (0,) * ports), (b[i] if i < len(b) else (0,) * ports)
        d = max((abs(p - q) for p, q in zip(x, y)), default=0)
        if d and first is None:
            first = i
        gap = max(gap, d)
    return gap, first


def within(x: float | None, y: float | None) -> bool:
    if x is None or y is None:
        return x is y
    return abs(x - y) <= TOLERANCE * max(abs(x), abs(y), 1e-9)


def agree(native: Run, real: Run) -> bool:
    n, r = native.result, real.result
    return n.event == r.event and within(n.lap_time_s, r.lap_time_s) and within(n.distance_m, r.distance_m)


def sim_seconds(r: TestResult, limit_s: float) -> float:
    return r.lap_time_s if r.lap_time_s is not None else limit_s


def programs(corpus: bool, teams: bool) -> list[Subject]:
    """The programs to compare: the SDK's samples (each folder with an app.c), the team-style programs, then
    the tracer."""
    found = []
    if corpus and WORKSPACE.is_dir():
        found = [Subject(d.name, str(d)) for d in sorted(WORKSPACE.iterdir()) if (d / "app.c").is_file()]
    if teams:
        found += [Subject(name, str(TEAM_PROGRAMS / name), robot, press) for name, robot, press in TEAMS]
    if corpus:
        found += [Subject(label, str(folder), robot, press) for label, folder, robot, press in SPIKE_SAMPLES
                  if folder.is_dir()]
    return [*found, Subject(TRACER, TRACER)]


def random_gains(sets: int, seed: int) -> list[tuple[float, float, float]]:
    rng = random.Random(seed)
    return [tuple(round(rng.uniform(*GAIN_RANGE), 3) for _ in range(3)) for _ in range(sets)]


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--sets", type=click.IntRange(min=1), default=20, show_default=True,
              help="Random gain sets of the tracer.")
@click.option("--seed", type=click.IntRange(min=0), default=1, show_default=True, help="Seed of the gain sets.")
@click.option("--noise", type=click.FloatRange(0, 10), default=0.0, show_default=True, help="Noise scale (both sides).")
@click.option("--noise-seed", type=click.IntRange(min=0), default=0, show_default=True, help="Noise draw (both sides).")
@click.option("--course", default="oval", show_default=True, help="Course of every run.")
@click.option("--time-limit", type=click.FloatRange(min=0.1), default=None,
              help="Simulated seconds per run [the course's].")
@click.option("--corpus/--no-corpus", default=True, show_default=True,
              help="Include the EV3RT SDK's sample programs and RasPike-ART's.")
@click.option("--teams/--no-teams", default=True, show_default=True,
              help="Include the team-style C and C++ programs of tests/programs.")
@click.option("--program", "extra", multiple=True, type=click.Path(exists=True, path_type=Path),
              help="Another EV3RT program (app.c or workspace folder) to compare; repeatable.")
@click.option("--only", multiple=True, help="Only these programs (labels as printed); repeatable.")
@click.option("--athrill2", default=None, help="athrill2 with the sync patch [on PATH, else build/athrill-repeatable].")
@click.option("--sync-cost", is_flag=True, help="Also time the tracer at the paper's gains with --sync hakoniwa.")
def main(sets: int, seed: int, noise: float, noise_seed: int, course: str, time_limit: float | None,
         corpus: bool, teams: bool, extra: tuple[Path, ...], only: tuple[str, ...], athrill2: str | None,
         sync_cost: bool) -> None:
    """Run each program natively and in the real emulator; print the pairs and whether they agree."""
    limit_s = BenchOptions(course=course, time_limit_s=time_limit).time_limit_us(
        load_course(course).time_limit_us) / US_PER_S
    wall = {"native": [0.0, 0.0], "real": [0.0, 0.0]}  # sim s, wall s
    misses = []
    print(f"{'program':<26} {'native: event':>14} {'lap':>7} {'dist':>6}   {'real: event':>12} {'lap':>7} {'dist':>6}"
          f"   {'max dP':>6} {'first':>5}  ok")
    for subject in [*programs(corpus, teams), *(Subject(p.name, str(p)) for p in extra)]:
        label, app = subject.label, subject.app
        if only and label not in only:
            continue
        gain_sets = random_gains(sets, seed) if app == TRACER else [BEST_GAINS]
        try:
            native = RecordingBench(resolve_program(app), course, time_limit, subject)
            real = RecordingBench(resolve_program(app, emulator=Emulator.ATHRILL2, athrill2=athrill2), course,
                                  time_limit, subject)
        except ProgramError as e:
            print(f"{label:<26} skipped: {e}")
            continue
        try:
            for gains in gain_sets:
                params = line_trace_params(*gains)
                name = f"{label} {'/'.join(f'{g:g}' for g in gains)}" if app == TRACER else label
                first_run = native.run(params, noise_seed, noise)
                if first_run.result.distance_m == 0:  # a real run of a CPU-bound sample takes an hour
                    print(f"{name:<26} {first_run.result.event.name:>14} {first_run.lap():>7} {0:6.2f}   not run: "
                          "does not move the robot natively", flush=True)
                    continue
                pair = [first_run, real.run(params, noise_seed, noise)]
                for side, run in zip(wall, pair):
                    wall[side][0] += sim_seconds(run.result, limit_s)
                    wall[side][1] += run.result.wall_s
                gap, first = power_gap(pair[0].commands, pair[1].commands)
                ok = agree(*pair)
                if not ok:
                    misses.append(name)
                n, r = pair[0].result, pair[1].result
                print(f"{name:<26} {n.event.name:>14} {pair[0].lap():>7} {n.distance_m:6.2f}   {r.event.name:>12} "
                      f"{pair[1].lap():>7} {r.distance_m:6.2f}   {gap:6d} {'-' if first is None else first:>5}  "
                      f"{'yes' if ok else 'no'}", flush=True)
        finally:
            native.close()
            real.close()
    for side, (sim, spent) in wall.items():
        if spent:
            print(f"{side}: {sim:.1f} sim-s in {spent:.1f} wall-s = {sim / spent:.2f} sim-s per wall-s")
    if sync_cost:
        params = line_trace_params(*BEST_GAINS)
        exe = athrill2  # the same athrill2 both times: the patch's wait is off under --sync hakoniwa
        for sync in RealSync:
            try:
                program = resolve_program(TRACER, emulator=Emulator.ATHRILL2, athrill2=exe, sync=sync)
            except ProgramError as e:
                raise click.ClickException(str(e)) from None
            exe = program.argv[0]
            bench = RecordingBench(program, course, time_limit)
            try:
                start = time.perf_counter()
                r = bench.run(params, noise_seed, noise).result
                spent = time.perf_counter() - start
            finally:
                bench.close()
            print(f"tracer at the paper's gains, --sync {sync}: {r.event.name} "
                  f"{sim_seconds(r, limit_s):.2f} sim-s in {spent:.2f} wall-s = {sim_seconds(r, limit_s) / spent:.2f} "
                  f"sim-s per wall-s, max time diff {r.max_time_diff_us} us")
    print(f"pairs off the target (same event, laps and distances within {TOLERANCE:.0%}): "
          + (", ".join(misses) if misses else "none"))
    sys.exit(1 if misses else 0)


if __name__ == "__main__":
    main()
