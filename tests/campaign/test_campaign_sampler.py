"""The samplers' batches: a pure function of their inputs, q distinct points in the space, pending points
taken into account, and (for EI) good points."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from hakoniwa.wire.protocol import Rx
from testctl.search import optimizers
from testctl.search.optimizers import make_sampler
from testctl.search.sampler import GPyOptSampler, RandomSampler
from testctl.search.space import Parameter, ParameterSpace
from tests.helpers.paths import REPO

# Ranges of very different widths, so that a point scaled wrongly shows up out of bounds.
SPACE = ParameterSpace(
    params=(Parameter("a", Rx.KP, 0.0, 5.0), Parameter("b", Rx.KI, 10.0, 200.0), Parameter("c", Rx.KD, -1.0, 1.0))
)
LOW = np.array([p.low for p in SPACE.params])
HIGH = np.array([p.high for p in SPACE.params])
BEST = np.array([1.0, 150.0, -0.5])


def bowl(X: np.ndarray) -> np.ndarray:
    """A lap-time-like bowl over SPACE (least 30 at BEST), with a 60 plateau where it fails."""
    lap = 30.0 + 40.0 * np.sum(((X - BEST) / (HIGH - LOW)) ** 2, axis=1, keepdims=True)
    return np.minimum(lap, 60.0)


def initial(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    X = np.array(RandomSampler(seed).suggest_batch(SPACE, np.empty((0, 3)), np.empty((0, 1)), 0, n))
    return X, bowl(X)


def assert_distinct_inside(batch: list[tuple[float, ...]], q: int) -> None:
    P = np.array(batch)
    assert P.shape == (q, SPACE.dim)
    assert np.all(P >= LOW) and np.all(P <= HIGH)
    unit = (P - LOW) / (HIGH - LOW)
    gaps = [np.linalg.norm(unit[i] - unit[j]) for i in range(q) for j in range(i)]
    assert min(gaps, default=1.0) > 1e-3  # not q copies of one point


@pytest.mark.parametrize("name", ["gpyopt", "random"])
def test_a_batch_is_a_pure_function_of_seed_round_and_data(name: str) -> None:
    X, Y = initial(8)
    state = np.random.get_state()
    first = make_sampler(name, 3).suggest_batch(SPACE, X, Y, 1, 4)
    assert make_sampler(name, 3).suggest_batch(SPACE, X.copy(), Y.copy(), 1, 4) == first
    assert make_sampler(name, 3).suggest_batch(SPACE, X, Y, 2, 4) != first
    assert make_sampler(name, 4).suggest_batch(SPACE, X, Y, 1, 4) != first
    after = np.random.get_state()
    assert after[0] == state[0] and np.array_equal(after[1], state[1]) and after[2:] == state[2:]


def test_a_fresh_process_proposes_the_same_batch() -> None:
    """What `--resume` relies on. The first batch of a process once differed in its last bits: the BLAS and
    OpenMP libraries that importing GPyOpt loads escaped the one-thread limit."""
    code = (
        "import numpy as np; from tests.campaign.test_campaign_sampler import SPACE, initial;"
        "from testctl.search.sampler import GPyOptSampler;"
        "X, Y = initial(20); print(repr(GPyOptSampler(5).suggest_batch(SPACE, X, Y, 3, 3)))"
    )
    fresh = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=REPO)
    X, Y = initial(20)
    assert fresh.stdout.strip() == repr(GPyOptSampler(5).suggest_batch(SPACE, X, Y, 3, 3))


@pytest.mark.parametrize("name", ["gpyopt", "random", "tpe", "cmaes", "optuna-gp"])
def test_the_first_points_of_a_batch_do_not_depend_on_its_size(name: str) -> None:
    """So a round cut short (the last one of a campaign) proposes the same sets, and `suggest` is q = 1. (Round
    1: CMA-ES replays the earlier rounds, whose size is the batch's.)"""
    if optimizers.missing(name):
        pytest.skip(optimizers.missing(name))
    X, Y = initial(8)
    sampler = make_sampler(name, 3)
    full = sampler.suggest_batch(SPACE, X, Y, 1, 4)
    assert sampler.suggest_batch(SPACE, X, Y, 1, 2) == full[:2]
    assert sampler.suggest(SPACE, X, Y, 1) == full[0]


@pytest.mark.parametrize("name", ["gpyopt", "random"])
def test_a_batch_is_q_distinct_points_inside_the_bounds(name: str) -> None:
    X, Y = initial(12)
    assert_distinct_inside(make_sampler(name, 0).suggest_batch(SPACE, X, Y, 1, 8), 8)


def test_pending_points_push_the_rest_of_the_batch_away() -> None:
    """Near the bowl's bottom, EI alone would propose the same spot again and again; the lie for the pending
    points sends each further point elsewhere."""
    X, Y = initial(6)
    near = BEST + np.array([[0.3, 10.0, 0.1], [-0.3, -10.0, -0.1], [0.2, -8.0, 0.05]])
    X, Y = np.vstack([X, near]), np.vstack([Y, bowl(near)])
    batch = GPyOptSampler(0).suggest_batch(SPACE, X, Y, 1, 6)
    assert_distinct_inside(batch, 6)
    unit = (np.array(batch) - LOW) / (HIGH - LOW)
    assert np.linalg.norm(unit[1:] - unit[0], axis=1).min() > 0.02


def test_every_lie_gives_a_batch_and_they_differ() -> None:
    X, Y = initial(10)
    batches = {lie: GPyOptSampler(1, lie=lie).suggest_batch(SPACE, X, Y, 1, 3) for lie in ("min", "mean", "max")}
    for batch in batches.values():
        assert_distinct_inside(batch, 3)
        assert batch[0] == batches["min"][0]  # the first point has nothing pending
    assert batches["min"][1:] != batches["max"][1:]


def test_a_batch_when_every_set_failed() -> None:
    """Nothing to learn from yet (all Y equal): still q distinct points, no error."""
    X, _ = initial(5)
    assert_distinct_inside(GPyOptSampler(0).suggest_batch(SPACE, X, np.full((5, 1), 60.0), 1, 4), 4)


def test_ei_batches_find_the_bottom_of_a_bowl_within_a_few_rounds() -> None:
    X, Y = initial(5, seed=2)
    sampler = GPyOptSampler(2)
    for round_index in range(1, 5):
        batch = np.array(sampler.suggest_batch(SPACE, X, Y, round_index, 4))
        X, Y = np.vstack([X, batch]), np.vstack([Y, bowl(batch)])
    assert Y.min() < 30.5 < initial(5, seed=2)[1].min()  # 21 sets; random search's first 5 are far off


def test_random_batches_keep_the_single_suggestions_of_earlier_versions() -> None:
    """Point 0 of round i is what set i got before batches; the other points are fresh uniform draws."""
    X, Y = initial(3)
    batch = RandomSampler(7).suggest_batch(SPACE, X, Y, 4, 3)
    legacy = np.random.default_rng([7, 4])
    assert batch[0] == tuple(float(legacy.uniform(p.low, p.high)) for p in SPACE.params)
    assert_distinct_inside(batch, 3)


def test_bad_requests_are_refused() -> None:
    X, Y = initial(3)
    for name in ("gpyopt", "random"):
        with pytest.raises(ValueError, match="at least one point"):
            make_sampler(name, 0).suggest_batch(SPACE, X, Y, 1, 0)
    with pytest.raises(ValueError, match="at least one finished set"):
        GPyOptSampler(0).suggest_batch(SPACE, np.empty((0, 3)), np.empty((0, 1)), 1, 2)
    with pytest.raises(ValueError, match="unknown lie"):
        GPyOptSampler(0, lie="median")


def test_the_fast_predictions_are_gpyopts() -> None:
    """The numpy predictions that L-BFGS uses are GPyOpt's GPModel.predict_withGradients, faster."""
    import GPy
    from GPyOpt.models import GPModel

    from testctl.search.sampler import _LyingGP

    rng = np.random.default_rng(0)
    X = rng.uniform(size=(30, 3))
    Y = np.sin(4.0 * X).sum(axis=1, keepdims=True) + 0.1 * rng.standard_normal((30, 1))
    gp = GPModel(kernel=GPy.kern.Matern52(3, lengthscale=0.2), optimizer="lbfgs", optimize_restarts=1, verbose=False)
    model = _LyingGP(gp, np.min)
    model.updateModel(X, Y, None, None)
    model.pretend(rng.uniform(size=(1, 3)))
    P = rng.uniform(size=(5, 3))
    for ours, theirs in zip(model.predict_withGradients(P), gp.predict_withGradients(P), strict=True):
        np.testing.assert_allclose(ours, theirs, rtol=1e-7, atol=1e-9)
    assert model.get_fmin() == pytest.approx(gp.get_fmin())
