"""Whether the ET Robocon-style course costs the bench speed: simulated seconds per wall second of three-process
trials of the native C tracer (`line_trace_c`) on the oval and on `etrobocon-l`, in one run.

The two courses differ in what each physics step and snapshot costs: a mat four times the oval's size, a
colour image (three more channels looked up at each sensor snapshot), the sumo bottle (a free body with its
contacts in every MuJoCo step, and a ray at each snapshot) and no walls. Both benches run the same program
with the same time limit, so every test covers the same simulated time whatever the program does on the
course (on etrobocon-l, calibrated for the oval, it circles): the rate compares the physics, not the laps.
Rounds alternate between the courses so that a change in the machine's load falls on both; each bench's
own start is left out (once per campaign), as `benchmark_sim.py`, whose trials these are, leaves it out.
"""

from __future__ import annotations

import datetime as dt
import os
import platform

import click
from benchmark_sim import trial_rate  # scripts/ is on the path of a script run from it

from testctl.bench_options import BenchOptions

COURSES = ("oval", "etrobocon-l")


def round_of(course: str, tests: int, time_limit_s: float) -> tuple[float, float, list[str]]:
    """One bench on `course`: a warm-up test, then `tests` tests; (simulated s, wall s, events) of the latter."""
    rate, results = trial_rate(BenchOptions(course=course, app="line_trace_c", time_limit_s=time_limit_s), tests)
    wall = sum(r.wall_s for r in results)
    return rate * wall, wall, [r.event.name for r in results]


@click.command()
@click.option("--rounds", default=3, show_default=True, help="Rounds; each runs both courses, alternating.")
@click.option("--tests", default=3, show_default=True, help="Tests per course per round, after a warm-up test.")
@click.option("--time-limit", "time_limit_s", default=30.0, show_default=True,
              help="Simulated seconds of each test on both courses.")
def main(rounds: int, tests: int, time_limit_s: float) -> None:
    """Print each course's sim-s per wall-s and their ratio (the issue asks etrobocon-l >= 0.8 of the oval)."""
    totals = {c: [0.0, 0.0] for c in COURSES}
    events: dict[str, set[str]] = {c: set() for c in COURSES}
    for i in range(rounds):
        for course in COURSES if i % 2 == 0 else COURSES[::-1]:
            sim, wall, ev = round_of(course, tests, time_limit_s)
            totals[course][0] += sim
            totals[course][1] += wall
            events[course].update(ev)
    rate = {c: sim / wall for c, (sim, wall) in totals.items()}
    for course in COURSES:
        click.echo(f"{course:12s} {rate[course]:7.1f} sim-s per wall-s ({totals[course][0]:.0f} sim-s in "
                   f"{totals[course][1]:.1f} wall-s, events {sorted(events[course])})")
    click.echo(f"etrobocon-l / oval: {rate['etrobocon-l'] / rate['oval']:.2f}")
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    click.echo(f"{dt.date.today()}, {platform.node()}, {os.cpu_count()} CPUs, load average {load}")


if __name__ == "__main__":
    main()
