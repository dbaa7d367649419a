"""A campaign on several benches: the same sets and results whatever the number of benches and whatever order
tests finish in, and bench faults that are rerun, never scored, and stop a campaign when they do not stop."""

from __future__ import annotations

import random
from collections.abc import Callable
from pathlib import Path

import pytest

from hakoniwa.wire.result import TestResult
from testctl.campaign.journal import JOURNAL_FILE, read_journal
from testctl.campaign.loop import MAX_BENCH_FAULTS_IN_A_ROW, BenchBroken, Campaign, CampaignConfig
from testctl.executor import Executor, TestSpec
from tests.helpers.campaign_doubles import BENCH_FAULT, Killed, SyntheticBench


class ShuffledExecutor(Executor):
    """`capacity` benches that finish their tests in a random order."""

    def __init__(self, run_test: Callable[[TestSpec], TestResult], capacity: int, seed: int) -> None:
        self.run_test = run_test
        self.capacity = capacity
        self.rng = random.Random(seed)
        self.queue: list[TestSpec] = []
        self.max_running = 0

    def submit(self, spec: TestSpec) -> None:
        self.queue.append(spec)
        self.max_running = max(self.max_running, self.running)

    def next_result(self) -> tuple[TestSpec, TestResult, str]:
        i = self.rng.randrange(min(len(self.queue), self.capacity))
        spec = self.queue.pop(i)
        return spec, self.run_test(spec), f"bench{i}"

    @property
    def running(self) -> int:
        return min(len(self.queue), self.capacity)


class NoisyBench(SyntheticBench):
    """The synthetic bench with a seeded wobble: repetitions of a set differ, as on the noisy bench."""

    def __call__(self, spec: TestSpec) -> TestResult:
        r = super().__call__(spec)
        if r.success:
            wobble = (spec.noise_seed % 1000) * 1000  # up to 1 s
            return TestResult(r.event, r.goal_time_us + wobble, r.wall_s)
        return r


class FaultyBench(NoisyBench):
    """Spoils the first attempt of some tests, as a bench whose files someone damaged would."""

    def __init__(self) -> None:
        super().__init__()
        self.spoiled: set[tuple[int, int]] = set()

    def __call__(self, spec: TestSpec) -> TestResult:
        key = (spec.set_index, spec.rep)
        if (spec.set_index + spec.rep) % 3 == 0 and key not in self.spoiled:
            self.spoiled.add(key)
            self.calls.append(spec)
            return BENCH_FAULT
        return super().__call__(spec)


CONFIG = CampaignConfig(init_points=4, trials=6, repeats=5, seed=11, optimizer="gpyopt", batch=3, noise=1.0)


def essence(out: Path) -> list[tuple]:
    _, records = read_journal(out / JOURNAL_FILE)
    return sorted((r.set_index, r.rep, r.noise_seed, sorted(r.params.items()), r.result.event,
                   r.result.goal_time_us) for r in records if not r.result.bench_fault)


@pytest.fixture(scope="module")
def serial(tmp_path_factory) -> tuple[Path, object]:
    out = tmp_path_factory.mktemp("serial")
    return out, Campaign(CONFIG, out, NoisyBench()).run()


@pytest.mark.parametrize("benches, seed", [(2, 0), (4, 1), (8, 2)])
def test_benches_and_finishing_order_do_not_change_the_results(tmp_path, serial, benches, seed):
    ex = ShuffledExecutor(NoisyBench(), benches, seed)
    summary = Campaign(CONFIG, tmp_path, ex).run()
    serial_out, serial_summary = serial
    assert ex.max_running == benches  # tests really ran side by side
    assert essence(tmp_path) == essence(serial_out)
    assert [(s.x, s.value) for s in summary.sets] == [(s.x, s.value) for s in serial_summary.sets]


def test_repetitions_differ_with_noise(serial):
    _, summary = serial
    laps = [s.verdict.laps for s in summary.sets if s.verdict.success]
    assert any(len(set(v)) > 1 for v in laps)


