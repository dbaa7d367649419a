"""Optuna's samplers as optimizers: batches that are a pure function of (seed, round, data), integers where
the space says so, good points, campaigns that resume exactly, and one line when a dependency is missing."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from hakoniwa.wire.protocol import Rx
from testctl.campaign.journal import JOURNAL_FILE, read_journal
from testctl.campaign.loop import Campaign, CampaignConfig
from testctl.search import optimizers
from testctl.search.optimizers import OptimizerUnavailable, make_sampler, missing
from testctl.search.space import Parameter, ParameterSpace
from tests.campaign.test_campaign_resume import essence
from tests.campaign.test_campaign_sampler import SPACE, assert_distinct_inside, bowl, initial
from tests.helpers.campaign_doubles import Killed, KilledAfter, SyntheticBench
from tests.helpers.commands import hako, one_line_error
from tests.helpers.paths import REPO

GP = pytest.param("optuna-gp", marks=pytest.mark.skipif(importlib.util.find_spec("torch") is None,
                                                         reason="optuna-gp needs PyTorch (pip install -e '.[gp]')"))
OPTUNA = ["tpe", "cmaes", GP]


@pytest.mark.parametrize("name", OPTUNA)
def test_a_batch_is_a_pure_function_of_seed_round_and_data(name: str) -> None:
    X, Y = initial(8)
    first = make_sampler(name, 3).suggest_batch(SPACE, X, Y, 1, 4)
    assert make_sampler(name, 3).suggest_batch(SPACE, X.copy(), Y.copy(), 1, 4) == first
    assert make_sampler(name, 4).suggest_batch(SPACE, X, Y, 1, 4) != first
    assert make_sampler(name, 3).suggest_batch(SPACE, X, Y, 2, 4) != first
    assert_distinct_inside(first, 4)


@pytest.mark.parametrize("name", ["tpe", "cmaes"])
def test_a_fresh_process_proposes_the_same_batch(name: str) -> None:
    """What `--resume` relies on: nothing of an earlier process's sampler is carried over."""
    code = ("from tests.campaign.test_campaign_sampler import SPACE, initial;"
            f"from testctl.search.optimizers import make_sampler; X, Y = initial(11);"
            f"print(repr(make_sampler({name!r}, 5).suggest_batch(SPACE, X, Y, 3, 3)))")
    fresh = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=REPO)
    X, Y = initial(11)
    assert fresh.stdout.strip() == repr(make_sampler(name, 5).suggest_batch(SPACE, X, Y, 3, 3))


@pytest.mark.parametrize("name", OPTUNA)
def test_integer_parameters_are_proposed_as_integers(name: str) -> None:
    space = ParameterSpace(params=(Parameter("gain", Rx.KP, 0.0, 5.0), Parameter("power", Rx.MOTOR_POWER, 10, 30,
                                                                                     type="int")))
    X = np.array([[1.0, 12.0], [2.0, 25.0], [4.0, 18.0], [0.5, 30.0]])
    Y = np.array([[40.0], [33.0], [36.0], [60.0]])
    for gain, power in make_sampler(name, 0).suggest_batch(space, X, Y, 1, 5):
        assert 0.0 <= gain <= 5.0 and power == int(power) and 10 <= power <= 30


@pytest.mark.parametrize("name", OPTUNA)
def test_the_search_goes_below_the_initial_design(name: str) -> None:
    X, Y = initial(5, seed=2)
    sampler = make_sampler(name, 2)
    for round_index in range(1, 11):
        batch = np.array(sampler.suggest_batch(SPACE, X, Y, round_index, 3))
        X, Y = np.vstack([X, batch]), np.vstack([Y, bowl(batch)])
    assert Y.min() < Y[:5].min() - 1.0, (Y.min(), Y[:5].min())  # the bowl's least is 30 at BEST


@pytest.mark.parametrize("name, batch, k", [("tpe", 1, 5), ("cmaes", 1, 5), ("cmaes", 2, 7), ("tpe", 2, 9)])
def test_a_killed_campaign_resumes_to_the_uninterrupted_one(tmp_path: Path, name: str, batch: int, k: int) -> None:
    config = CampaignConfig(init_points=2, trials=6, repeats=3, seed=7, optimizer=name, batch=batch)
    Campaign(config, tmp_path / "whole", SyntheticBench()).run()
    with pytest.raises(Killed):
        Campaign(config, tmp_path / "killed", KilledAfter(SyntheticBench(), k)).run()
    Campaign(config, tmp_path / "killed", SyntheticBench(), resume=True).run()
    assert (essence(read_journal(tmp_path / "killed" / JOURNAL_FILE)[1])
            == essence(read_journal(tmp_path / "whole" / JOURNAL_FILE)[1]))


def test_a_missing_dependency_is_one_line_before_anything_runs(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setitem(optimizers._NEEDS, "optuna-gp", (("no_such_module_here",), "pip install it"))
    assert missing("tpe") is None
    why = missing("optuna-gp")
    assert why is not None and "no_such_module_here" in why and "pip install it" in why
    with pytest.raises(OptimizerUnavailable, match="no_such_module_here"):
        make_sampler("optuna-gp", 0)
    from testctl.hako.main import main

    r = CliRunner().invoke(main, ["run", "--smoke", "--optimizer", "optuna-gp", "--out", str(tmp_path / "c")])
    assert r.exit_code == 1 and "Traceback" not in r.output
    assert r.output.strip().splitlines() == [f"Error: {why}"]
    assert not (tmp_path / "c" / JOURNAL_FILE).exists()


def test_an_unknown_optimizer_is_one_line(tmp_path: Path) -> None:
    one_line_error(hako("run", "--optimizer", "nosuch", "--out", str(tmp_path / "c")), "--optimizer", "'nosuch'",
                   "tpe", "cmaes", "optuna-gp")
