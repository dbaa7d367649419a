"""Simulated seconds per wall second: raw MuJoCo stepping vs. the full three-process trial.

(a) steps the very model the physics process uses, in this process, with constant motor commands: what
    MuJoCo alone costs. Both the one-call-per-step loop and MuJoCo's batched `nstep` are shown.
(b) runs real tests: a `hakoniwa-physics` process (which starts a fresh `athrill-sim` per test) driven by
    this script acting as the test controller over the mapped files. Process start-up of the physics
    process is excluded (it happens once per campaign); Athrill's start-up is included (once per test).
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import click
import mujoco

from hakoniwa.course import load_course
from hakoniwa.launch import physics_command
from hakoniwa.world import World
from testctl.paper import BEST_GAINS, line_trace_params
from testctl.runner import TrialRunner

PAPER = line_trace_params(*BEST_GAINS)


def raw_rate(sim_s: float, batched: bool) -> float:
    world = World(load_course())
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


def trial_rate(tests: int, params: dict[int, float]) -> tuple[float, list]:
    with tempfile.TemporaryDirectory(prefix="hako-bench-") as tmp:
        run_dir = Path(tmp)
        proc = subprocess.Popen(physics_command(run_dir, "oval", []))
        try:
            runner = TrialRunner.attach(run_dir, proc)
            runner.run_test(params)  # warm-up: first spare Athrill, caches
            results = [runner.run_test(params) for _ in range(tests)]
            runner.end()
            proc.wait(timeout=30)
        finally:
            if proc.poll() is None:
                proc.kill()
    sim = sum((r.goal_time_us or load_course().time_limit_us) for r in results) / 1e6
    wall = sum(r.wall_s for r in results)
    return sim / wall, results


@click.command()
@click.option("--sim-seconds", default=60.0, show_default=True, help="Simulated seconds for (a).")
@click.option("--tests", default=5, show_default=True, help="Tests for (b), after one warm-up test.")
def main(sim_seconds: float, tests: int) -> None:
    """Print simulated-seconds-per-wall-second of (a) raw MuJoCo and (b) full three-process trials."""
    a_loop = raw_rate(sim_seconds, batched=False)
    a_batched = raw_rate(sim_seconds, batched=True)
    b, results = trial_rate(tests, PAPER)
    events = {r.event.name for r in results}
    laps = {r.lap_time_s for r in results}
    print(f"(a) raw MuJoCo, one mj_step call per 1 ms step : {a_loop:7.1f} x real time")
    print(f"(a) raw MuJoCo, batched mj_step(nstep=100)     : {a_batched:7.1f} x real time")
    print(f"(b) three-process trial (paper gains, {tests} tests) : {b:7.1f} x real time "
          f"(events {sorted(events)}, lap times {sorted(laps)})")
    print(f"(b)/(a) vs. one call per step                  : {b / a_loop:7.2f}")
    print(f"(b)/(a) vs. batched                             : {b / a_batched:7.2f}")


if __name__ == "__main__":
    sys.exit(main())