def test_bench_faults_are_journaled_rerun_and_never_scored(tmp_path, serial):
    bench = FaultyBench()
    summary = Campaign(CONFIG, tmp_path, ShuffledExecutor(bench, 3, 5)).run()
    serial_out, serial_summary = serial
    assert essence(tmp_path) == essence(serial_out)  # the same results, as if nothing had happened
    assert summary.bench_faults == len(bench.spoiled) > 0
    _, records = read_journal(tmp_path / JOURNAL_FILE)
    faults = [r for r in records if r.result.bench_fault]
    assert len(faults) == len(bench.spoiled)
    assert all(any(o.rep == f.rep and o.set_index == f.set_index and not o.result.bench_fault for o in records)
               for f in faults)  # each spoiled repetition ran again
    assert [s.value for s in summary.sets] == [s.value for s in serial_summary.sets]


def test_resume_reruns_a_spoiled_test(tmp_path, serial):
    class SpoilThenKill(NoisyBench):
        def __init__(self) -> None:
            super().__init__()
            self.n = 0

        def __call__(self, spec: TestSpec) -> TestResult:
            self.n += 1
            if self.n == 4:
                self.calls.append(spec)
                return BENCH_FAULT
            if self.n == 5:
                raise Killed
            return super().__call__(spec)

    with pytest.raises(Killed):
        Campaign(CONFIG, tmp_path, SpoilThenKill()).run()
    _, before = read_journal(tmp_path / JOURNAL_FILE)
    assert [r.result.bench_fault for r in before] == [False, False, False, True]
    Campaign(CONFIG, tmp_path, NoisyBench(), resume=True).run()
    assert essence(tmp_path) == essence(serial[0])


def test_a_bench_that_keeps_failing_stops_the_campaign(tmp_path):
    with pytest.raises(BenchBroken, match=f"failed {MAX_BENCH_FAULTS_IN_A_ROW} tests in a row"):
        Campaign(CONFIG, tmp_path, lambda spec: BENCH_FAULT).run()
    _, records = read_journal(tmp_path / JOURNAL_FILE)
    assert len(records) == MAX_BENCH_FAULTS_IN_A_ROW and all(r.result.bench_fault for r in records)


def test_a_longer_batch_round_extends_exactly(tmp_path):
    """Extending a campaign whose last round was cut short proposes what a longer campaign would have."""
    short = CampaignConfig(init_points=2, trials=2, repeats=1, seed=3, optimizer="gpyopt", batch=3, noise=0.0)
    long = CampaignConfig(init_points=2, trials=5, repeats=1, seed=3, optimizer="gpyopt", batch=3, noise=0.0)
    Campaign(short, tmp_path / "a", SyntheticBench()).run()
    extended = Campaign(long, tmp_path / "a", SyntheticBench(), resume=True).run()
    fresh = Campaign(long, tmp_path / "b", SyntheticBench()).run()
    assert [s.x for s in extended.sets] == [s.x for s in fresh.sets]


@pytest.mark.parametrize("k", [1, 2, 3, 5, 8, 13])
def test_resume_after_a_kill_with_repetitions_out_of_order(tmp_path, serial, k):
    """Killed while a set's repetitions ran side by side and a later one had finished first: the resumed
    campaign runs the missing repetitions, not new ones after the last, so its journal is the uninterrupted
    one (with noise, a repetition's number is its noise)."""

    class KillAfter(NoisyBench):
        def __call__(self, spec: TestSpec) -> TestResult:
            if len(self.calls) == k:
                raise Killed
            return super().__call__(spec)

    with pytest.raises(Killed):
        Campaign(CONFIG, tmp_path, ShuffledExecutor(KillAfter(), 4, k)).run()
    _, before = read_journal(tmp_path / JOURNAL_FILE)
    assert len(before) == k
    bench = NoisyBench()
    Campaign(CONFIG, tmp_path, ShuffledExecutor(bench, 4, 100 + k), resume=True).run()
    assert essence(tmp_path) == essence(serial[0])
    assert len(bench.calls) == len(essence(serial[0])) - k  # nothing repeated, nothing skipped
