"""One live campaign per folder: a second run, or a resume, of a campaign that is still running is refused
with one line before it writes anything, and the journal stays what the one campaign wrote."""

from __future__ import annotations

import random
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import click
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from testctl.campaign.journal import JOURNAL_FILE, read_journal
from testctl.campaign.loop import Campaign
from testctl.executor import TestSpec
from testctl.options import make_out_dir, plan
from tests.campaign.test_campaign_resume import essence
from tests.helpers.campaign_doubles import Killed, SyntheticBench
from tests.helpers.campaign_racer import CAMPAIGN
from tests.helpers.paths import TESTS

RACER = TESTS / "helpers" / "campaign_racer.py"
TESTS = 8  # 4 sets of 2 tests on the synthetic bench


def plan_new(out: Path):
    return plan(**CAMPAIGN, out=out, resume=None, penalty_s=60.0)


def plan_resume(out: Path):
    return plan(**{**{k: None for k in CAMPAIGN}, "smoke": False}, out=None, resume=out, penalty_s=60.0)


def reference() -> list[tuple]:
    with tempfile.TemporaryDirectory() as tmp:
        p = plan_new(Path(tmp) / "c")
        Campaign(p.config, p.out_dir, SyntheticBench()).run()
        p.lock.release()
        return essence(read_journal(p.out_dir / JOURNAL_FILE)[1])


REFERENCE = reference()


class PausingBench:
    """Stops before test `at` until let go (or raises Killed there, standing for a kill of the campaign)."""

    def __init__(self, at: int, kill: bool) -> None:
        self.bench, self.at, self.kill, self.n = SyntheticBench(), at, kill, 0
        self.paused, self.go = threading.Event(), threading.Event()

    def __call__(self, spec: TestSpec):
        if self.n == self.at:
            self.paused.set()
            self.go.wait()
            if self.kill:
                raise Killed
        self.n += 1
        return self.bench(spec)


def refused_in_one_line(attempt, out: Path) -> str:
    with pytest.raises(click.ClickException) as info:
        attempt(out)
    message = info.value.format_message()
    assert "\n" not in message
    assert f"campaign folder {out} is in use by another run (pid " in message
    return message


@settings(max_examples=25, deadline=None)
@given(at=st.integers(0, TESTS - 1), kill=st.booleans(),
       contenders=st.lists(st.sampled_from(["new", "resume"]), min_size=1, max_size=3))
def test_a_second_run_or_a_resume_while_a_campaign_runs_is_refused(at: int, kill: bool, contenders: list[str]):
    """The campaign is held before test `at`; each contender then tries the same folder."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "c"
        p = plan_new(out)
        bench = PausingBench(at, kill)
        failure: list[BaseException] = []

        def campaign() -> None:
            try:
                Campaign(p.config, p.out_dir, bench).run()
            except Killed as e:
                failure.append(e)
            finally:
                p.lock.release()  # what the process's exit does

        thread = threading.Thread(target=campaign)
        thread.start()
        assert bench.paused.wait(60)
        before = (out / JOURNAL_FILE).read_bytes()
        for how in contenders:
            refused_in_one_line(plan_new if how == "new" else plan_resume, out)
        assert (out / JOURNAL_FILE).read_bytes() == before  # nothing written by the refused ones
        bench.go.set()
        thread.join(60)
        assert len(read_journal(out / JOURNAL_FILE)[1]) == (at if kill else TESTS)
        assert bool(failure) == kill
        again = plan_resume(out)  # once the campaign is over the folder is free again
        try:
            Campaign(again.config, out, SyntheticBench(), resume=True).run()
        finally:
            again.lock.release()
        assert essence(read_journal(out / JOURNAL_FILE)[1]) == REFERENCE


def test_runs_probing_one_folder_at_once_do_not_see_it_unwritable(tmp_path: Path):
    """Each run proves its --out takes files before it takes the lock; runs started together on one folder
    used to share the probe's name, so one could unlink the other's probe and call the folder unwritable."""
    out = tmp_path / "c"
    start = threading.Barrier(8)
    errors: list[BaseException] = []

    def probe() -> None:
        start.wait()
        for _ in range(300):
            try:
                make_out_dir(out)
            except click.ClickException as e:
                errors.append(e)
                return

    threads = [threading.Thread(target=probe) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(60)
    assert not errors, errors[0].format_message()
    assert [p.name for p in out.iterdir()] == []  # no probe left behind


@pytest.mark.slow
@pytest.mark.parametrize("round_", range(20))
def test_two_runs_and_a_resume_racing_on_one_folder(tmp_path: Path, round_: int):
    """Three processes (two new runs and a resume) started at random moments on one folder: whichever order
    they get there in, each one either runs or is refused with one line, and the journal is one campaign's."""
    rng = random.Random(round_)
    out = tmp_path / "c"
    racers = []
    for how in rng.sample(["new", "new", "resume"], 3):
        time.sleep(rng.uniform(0, 0.6))
        racers.append((how, subprocess.Popen([sys.executable, str(RACER), str(out), how], stdout=subprocess.PIPE,
                                             stderr=subprocess.PIPE, text=True)))
    ran = 0
    for how, proc in racers:
        _, err = proc.communicate(timeout=300)
        if proc.returncode == 0:
            ran += how == "new"
            continue
        assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
        assert ("is in use by another run" in err or "already holds a campaign" in err
                or (how == "resume" and "no journal" in err)), err
    assert ran == 1
    assert essence(read_journal(out / JOURNAL_FILE)[1]) == REFERENCE
