"""What a campaign leaves for people: results.csv, best.json, and the paper's Fig. 8 and Fig. 9 as PNGs.

Everything here is computed from the campaign summary, so a report can be rewritten from a journal at any
time (`Campaign(..., resume=True).run()` on a finished campaign runs no test and returns the summary), and
nothing depends on the clock or on which bench ran what: the same campaign gives the same results.csv and
best.json wherever it ran (wall times stay in the journal). Sets are numbered from 1 everywhere.
Figures are drawn on a bare `matplotlib.figure.Figure` (Agg), never through pyplot's global state, so this
works headless and inside a long-running process.
"""

from __future__ import annotations

import csv
import json
from itertools import accumulate
from pathlib import Path
from typing import Any

from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from testctl.campaign.loop import PHASE_INIT, CampaignSummary, SetResult
from testctl.campaign.patch import BEST_JSON

RESULTS_CSV = "results.csv"
FIG8_PNG = "fig8.png"
FIG9_PNG = "fig9.png"
# The paper's colours for Kp, Ki, Kd (Fig. 8); further parameters take matplotlib's cycle.
_PARAM_COLOURS = ("red", "blue", "green")


def write_report(out_dir: Path, summary: CampaignSummary, patch: dict[str, Any] | None = None) -> list[Path]:
    """Write all four files into `out_dir` and return their paths; `patch` is what best.patch does."""
    out_dir = Path(out_dir)
    paths = [out_dir / RESULTS_CSV, out_dir / BEST_JSON, out_dir / FIG8_PNG, out_dir / FIG9_PNG]
    write_results_csv(paths[0], summary)
    write_best_json(paths[1], summary, patch=patch)
    plot_fig8(paths[2], summary)
    plot_fig9(paths[3], summary)
    return paths


def best_so_far(sets: tuple[SetResult, ...]) -> list[float]:
    """The lowest objective value up to and including each set (Fig. 9, bottom)."""
    return list(accumulate((s.value for s in sets), min))


def l1_changes(sets: tuple[SetResult, ...]) -> list[float]:
    """|x_i - x_(i-1)|_1 for each set after the first (Fig. 9, top): how far the search still moves."""
    return [sum(abs(a - b) for a, b in zip(cur.x, prev.x)) for prev, cur in zip(sets, sets[1:])]


def write_results_csv(path: Path, summary: CampaignSummary) -> None:
    """One row per decided parameter set."""
    names = summary.config.space.names
    best = best_so_far(summary.sets)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        m = summary.config.measure
        suffix = "_s" if m.unit == "s" else ""  # the columns are named for what they hold: seconds or a score
        w.writerow(
            ["set", "phase", *names, "tests", "successes", "failures", "crashes", "success", f"objective{suffix}",
             f"best_so_far{suffix}"]
        )
        for s, b in zip(summary.sets, best):
            v = s.verdict
            w.writerow(
                [s.number, s.phase, *(repr(c) for c in s.x), len(s.tests), v.successes, v.failures, v.crashes,
                 int(v.success), repr(m.shown(s.value)), repr(m.shown(b))]
            )


def write_best_json(path: Path, summary: CampaignSummary, validation: dict[str, Any] | None = None,
                    patch: dict[str, Any] | None = None) -> None:
    path.write_text(json.dumps(best_dict(summary, validation, patch), indent=2) + "\n")


def best_dict(summary: CampaignSummary, validation: dict[str, Any] | None = None,
              patch: dict[str, Any] | None = None) -> dict[str, Any]:
    """best.json: the best set's parameters (searched and fixed, by name and by slot offset) and lap, how
    each reaches the program (`kinds`), how it fared on fresh noise draws (`testctl.campaign.validate`) once it was
    validated, and what best.patch sets where."""
    space = summary.config.space
    best = summary.best
    m = summary.config.measure
    value = ({"lap_time_s": best.value if best else None, "laps_s": list(best.verdict.laps) if best else None}
             if m.time else
             {m.word: m.shown(best.value) if best else None,
              f"{m.word}s": [m.shown(v) for v in best.verdict.laps] if best else None})
    return {
        "success": best is not None,
        "set": best.number if best else None,
        "params": space.to_named(best.x) if best else None,
        "fixed": {f.name: f.value for f in space.fixed},
        "offsets": {str(k): v for k, v in space.to_offsets(best.x).items()} if best else None,
        "kinds": {p.name: p.to_dict() for p in space.every},
        **value,
        "n_sets": len(summary.sets),
        "n_tests": summary.n_tests,
        "bench_faults": summary.bench_faults,
        "bench_causes": dict(summary.bench_causes),
        "seed": summary.config.seed,
        "optimizer": summary.config.optimizer,
        "batch": summary.config.batch,
        "noise": summary.config.noise,
        **({"validation": validation} if validation is not None else {}),
        **({"patch": patch} if patch is not None else {}),
    }


