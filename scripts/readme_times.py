"""How long the README's quick-start commands take, idle and with one core busy: the ranges the README states.

Usage: python scripts/readme_times.py [--command campaign --command fast --command full] [--runs N]
                                       [--condition idle --condition busy]

Each command runs as the README gives it, from this checkout, in a fresh temporary folder for its output:
`campaign` is `hako run --trials 100 --out runs/paper`; `full` is the test command CI runs,
`python -m pytest -m "slow or not slow" -q`; `fast` is its variant without the slow end-to-end tests,
`python -m pytest -m "not slow" -q`. `busy` runs a burner process (one core at 100 %, a stand-in for the
other job a user's machine has) beside the command. Each time printed is the command's whole wall time in
minutes, with the load average before it started and the machine's CPU count, so the conditions are on
record with the numbers. A run that fails is timed too (a failing test costs about what a passing one does),
and said with its failures beside its time; the script then exits 1.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import click

REPO = Path(__file__).resolve().parent.parent
PYTEST = [sys.executable, "-m", "pytest", "-q"]
COMMANDS = {  # the README's commands as it gives them, and whether they run in a scratch folder (the tests
    # run in the checkout, as a user runs them)
    "campaign": ("hako run --trials 100 --out runs/paper",
                 [sys.executable, "-m", "testctl.hako", "run", "--trials", "100", "--out", "runs/paper"], True),
    "fast": ('python -m pytest -m "not slow" -q', [*PYTEST, "-m", "not slow"], False),
    "full": ('python -m pytest -m "slow or not slow" -q', [*PYTEST, "-m", "slow or not slow"], False),
}
BURNER = [sys.executable, "-c", "while True: pass"]  # one core busy, as another job would keep it


def as_from_a_terminal() -> None:
    """preexec_fn: SIGINT's default action, as a command typed at a terminal has it, even when this script runs
    as a shell's background job (which starts it ignored, and every child would inherit that)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def timed(argv: list[str], in_scratch: bool, busy: bool) -> tuple[float, str | None]:
    """The wall minutes of `argv`, run in a fresh folder or the checkout (with the burner beside it when
    `busy`), and what failed (None if it succeeded)."""
    burner = subprocess.Popen(BURNER) if busy else None
    try:
        with tempfile.TemporaryDirectory(prefix="readme-times-") as work:
            start = time.monotonic()
            r = subprocess.run(argv, cwd=work if in_scratch else REPO, capture_output=True, text=True,
                               preexec_fn=as_from_a_terminal)
            wall = time.monotonic() - start
    finally:
        if burner is not None:
            burner.kill()
            burner.wait()
    if r.returncode == 0:
        return wall / 60, None
    lines = (r.stdout + r.stderr).strip().splitlines()
    failed = [line for line in lines if line.startswith("FAILED ")]  # pytest's short summary
    return wall / 60, f"exit {r.returncode}: " + "; ".join(failed + lines[-1:] if lines else ["no output"])


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--command", "commands", type=click.Choice(list(COMMANDS)), multiple=True,
              default=("campaign", "fast"), show_default=True, help="Which README command to time (repeatable).")
@click.option("--condition", "conditions", type=click.Choice(["idle", "busy"]), multiple=True,
              default=("idle", "busy"), show_default=True, help="Idle, or one core busy with a burner (repeatable).")
@click.option("--runs", type=click.IntRange(min=1), default=1, show_default=True,
              help="Runs per command and condition.")
def main(commands: tuple[str, ...], conditions: tuple[str, ...], runs: int) -> None:
    """Time the README's commands and print each run and each command's range, in minutes."""
    failures = 0
    for name in commands:
        shown, argv, in_scratch = COMMANDS[name]
        times = []
        for condition in conditions:
            for _ in range(runs):
                load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
                minutes, failed = timed(argv, in_scratch, condition == "busy")
                times.append(minutes)
                failures += failed is not None
                print(f"{shown}: {minutes:.1f} min ({condition}; load average {load} before, "
                      f"{os.cpu_count()} CPUs){f'; FAILED, {failed}' if failed else ''}", flush=True)
        print(f"{shown}: {min(times):.1f}-{max(times):.1f} min over {len(times)} runs "
              f"({', '.join(conditions)})", flush=True)
    if failures:
        sys.exit(1)


if __name__ == "__main__":
    main()
