"""How robust a campaign's best set really is: the set tested again on fresh noise draws.

A campaign decides a set on 3 to 5 tests, first to a majority, and reports the mean of their laps; that says
little about how often the set fails on the robot. So `hako run` ends by running the best set on
`--validate N` further draws and reporting its success rate and lap quantiles (`testctl.lapstats`) beside
the campaign's estimate. The draws continue the best set's own repetitions past the campaign's `repeats`,
numbers no test of the campaign ever used: fresh, and yet the same for the same campaign, so a resumed or
re-run campaign validates on the same draws. Each draw goes to the campaign's journal as it finishes
(phase `validation`, which the campaign's search never reads), so an interrupted validation resumes with
the draws it lacks.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from hakoniwa.wire.measure import LAP_TIME, Measure
from hakoniwa.wire.result import TestResult
from testctl.campaign.journal import JOURNAL_FILE, PHASE_VALIDATION, Journal, TestRecord, now_timestamp
from testctl.executor import Executor, TestSpec, bench_fault, results_of
from testctl.lapstats import LapStats
from testctl.noise_seed import noise_seed

if TYPE_CHECKING:
    from testctl.campaign.loop import CampaignSummary  # NumPy: not for `hako --help`

VALIDATION_PNG = "validation.png"


@dataclass(frozen=True)
class Validation:
    seeds: tuple[int, ...]
    results: tuple[TestResult, ...]  # in draw order
    estimate_s: float  # what the campaign made of the set: the mean of its tests' values (`measure`)
    measure: Measure = LAP_TIME

    @property
    def stats(self) -> LapStats:
        return LapStats.of(self.results)

    @property
    def scores(self) -> list[float]:
        """ET Robocon's score of each draw (a crash scores none)."""
        return [r.score.total for r in self.results if r.score is not None]

    def to_dict(self) -> dict:
        if self.measure.time:
            value: dict[str, Any] = {"campaign_estimate_s": self.estimate_s}
        else:
            value = {"scores": self.scores, "campaign_estimate": self.measure.shown(self.estimate_s)}
        return {"draws": len(self.seeds), **self.stats.to_dict(), **value,
                "events": dict(Counter(r.event.name for r in self.results)), "noise_seeds": list(self.seeds)}

    def describe(self) -> str:
        scores = self.scores
        mean = f"score mean {sum(scores) / len(scores):.2f} (min {min(scores):g}, max {max(scores):g}); " \
            if scores else ""
        estimate = f"{self.estimate_s:.2f} s" if self.measure.time else self.measure.format(self.estimate_s)
        return (f"validation on {len(self.seeds)} fresh noise draws: {mean}{self.stats.describe()} "
                f"(the campaign's estimate: {estimate})")


def validation_specs(summary: CampaignSummary, draws: int) -> list[TestSpec]:
    best, config = summary.best, summary.config
    assert best is not None
    params = config.space.to_offsets(best.x)
    reps = range(config.repeats + 1, config.repeats + 1 + draws)
    return [TestSpec(best.index, rep, params, noise_seed(config.seed, best.index, rep), config.noise,
                     config.space.slot_types) for rep in reps]


def validate_best(summary: CampaignSummary, executor: Executor, draws: int, out_dir: Path,
                  on_result: Callable[[TestSpec, TestResult], None] = lambda spec, result: None) -> Validation:
    """Run the best set on the `draws` fresh noise draws that `out_dir`'s journal lacks, journaling each
    (a bench fault is journaled, and stops it: `testctl.executor.BenchFault`). `on_result` hears of every draw,
    the journaled ones first."""
    best = summary.best
    assert best is not None
    specs = validation_specs(summary, draws)
    with Journal.open(out_dir / JOURNAL_FILE) as journal:
        done = {r.rep: r.result for r in journal.records
                if r.phase == PHASE_VALIDATION and r.set_index == best.index and not r.result.bench_fault}
        for spec in specs:
            if spec.rep in done:
                on_result(spec, done[spec.rep])
        named = summary.config.space.to_named(best.x)
        for spec, result, bench in results_of(executor, (s for s in specs if s.rep not in done)):
            journal.append(TestRecord(best.index, PHASE_VALIDATION, named, spec.rep, result, now_timestamp(),
                                      spec.noise_seed, bench), keep=False)
            if result.bench_fault:
                raise bench_fault(result, bench)
            done[spec.rep] = result
            on_result(spec, result)
    return Validation(tuple(s.noise_seed for s in specs), tuple(done[s.rep] for s in specs), best.value,
                      summary.config.measure)


def draw_validation(path: Path, summary: CampaignSummary, validation: Validation) -> Path:
    from testctl.lap_figure import plot_lap_distribution

    best = summary.best
    assert best is not None
    names = " ".join(f"{k}={v:.3f}" for k, v in summary.config.space.to_named(best.x).items())
    # The figure is of laps: the campaign's estimate is one only when the campaign's value is a time.
    estimate = validation.estimate_s if validation.measure.time else None
    return plot_lap_distribution(path, validation.results, f"best set {best.number} ({names}) on "
                                 f"{len(validation.seeds)} fresh noise draws", estimate)
