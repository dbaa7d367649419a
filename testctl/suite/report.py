"""What `hako test` tells a person and a script: the table of cases against their expectations, the full
results as JSON, and, for each case, its lap distribution and (when it failed) the failing run's path."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from hakoniwa.wire.result import TestResult
from testctl.suite.cases import case_folder
from testctl.suite.run import CaseRun

PASS, FAIL = "pass", "FAIL"
LAPS_PNG = "laps.png"
TRAJECTORY_PNG = "trajectory.png"


def verdict(run: CaseRun) -> str:
    return PASS if run.passed else FAIL


def format_table(runs: Sequence[CaseRun]) -> str:
    """One row per expectation: case, verdict, the expectation and what was measured against it."""
    rows = [("case", "verdict", "expectation", "measured")]
    for run in runs:
        for i, check in enumerate(run.checks):
            rows.append((run.case.name if i == 0 else "", verdict(run) if i == 0 else "",
                         ("" if check.passed else "✗ ") + check.expectation, check.measured))
    widths = [max(len(r[k]) for r in rows) for k in range(3)]
    lines = ["  ".join(cell.ljust(w) for cell, w in zip(row, widths)) + "  " + row[3] for row in rows]
    failed = sum(not r.passed for r in runs)
    lines.append(f"{len(runs) - failed} of {len(runs)} cases passed"
                 + (f"; failing: {', '.join(r.case.name for r in runs if not r.passed)}" if failed else ""))
    return "\n".join(lines)


def case_dict(run: CaseRun, files: Sequence[Path]) -> dict[str, Any]:
    case = run.case
    return {
        "name": case.name, "verdict": verdict(run), "passed": run.passed,
        "bench": dataclasses.asdict(case.bench), "params": dict(case.named), "noise": case.noise,
        "checks": [dataclasses.asdict(c) for c in run.checks], "stats": run.stats.to_dict(),
        "runs": [{"seed": r.seed, "bench": r.bench, "wall_s": r.result.wall_s, **r.result.to_dict()} for r in run.runs],
        "files": [str(f) for f in files],
    }


def results_dict(test_file: Path, runs: Sequence[CaseRun], files: dict[str, list[Path]]) -> dict[str, Any]:
    return {"file": str(test_file), "passed": all(r.passed for r in runs),
            "cases": [case_dict(r, files.get(r.case.name, [])) for r in runs]}


def keep_case_files(out_dir: Path, run: CaseRun, worst: Callable[[CaseRun, Path], tuple[TestResult, Path]]
                    ) -> list[Path]:
    """Draw the case's lap distribution into OUT/CASE/; for a failing case also run its worst run again on
    a bench of its own in OUT/CASE/run (`worst`; the lockstep repeats a test to the microsecond) and keep
    that folder, with the path it drove drawn into OUT/CASE/trajectory.png."""
    from testctl.lap_figure import plot_lap_distribution

    folder = out_dir / case_folder(run.case.name)
    folder.mkdir(parents=True, exist_ok=True)
    files = [plot_lap_distribution(folder / LAPS_PNG, [r.result for r in run.runs],
                                   f"case {run.case.name}: {verdict(run)} on {len(run.runs)} noise draws")]
    if not run.passed:
        from hakoniwa.physics.course import load_course
        from hakoniwa.pictures.plot import draw_trajectory, read_trajectory
        from hakoniwa.wire.rundir import TRAJECTORY_FILE

        result, run_dir = worst(run, folder / "run")
        seed = run.worst_run().seed
        outcome = f"lap {result.lap_time_s:.2f} s" if result.lap_time_s is not None else result.event.name
        draw_trajectory(load_course(run.case.bench.course), read_trajectory(run_dir / TRAJECTORY_FILE),
                        folder / TRAJECTORY_PNG, title=f"case {run.case.name}, noise seed {seed}: {outcome}")
        from testctl.film import CASE_VIDEO, film_run

        video = film_run(run_dir, folder / CASE_VIDEO, f"case {run.case.name}, noise seed {seed}")
        files += [folder / TRAJECTORY_PNG, *([video] if video else []), run_dir]
    return files
