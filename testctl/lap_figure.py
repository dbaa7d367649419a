"""The picture of a parameter set's robustness: how its laps spread over fresh noise draws, against what the
campaign believed of it. Drawn on a bare Figure (Agg), as the campaign's figures are."""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from pathlib import Path

from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from hakoniwa.wire.result import TestResult
from testctl.lapstats import LapStats


def plot_lap_distribution(path: Path, results: Sequence[TestResult], title: str,
                          estimate_s: float | None = None) -> Path:
    lap_figure(results, title, estimate_s).savefig(path, dpi=100)
    return path


def lap_figure(results: Sequence[TestResult], title: str, estimate_s: float | None = None) -> Figure:
    """Histogram of the laps, the reported quantiles, and (for a campaign's best set) the campaign's estimate:
    the mean lap of the few tests that chose it. Runs without a lap are counted in the legend."""
    stats = LapStats.of(results)
    fig = Figure(figsize=(10, 4.5), layout="constrained")
    ax = fig.subplots()
    if stats.laps_s:
        ax.hist(stats.laps_s, bins=min(20, max(5, len(stats.laps_s) // 2)), color="steelblue", alpha=0.8,
                label=f"lap of a run that reached {stats.reached} ({stats.successes} of {stats.runs})")
    for (p, q), style in zip(stats.quantiles_s.items(), (":", "--")):
        if q is not None:
            ax.axvline(q, color="black", ls=style, lw=1.2, label=f"p{p} of all runs: {q:.2f} s")
    if estimate_s is not None:
        ax.axvline(estimate_s, color="crimson", lw=2, label=f"campaign's estimate (mean lap): {estimate_s:.2f} s")
    missed = Counter(r.event.name for r in results if not r.success)
    if missed:  # an empty plot entry, so that the legend says it
        ax.plot([], [], " ", label="no lap: " + ", ".join(f"{n} {event}" for event, n in sorted(missed.items())))
    ax.set_xlabel("lap time [s]")
    ax.set_ylabel("runs")
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=9)
    fig.suptitle(title)
    return fig