def format_summary(summary: CampaignSummary) -> str:
    """The lines `hako run` prints at the end."""
    best = summary.best
    if best is None:
        best_line = "best: no parameter set succeeded"
    else:
        params = ", ".join(f"{k}={v:.3f}" for k, v in summary.config.space.to_named(best.x).items())
        best_line = f"best: [{params}] {summary.config.measure.format(best.value)} (set {best.number})"
    return "\n".join(
        [
            best_line,
            f"sets: {len(summary.sets)}, tests: {summary.n_tests} ({summary.tests_run} this run)",
            *filter(None, [summary.describe_bench_faults()]),
            f"wall time: {summary.wall_s:.1f} s this run, {summary.test_wall_s:.1f} s in tests overall",
        ]
    )


def _iteration_axes(fig: Figure, summary: CampaignSummary, *labels: str) -> list[Any]:
    """Stacked axes over the set number (from 1, the paper's 'iteration'), initial design shaded."""
    axes = list(fig.subplots(len(labels), 1, sharex=True, squeeze=False)[:, 0])
    n_init = sum(s.phase == PHASE_INIT for s in summary.sets)
    for ax, label in zip(axes, labels):
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        if n_init:
            ax.axvspan(0.5, n_init + 0.5, color="0.9", zorder=0, label="initial random design")
    axes[-1].set_xlabel("parameter set (iteration)")
    axes[-1].xaxis.set_major_locator(MaxNLocator(integer=True))
    return axes


def param_colour(i: int) -> str:
    """Kp, Ki, Kd in the paper's red, blue, green; further parameters in colours none of those takes."""
    return _PARAM_COLOURS[i] if i < len(_PARAM_COLOURS) else f"C{i + 1}"  # C3 is matplotlib's red


def plot_fig8(path: Path, summary: CampaignSummary) -> None:
    fig8(summary).savefig(path, dpi=100)


def fig8(summary: CampaignSummary) -> Figure:
    """Fig. 8: the searched values per iteration (Kp red, Ki blue, Kd green), one panel per parameter since
    their ranges differ (gains in 0..5, a motor power in 10..30), and the lap time (or ET Robocon's score) per
    iteration (failed sets drawn as crosses at the penalty)."""
    names = summary.config.space.names
    m = summary.config.measure
    fig = Figure(figsize=(8, 2.5 + 1.5 * len(names)), layout="constrained")
    *ax_params, ax_lap = _iteration_axes(fig, summary, *names, m.label)
    its = [s.number for s in summary.sets]
    for i, (ax, name) in enumerate(zip(ax_params, names)):
        ax.plot(its, [s.x[i] for s in summary.sets], ".-", color=param_colour(i), label=name, lw=1)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1))
    ok = [s for s in summary.sets if s.verdict.success]
    failed = [s for s in summary.sets if not s.verdict.success]
    penalty = m.shown(summary.config.rule.failure_value)
    ax_lap.plot(its, [m.shown(s.value) for s in summary.sets], "-", color="0.6", lw=0.8)
    ax_lap.plot([s.number for s in ok], [m.shown(s.value) for s in ok], "o", color="black", ms=4,
                label=f"success (mean {m.word})")
    ax_lap.plot([s.number for s in failed], [m.shown(s.value) for s in failed], "x", color="red",
                label=f"failure (scored {penalty:g} {m.unit})")
    ax_lap.axhline(penalty, color="red", ls=":", lw=0.8)
    ax_lap.legend(loc="upper left", bbox_to_anchor=(1.01, 1))
    fig.suptitle(f"Search values of the control parameters and {m.name}")
    return fig


def plot_fig9(path: Path, summary: CampaignSummary) -> None:
    """Fig. 9: the total parameter change |dx|_1 per iteration and the best objective so far."""
    fig = Figure(figsize=(8, 6), layout="constrained")
    m = summary.config.measure
    ax_change, ax_best = _iteration_axes(fig, summary, "|Δx|₁", f"best {m.word} so far [{m.unit}]")
    its = [s.number for s in summary.sets]
    ax_change.plot(its[1:], l1_changes(summary.sets), ".-", color="purple", lw=1, label="|Δx|₁ from the set before")
    ax_best.step(its, [m.shown(b) for b in best_so_far(summary.sets)], where="post", color="black",
                 label=f"best objective so far ({m.better} {m.name})")
    for ax in (ax_change, ax_best):
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1))
    fig.suptitle("Total parameter change and best solution so far")
    fig.savefig(path, dpi=100)
