"""Simulated seconds per wall second, and what starting an Athrill costs per test, for every kind of program.

(a) raw MuJoCo: the very model the physics process uses, stepped in this process with constant motor
    commands (one `mj_step` call per step, and MuJoCo's batched `nstep`).
(b) three-process trials at the paper's gains: a `hakoniwa-physics` process driven by this script acting as
    the test controller, once with the Python mock (`line_trace`) and once with the C tracer built natively
    (`line_trace_c`), in the same run. The physics process's own start is excluded (once per campaign); the
    Athrill's start is included (once per test, overlapped with the previous test by the pre-launch).
(c) the start of one Athrill process: spawn to its first answer on a test that has already begun (what a test
    would wait for without the pre-launch): Python mock (started, and forked from the zygote as the bench
    does, `athrill_sim.programs.zygote`), native C tracer, and the real TOPPERS athrill2 running
    the EV3RT sample image (spawn to its clock first moving; it is started with its test, never ahead).
(d) the real emulator's trials (hakoniwa sync) on the sample image, which drives until TIME_OVER.
(e) HackSPi tracers natively, in the same run: ET Robocon's official sample_c5_spike (one task woken by a cyclic
    handler every 100 ms) and tests/programs/spike_thread_tracer, its control written as teams write for
    RasPike-ART (a std::thread paced by sleep_until on steady_clock every 100 ms, started through a condition
    variable); the second's rate over the first's: what the threads and clocks cost.
(f) RasPike-ART's own sample_c5_spike, then tests/programs/team_spike_threads (its control, gyro and logger in
    std::threads of its own), on etrobocon-r: each program's asp, built by RasPike-ART's make, under qemu-user
    against the hub the physics side plays on a pty (`--emulator raspike-art`), and the same folder natively,
    in alternating rounds; each test's wall time includes starting its asp (never started ahead).
Rows that need something absent (no C compiler, no athrill2, no ../shared) print why instead of a number.
"""

from __future__ import annotations

import dataclasses
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import click
import mujoco

from athrill_sim.programs.athrill2 import RealSync
from athrill_sim.programs.kinds.kind import Emulator
from athrill_sim.programs.program import MOCK_ARGV, Program, ProgramError
from athrill_sim.programs.resolve import resolve_program
from athrill_sim.programs.zygote import Zygote
from athrill_sim.raspike_art.build import DEFAULT_FOLDER
from hakoniwa.physics.course import load_course
from hakoniwa.physics.sync import HAKONIWA_START_US
from hakoniwa.physics.world import World
from hakoniwa.wire.protocol import MappedFile, Rx, SyncMode, Tx, open_athrill, open_unity
from testctl.bench_options import DEFAULT_COURSE, BenchOptions
from testctl.paper import BEST_GAINS, line_trace_params
from testctl.runner import TestRunner

PAPER = line_trace_params(*BEST_GAINS)
REPO = Path(__file__).resolve().parents[1]
ASP_IMAGE = REPO.parent / "shared" / "third_party" / "athrill" / "ev3rt-ble_sample" / "asp"
RASPIKE_ART_SAMPLE = DEFAULT_FOLDER / "sdk" / "workspace" / "sample_c5_spike"  # RasPike-ART's own
SAMPLE_C5_SPIKE = REPO.parent / "shared" / "third_party" / "raspike" / "raspike-art-samples" / "sample_c5_spike"
THREADED_TRACER = REPO / "tests" / "programs" / "spike_thread_tracer"
TEAM_THREADS = REPO / "tests" / "programs" / "team_spike_threads"  # a team's std::threads, built by RasPike-ART too
FORCE_START = str(REPO / "tests" / "programs" / "scenarios" / "force-start.toml")
START_TIMEOUT_S = 60.0


