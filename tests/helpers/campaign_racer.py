"""A campaign process for the race tests: `python campaign_racer.py OUT new|resume` plans the campaign as
`hako run` does (taking the folder's lock) and runs it on the synthetic bench, slowly enough to overlap with
the others; a refusal is printed as `hako run` prints it (one line, exit 1)."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import click

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # run as a script: the repository, for tests.helpers
from testctl.campaign.loop import Campaign
from testctl.executor import TestSpec
from testctl.options import plan
from tests.helpers.campaign_doubles import SyntheticBench

CAMPAIGN = {"trials": 2, "init_points": 2, "repeats": 3, "seed": 7, "optimizer": "random", "batch": None,
            "noise": None, "space_file": None, "smoke": False}
TEST_S = 0.02  # each synthetic test's wall time: a campaign lasts a few tenths of a second


def run(out: Path, how: str) -> None:
    options = {**CAMPAIGN, "out": out, "resume": None} if how == "new" else \
        {**{k: None for k in CAMPAIGN}, "smoke": False, "out": None, "resume": out}
    p = plan(**options, penalty_s=60.0)
    bench = SyntheticBench()

    def slow(spec: TestSpec):
        time.sleep(TEST_S)
        return bench(spec)

    try:
        Campaign(p.config, p.out_dir, slow, resume=p.resume).run()
    finally:
        p.lock.release()


if __name__ == "__main__":
    try:
        run(Path(sys.argv[1]), sys.argv[2])
    except click.ClickException as e:
        e.show()
        sys.exit(1)
