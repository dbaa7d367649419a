"""Killing a campaign at any moment loses no finished test, and resuming it reproduces the uninterrupted run."""

from __future__ import annotations

import dataclasses
import tempfile
from functools import cache
from pathlib import Path

import pytest

from testctl.campaign.journal import JOURNAL_FILE, JournalError, TestRecord, read_journal
from testctl.campaign.loop import Campaign, CampaignConfig, load_config
from testctl.search.space import Parameter, ParameterSpace
from tests.helpers.campaign_doubles import Killed, KilledAfter, SyntheticBench

# 4 sets of 2 tests each (the synthetic bench is deterministic, so every set is 2-0 or 0-2).
CONFIGS = {
    "random": CampaignConfig(init_points=2, trials=2, repeats=3, seed=7, optimizer="random"),
    "gpyopt": CampaignConfig(init_points=2, trials=2, repeats=3, seed=7, optimizer="gpyopt"),
}


def essence(records: list[TestRecord]) -> list[tuple]:
    """What must match between runs: everything but the clock, in (set, repetition) order (tests on several
    benches finish in any order)."""
    return sorted((r.set_index, r.phase, sorted(r.params.items()), r.rep, r.noise_seed, r.result.event,
                   r.result.goal_time_us) for r in records)


@cache
def reference(optimizer: str, trials: int | None = None) -> list[tuple]:
    """The journal of an uninterrupted run (computed once per configuration)."""
    config = CONFIGS[optimizer]
    if trials is not None:
        config = dataclasses.replace(config, trials=trials)
    with tempfile.TemporaryDirectory() as out:
        Campaign(config, Path(out), SyntheticBench()).run()
        return essence(read_journal(Path(out) / JOURNAL_FILE)[1])


def resume(config: CampaignConfig, out: Path) -> SyntheticBench:
    bench = SyntheticBench()
    summary = Campaign(config, out, bench, resume=True).run()
    assert len(summary.sets) == config.total_sets
    assert summary.tests_run == len(bench.calls)
    return bench


@pytest.mark.parametrize(
    "optimizer, k", [("random", 0), ("random", 1), ("random", 2), ("random", 5), ("gpyopt", 5), ("gpyopt", 6)]
)
def test_kill_during_a_test_then_resume(tmp_path: Path, optimizer: str, k: int) -> None:
    config = CONFIGS[optimizer]
    with pytest.raises(Killed):
        Campaign(config, tmp_path, KilledAfter(SyntheticBench(), k)).run()
    assert len(read_journal(tmp_path / JOURNAL_FILE)[1]) == k  # every finished test is on disk
    bench = resume(config, tmp_path)
    ref = reference(optimizer)
    assert len(bench.calls) == len(ref) - k  # nothing redone, nothing skipped
    assert essence(read_journal(tmp_path / JOURNAL_FILE)[1]) == ref


@pytest.mark.parametrize("optimizer, k", [("random", 3), ("gpyopt", 5)])
def test_torn_journal_then_resume(tmp_path: Path, optimizer: str, k: int) -> None:
    """A kill in the middle of writing test k + 1: the journal ends with half a line."""
    config = CONFIGS[optimizer]
    full = tmp_path / "full"
    Campaign(config, full, SyntheticBench()).run()
    lines = (full / JOURNAL_FILE).read_bytes().split(b"\n")
    out = tmp_path / "killed"
    out.mkdir()
    (out / JOURNAL_FILE).write_bytes(b"\n".join(lines[: k + 1]) + b"\n" + lines[k + 1][:25])
    bench = resume(config, out)
    assert len(bench.calls) == len(reference(optimizer)) - k
    assert essence(read_journal(out / JOURNAL_FILE)[1]) == reference(optimizer)


def test_resume_can_extend_the_number_of_trials(tmp_path: Path) -> None:
    config = CONFIGS["random"]
    Campaign(config, tmp_path, SyntheticBench()).run()
    resume(dataclasses.replace(config, trials=4), tmp_path)
    assert essence(read_journal(tmp_path / JOURNAL_FILE)[1]) == reference("random", trials=4)


def test_resume_of_a_finished_campaign_runs_nothing(tmp_path: Path) -> None:
    config = CONFIGS["random"]
    first = Campaign(config, tmp_path, SyntheticBench()).run()
    assert load_config(tmp_path) == config
    bench = SyntheticBench()
    again = Campaign(load_config(tmp_path), tmp_path, bench, resume=True).run()
    assert bench.calls == []
    assert again.sets == first.sets and again.n_tests == first.n_tests


def test_resume_refuses_another_space(tmp_path: Path) -> None:
    config = CONFIGS["random"]
    with pytest.raises(Killed):
        Campaign(config, tmp_path, KilledAfter(SyntheticBench(), 3)).run()
    default = ParameterSpace.default()
    other = dataclasses.replace(default, params=(*default.params[:2], Parameter("Kd", 548, 0.0, 4.0)))
    with pytest.raises(JournalError, match=r"different parameter space .*Kd@548\[0,5\].*Kd@548\[0,4\]"):
        Campaign(dataclasses.replace(config, space=other), tmp_path, SyntheticBench(), resume=True).run()


def test_resume_refuses_other_options(tmp_path: Path) -> None:
    config = CONFIGS["random"]
    with pytest.raises(Killed):
        Campaign(config, tmp_path, KilledAfter(SyntheticBench(), 3)).run()
    with pytest.raises(JournalError, match=r"seed 7 \(journal\) vs 8 \(given\); optimizer 'random'"):
        changed = dataclasses.replace(config, seed=8, optimizer="gpyopt")
        Campaign(changed, tmp_path, SyntheticBench(), resume=True).run()