def raw_rate(sim_s: float, batched: bool) -> float:
    world = World(load_course(DEFAULT_COURSE))
    world.set_motor_power(15, 15)
    steps = int(sim_s * 1000)
    m, d = world.model, world.data
    start = time.perf_counter()
    if batched:
        for _ in range(steps // 100):
            mujoco.mj_step(m, d, nstep=100)
            if world.touching_wall():  # bounce back to the start so the robot keeps driving on the floor
                world.reset()
                world.set_motor_power(15, 15)
    else:
        for i in range(steps):
            mujoco.mj_step(m, d)
            if i % 100 == 99 and world.touching_wall():
                world.reset()
                world.set_motor_power(15, 15)
    return sim_s / (time.perf_counter() - start)


def trial_rate(bench: BenchOptions, tests: int, *, warm_up: bool = True) -> tuple[float, list]:
    """Sim-s per wall-s of `tests` trials at the paper's gains (after a warm-up trial: the first spare Athrill,
    caches)."""
    with tempfile.TemporaryDirectory(prefix="hako-bench-") as tmp:
        run_dir = Path(tmp)
        proc = subprocess.Popen(bench.physics_command(run_dir, []))
        try:
            runner = TestRunner.attach(run_dir, proc)
            if warm_up:
                runner.run_test(PAPER)
            results = [runner.run_test(PAPER) for _ in range(tests)]
            runner.end()
            proc.wait(timeout=30)
        finally:
            if proc.poll() is None:
                proc.kill()
    limit_us = bench.time_limit_s * 1e6 if bench.time_limit_s else load_course(bench.course).time_limit_us
    sim = sum((r.goal_time_us or limit_us) for r in results) / 1e6
    return sim / sum(r.wall_s for r in results), results


def sign_of_life(program: Program, unity: MappedFile, athrill: MappedFile) -> Callable[[], bool]:
    """Set the files up for one start of `program`; returns what tells that the started process runs: a
    lockstep program's first answer, the real emulator's clock moving."""
    if program.sync == SyncMode.HAKONIWA:
        unity.unity_time_us, athrill.athrill_time_us = HAKONIWA_START_US, 0
        return lambda: athrill.athrill_time_us > 0
    answers = athrill.read_u32(Tx.ANSWER_SEQ)
    return lambda: athrill.read_u32(Tx.ANSWER_SEQ) != answers


def start_costs(program: Program, samples: int, forked: bool = False) -> list[float]:
    """Wall seconds from spawning `program` for a test that has already begun to its first sign of life;
    `forked`: forked from a zygote that has imported the mock, as the bench starts a Python program."""
    with tempfile.TemporaryDirectory(prefix="hako-start-") as tmp, open(os.devnull, "wb") as log:
        run_dir = Path(tmp)
        zygote = Zygote() if forked else None
        unity, athrill = open_unity(run_dir, create=True), open_athrill(run_dir, create=True)
        unity.write_u32(Rx.PHYSICS_PID, os.getpid())
        program.prepare(run_dir)
        costs = []
        for seq in range(1, samples + 1):
            unity.write_u32(Rx.TEST_SEQ, seq)
            alive = sign_of_life(program, unity, athrill)
            start = time.perf_counter()
            if zygote is None:
                proc = program.spawn(run_dir, seq, log)
            else:
                proc = zygote.spawn(program.args(run_dir, seq)[len(MOCK_ARGV):],
                                    run_dir if program.in_run_dir else None)
            try:
                while not alive():
                    if proc.poll() is not None or time.perf_counter() - start > START_TIMEOUT_S:
                        raise RuntimeError(f"{program.description} did not start (exit {proc.returncode})")
                    time.sleep(0.0002)
                costs.append(time.perf_counter() - start)
            finally:
                proc.kill()
                proc.wait()
                if zygote is not None and proc.stdout is not None:
                    proc.stdout.close()
        if zygote is not None:
            zygote.close()
        unity.close()
        athrill.close()
    return costs


def ms(costs: list[float]) -> str:
    return f"{statistics.median(costs) * 1e3:8.1f} ms median (min {min(costs) * 1e3:.1f}, max {max(costs) * 1e3:.1f})"


def describe(results: list) -> str:
    events = sorted({r.event.name for r in results})
    laps = sorted({r.lap_time_s for r in results if r.lap_time_s is not None})
    return f"events {events}" + (f", laps {laps} s" if laps else "")


@click.command()
@click.option("--sim-seconds", default=60.0, show_default=True, help="Simulated seconds for (a).")
@click.option("--tests", default=5, show_default=True, help="Trials per program in (b), after a warm-up trial.")
@click.option("--starts", default=10, show_default=True, help="Process starts measured per program in (c).")
@click.option("--real-tests", type=click.IntRange(min=0), default=1, show_default=True,
              help="Trials of the real emulator in (d).")
@click.option("--athrill2", default=str(REPO / "build" / "athrill" / "athrill2"), show_default=True,
              help="The real TOPPERS emulator (scripts/build_athrill2.sh builds it).")
@click.option("--parts", default="abcdef", show_default=True,
              help="Which of the measures (a)..(f) to run, as their letters ((b) runs (a) for its ratio).")
@click.option("--rounds", type=click.IntRange(min=1), default=3, show_default=True,
              help="(e), (f): rounds of --tests trials, alternating between the two programs.")
def main(sim_seconds: float, tests: int, starts: int, real_tests: int, athrill2: str, parts: str,
         rounds: int) -> None:
    """Print simulated-seconds-per-wall-second and start costs as a table."""
    rows: list[tuple[str, str]] = []
    a_batched = 0.0
    if "a" in parts or "b" in parts:
        a_loop, a_batched = raw_rate(sim_seconds, batched=False), raw_rate(sim_seconds, batched=True)
        if "a" in parts:
            rows += [("(a) raw MuJoCo, one mj_step call per 1 ms step", f"{a_loop:8.1f} x real time"),
                     ("(a) raw MuJoCo, batched mj_step(nstep=100)", f"{a_batched:8.1f} x real time")]
    if parts.strip("aef"):
        rows += athrill_rows(parts, a_batched, tests, starts, real_tests, athrill2)
    if "e" in parts:
        rows += spike_rows(tests, rounds)
    if "f" in parts:
        rows += asp_rows(tests, rounds)
    width = max(len(name) for name, _ in rows)
    for name, value in rows:
        print(f"{name:<{width}} : {value}")


def athrill_rows(parts: str, a_batched: float, tests: int, starts: int, real_tests: int,
                 athrill2: str) -> list[tuple[str, str]]:
    """(b) trials (their rates against (a)'s batched raw MuJoCo, `a_batched`), (c) starts and (d) the real
    emulator's trials."""
    rows: list[tuple[str, str]] = []
    kinds = {"Python mock (line_trace)": BenchOptions(app="line_trace"),
             "native C (line_trace_c)": BenchOptions(app="line_trace_c"),
             "real athrill2 (ble_sample asp)": BenchOptions(app=str(ASP_IMAGE), athrill2=athrill2,
                                                             sync=RealSync.HAKONIWA)}
    programs: dict[str, Program | str] = {}
    for label, bench in kinds.items():
        try:
            programs[label] = resolve_program(bench.app, athrill2=bench.athrill2, sync=bench.sync)
        except ProgramError as e:
            programs[label] = f"skipped: {e}"

    rates = {}
    for label in list(kinds)[:2] if "b" in parts else []:
        program = programs[label]
        if isinstance(program, str):
            rows.append((f"(b) three-process trial, {label}", program))
            continue
        rates[label], results = trial_rate(kinds[label], tests)
        rows.append((f"(b) three-process trial, {label}, {tests} tests",
                     f"{rates[label]:8.1f} x real time = {rates[label] / a_batched:.2f} of batched raw "
                     f"({describe(results)})"))
    if len(rates) == 2:
        python, native = rates.values()
        rows.append(("(b) native C / Python mock trial rate", f"{native / python:8.2f}"))

    for label, program in programs.items() if "c" in parts else ():
        value = program if isinstance(program, str) else ms(start_costs(program, starts))
        rows.append((f"(c) start per test, {label}" + ("" if isinstance(program, str) else f", {starts} starts"),
                     value))
        if not isinstance(program, str) and program.forkable:  # how the bench starts it (athrill_sim.programs.zygote)
            rows.append((f"(c) start per test, {label}, forked from the zygote, {starts} starts",
                         ms(start_costs(program, starts, forked=True))))

    real = list(kinds)[2]
    real_program = programs[real]
    if "d" not in parts:
        pass
    elif isinstance(real_program, str):
        rows.append((f"(d) trial, {real}", real_program))
    elif real_tests > 0:
        rate, results = trial_rate(kinds[real], real_tests, warm_up=False)
        rows.append((f"(d) trial, {real}, hakoniwa sync, {real_tests} tests",
                     f"{rate:8.1f} sim-s per wall-s ({describe(results)}, "
                     f"{statistics.mean(r.distance_m for r in results):.2f} m)"))

    return rows


def spike_rows(tests: int, rounds: int) -> list[tuple[str, str]]:
    """(e): the two HackSPi tracers' trials, `rounds` rounds of `tests`, alternating, so that a change of the
    machine's load falls on both."""
    spike = {"sample_c5_spike": BenchOptions(app=str(SAMPLE_C5_SPIKE), robot="hackspi", scenario=FORCE_START),
             "spike_thread_tracer": BenchOptions(app=str(THREADED_TRACER), robot="hackspi", scenario=FORCE_START)}
    missing = [label for label, bench in spike.items() if not Path(bench.app).is_dir()]
    if missing:
        return [(f"(e) HackSPi trial, {label}", f"skipped: no {spike[label].app} (../shared)") for label in missing]
    rates = alternating_rates(spike, tests, rounds, "(e) HackSPi trial")
    return [*((name, value) for name, value, _ in rates.values()),
            ("(e) threaded tracer / sample_c5_spike trial rate",
             f"{rates['spike_thread_tracer'][2] / rates['sample_c5_spike'][2]:8.2f}")]


def asp_rows(tests: int, rounds: int) -> list[tuple[str, str]]:
    """(f): RasPike-ART's sample_c5_spike and team_spike_threads, each as its asp against the pty hub and
    natively, alternating."""
    if not RASPIKE_ART_SAMPLE.is_dir():
        return [("(f) RasPike-ART's asp, sample_c5_spike", f"skipped: no {RASPIKE_ART_SAMPLE} (../shared)")]
    rows: list[tuple[str, str]] = []
    for title, app in (("RasPike-ART's sample_c5_spike", RASPIKE_ART_SAMPLE), ("team_spike_threads", TEAM_THREADS)):
        native = BenchOptions(app=str(app), robot="hackspi", scenario=FORCE_START, course="etrobocon-r")
        asp = dataclasses.replace(native, emulator=Emulator.RASPIKE_ART)
        try:
            asp.program()  # built once, before any timing
        except ProgramError as e:
            rows.append((f"(f) {title}, asp", f"skipped: {e}"))
            continue
        rates = alternating_rates({"asp under qemu (--emulator raspike-art)": asp, "native": native}, tests, rounds,
                                  f"(f) {title}")
        asp_rate, native_rate = (rate for *_, rate in rates.values())
        rows += [*((name, value) for name, value, _ in rates.values()),
                 (f"(f) {title}: asp under qemu / native trial rate", f"{asp_rate / native_rate:8.2f}")]
    return rows


def alternating_rates(benches: dict[str, BenchOptions], tests: int, rounds: int,
                      title: str) -> dict[str, tuple[str, str, float]]:
    """Each bench's trial rate over `rounds` rounds of `tests`, the benches alternating so that a change of
    the machine's load falls on all: by label, its row (name, value) and its rate."""
    sim = dict.fromkeys(benches, 0.0)
    wall = dict.fromkeys(benches, 0.0)
    seen: dict[str, list] = {label: [] for label in benches}
    for _ in range(rounds):
        for label, bench in benches.items():
            one_rate, results = trial_rate(bench, tests)
            wall[label] += sum(r.wall_s for r in results)
            sim[label] += one_rate * sum(r.wall_s for r in results)
            seen[label] += results
    rates = {label: sim[label] / wall[label] for label in benches}
    return {label: (f"{title}, {label}, {rounds} x {tests} tests",
                    f"{rates[label]:8.1f} x real time ({describe(seen[label])})", rates[label]) for label in benches}


if __name__ == "__main__":
    sys.exit(main())
