"""Where the next parameter sets come from: random search or GPyOpt's Bayesian optimization with EI.

A sampler proposes a round's batch of q sets at once (`suggest_batch`), so that q benches can test them in
parallel; `suggest` is the batch of one. Every batch is a pure function of (seed, round index, X, Y, q). That
is what makes `--resume` exact: a resumed campaign rebuilds X and Y from the journal and so proposes the very
points an uninterrupted one would have, instead of depending on how much random state an earlier process had
consumed. Point j of a round draws its randomness from the seed (seed, round, j) alone, so the first k points
of a batch of q are the batch of k (a last round cut short proposes what a full one would have begun with).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, Protocol

import numpy as np

from testctl.search.space import ParameterSpace

Point = tuple[float, ...]


class Sampler(Protocol):
    def suggest_batch(
        self, space: ParameterSpace, X: np.ndarray, Y: np.ndarray, round_index: int, q: int
    ) -> list[Point]:
        """The q points (in `space.names` order) of round `round_index`, given the finished sets' points `X`
        (n x d) and objective values `Y` (n x 1, minimized); each point takes the earlier points of its
        batch, still pending, into account."""
        ...

    def suggest(self, space: ParameterSpace, X: np.ndarray, Y: np.ndarray, index: int) -> Point:
        """The point for set `index` of a one-set-at-a-time campaign: the batch of one of round `index`."""
        return self.suggest_batch(space, X, Y, index, 1)[0]


def _rng(seed: int, round_index: int, j: int) -> np.random.Generator:
    """The random stream of point j of a round. A trailing zero does not change a short SeedSequence's
    entropy, so point 0's stream is the one that (seed, index) gave single suggestions before batches."""
    return np.random.default_rng([seed, round_index, j])


def _check_q(q: int) -> None:
    if q < 1:
        raise ValueError(f"a batch needs at least one point, got q={q}")


class SeededSampler(Sampler):
    """A sampler that draws all its randomness from the campaign's seed (with the round and the point)."""

    def __init__(self, seed: int) -> None:
        self.seed = seed


class RandomSampler(SeededSampler):
    """Uniform random search: the paper's initial design, and the honest baseline to compare BO against."""

    def suggest_batch(
        self, space: ParameterSpace, X: np.ndarray, Y: np.ndarray, round_index: int, q: int
    ) -> list[Point]:
        _check_q(q)
        return [_uniform(space, _rng(self.seed, round_index, j)) for j in range(q)]


def _uniform(space: ParameterSpace, rng: np.random.Generator) -> Point:
    return tuple(float(rng.uniform(p.low, p.high)) for p in space.params)


LIES: dict[str, Callable[[np.ndarray], float]] = {"min": np.min, "mean": np.mean, "max": np.max}
"""The constant liar's value for a pending point, as a function of the observed (normalized) Y. The min
(pending points will be as good as the best) keeps a batch near the best set found, in a local basin too;
once a set has failed, the max is the 60 s penalty, so it pretends that the pending point failed and pushes
the rest of the batch out of the promising region. The default is the mean, in between: in scripts/benchmark_sampler.py
(`--lies`) no lie beat the others beyond the spread of the seeds, and the max left the most campaigns far
from the best after 40 sets."""

# The GP and the acquisition search, chosen with scripts/benchmark_sampler.py on its `basins` objective.
_GP_RESTARTS = 1  # GPyOpt: 5. One fit from the start below found points as good as 2 did, at half the cost
_INIT_LENGTHSCALE = 1.0  # the whole range, GPy's default, on the unit cube (0.2 trapped the search more often)
_ANCHOR_SAMPLES = 1000  # uniform points scored to pick the L-BFGS starts, as GPyOpt does
_ANCHORS = 5  # L-BFGS starts per point, as GPyOpt (3 saved a quarter of a round and found a little worse)
_SQRT5 = np.sqrt(5.0)


class GPyOptSampler(Sampler):
    """Bayesian optimization with Expected Improvement, as in the paper (section 4.1), in batches by the
    constant liar: the GP is fitted once per round; after each point of the batch is chosen, it is added to
    the GP as if already observed with the lie `LIES[lie]` (hyperparameters kept), and EI is maximized
    again. The lie lowers EI around the pending point, so the next one goes elsewhere.

    The GP sees the space scaled to the unit cube (so that one length scale fits parameters with different
    ranges) and Y normalized, as GPyOpt does. GPy and GPyOpt draw from numpy's global random state (GP
    restarts, anchor points), so it is seeded per point and the caller's state is restored afterwards.
    GPyOpt is imported here, lazily: the import takes seconds and random search does not need it.
    """

    def __init__(self, seed: int, lie: str = "mean") -> None:
        if lie not in LIES:
            raise ValueError(f"unknown lie {lie!r}; choose from {', '.join(LIES)}")
        self.seed = seed
        self.lie = lie

    def suggest_batch(
        self, space: ParameterSpace, X: np.ndarray, Y: np.ndarray, round_index: int, q: int
    ) -> list[Point]:
        _check_q(q)
        if len(X) == 0:
            raise ValueError("Bayesian optimization needs at least one finished set (an initial point)")
        low = np.array([p.low for p in space.params])
        high = np.array([p.high for p in space.params])
        unit_X = (np.asarray(X, dtype=float).reshape(len(X), space.dim) - low) / (high - low)
        seeds = [int(_rng(self.seed, round_index, j).integers(2**32)) for j in range(q)]
        column_Y = np.asarray(Y, dtype=float).reshape(-1, 1)
        saved = np.random.get_state()
        # One thread: the GP's matrices are small, so BLAS and OpenMP threads mostly wait for each other (on
        # a loaded machine a round took 10 to 40 times longer), and a batch's last bits would depend on how
        # many threads shared a sum.
        try:
            with _threads().limit(limits=1):
                batch = _constant_liar_batch(unit_X, column_Y, seeds, LIES[self.lie])
        finally:
            np.random.set_state(saved)
        return [tuple(float(v) for v in np.clip(low + u * (high - low), low, high)) for u in batch]


@functools.cache
def _threads() -> Any:
    """threadpoolctl's handle on the BLAS and OpenMP libraries loaded, GPy's among them (imported first):
    finding them takes milliseconds, so it is done once."""
    import GPyOpt  # noqa: F401
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


def _constant_liar_batch(
    X: np.ndarray, Y: np.ndarray, seeds: list[int], lie: Callable[[np.ndarray], float]
) -> np.ndarray:
    """len(seeds) points in the unit cube (one per row) by EI with the constant liar, through GPyOpt's
    modular API: its GP model, EI and ModularBayesianOptimization (which normalizes Y and fits the GP),
    with the batch evaluator, model wrapper and acquisition optimizer below."""
    import GPy
    from GPyOpt.acquisitions import AcquisitionEI
    from GPyOpt.core.task.space import Design_space
    from GPyOpt.methods import ModularBayesianOptimization
    from GPyOpt.models import GPModel

    dim = X.shape[1]
    space = Design_space([{"name": f"u{i}", "type": "continuous", "domain": (0.0, 1.0)} for i in range(dim)])
    gp = GPModel(
        kernel=GPy.kern.Matern52(dim, lengthscale=_INIT_LENGTHSCALE),
        optimizer="lbfgs",
        optimize_restarts=_GP_RESTARTS,
        verbose=False,
    )
    model = _LyingGP(gp, lie)
    acquisition = AcquisitionEI(model, space, optimizer=_AnchoredLbfgs(dim))
    bo = ModularBayesianOptimization(model, space, None, acquisition, _ConstantLiar(acquisition, seeds), X, Y)
    np.random.seed(seeds[0])  # GP restarts beyond the first draw random starting points
    return bo.suggest_next_locations()


class _LyingGP:
    """GPyOpt's GPModel with a Matern 5/2 kernel, for EI and a constant-liar batch.

    `pretend` adds a pending point with the lie, without refitting. Two costs of GPyOpt's EI are cut: its
    `fmin` (the least posterior mean over the data: a prediction at every training point), asked for at
    every evaluation, is computed once per change of the data; and the one-point predictions with gradients
    that L-BFGS asks for (dozens per proposal) are computed in plain numpy from GPy's posterior: the same
    formulas as GPy's general path, which spends about ten times as long on bookkeeping (0.6 to 1 ms a call).
    """

    analytical_gradient_prediction = True

    def __init__(self, gp: Any, lie: Callable[[np.ndarray], float]) -> None:
        self.gp = gp
        self.lie = lie
        self.n_observed = 0

    def updateModel(self, X_all: np.ndarray, Y_all: np.ndarray, X_new: Any, Y_new: Any) -> None:
        self.gp.updateModel(X_all, Y_all, X_new, Y_new)
        self.n_observed = len(Y_all)
        self._refresh()

    def pretend(self, x: np.ndarray) -> None:
        model = self.gp.model
        lie = self.lie(np.asarray(model.Y)[: self.n_observed])
        model.set_XY(np.vstack([model.X, x]), np.vstack([model.Y, [[lie]]]))
        self._refresh()

    def _refresh(self) -> None:
        model = self.gp.model
        self.fmin = float(self.gp.get_fmin())
        self.X = np.asarray(model.X)
        self.woodbury_vector = model.posterior.woodbury_vector[:, 0]
        self.chol = model.posterior.woodbury_chol
        self.variance = float(model.kern.variance[0])
        self.lengthscale = float(model.kern.lengthscale[0])
        self.noise = float(model.likelihood.variance[0])

    def get_fmin(self) -> float:
        return self.fmin

    def predict(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self.gp.predict(X)

    def predict_withGradients(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """What GPModel.predict_withGradients returns: mean, standard deviation (noise included), and their
        gradients with respect to X. The variance goes through the Cholesky factor, as in GPy: with a tiny
        noise, the inverse would lose it to rounding."""
        from scipy.linalg import solve_triangular

        diff = np.atleast_2d(X)[:, None, :] - self.X[None, :, :]
        r = np.sqrt(np.sum(diff**2, axis=2)) / self.lengthscale
        decay = np.exp(-_SQRT5 * r)
        k = self.variance * (1.0 + _SQRT5 * r + 5.0 / 3.0 * r**2) * decay
        dk_dx = (-5.0 / 3.0 * self.variance / self.lengthscale**2 * (1.0 + _SQRT5 * r) * decay)[:, :, None] * diff
        half = solve_triangular(self.chol, k.T, lower=True, check_finite=False)  # L^-1 k
        k_kinv = solve_triangular(self.chol, half, lower=True, trans="T", check_finite=False).T  # (K^-1 k)^T
        var = np.clip(self.variance - np.sum(half**2, axis=0) + self.noise, 1e-10, np.inf)[:, None]
        std = np.sqrt(var)
        dm_dx = np.einsum("mnd,n->md", dk_dx, self.woodbury_vector)
        dv_dx = -2.0 * np.einsum("mnd,mn->md", dk_dx, k_kinv)
        return (k @ self.woodbury_vector)[:, None], std, dm_dx, dv_dx / (2.0 * std)

    def get_model_parameters(self) -> np.ndarray:
        return self.gp.get_model_parameters()


class _ConstantLiar:
    """A GPyOpt batch evaluator (what ModularBayesianOptimization asks for the next locations): maximize the
    acquisition, pretend the point was observed, repeat. Point j is seeded with `seeds[j]` alone, so the
    first k points do not depend on q."""

    def __init__(self, acquisition: Any, seeds: list[int]) -> None:
        self.acquisition = acquisition
        self.seeds = seeds

    def compute_batch(self, duplicate_manager: Any = None, context_manager: Any = None) -> np.ndarray:
        batch: list[np.ndarray] = []
        for seed in self.seeds:
            if batch:
                self.acquisition.model.pretend(batch[-1])
            np.random.seed(seed)
            x, _ = self.acquisition.optimize()
            batch.append(np.atleast_2d(x))
        return np.vstack(batch)


class _AnchoredLbfgs:
    """Minimizes GPyOpt's acquisition (negated EI) over the unit cube, as its AcquisitionOptimizer does: score
    `_ANCHOR_SAMPLES` uniform points, run L-BFGS-B with the analytical gradient from the best `_ANCHORS`.
    GPyOpt's own evaluates the acquisition twice per L-BFGS step (once without, once with the gradient);
    this has the interface that `AcquisitionBase.optimize` calls."""

    def __init__(self, dim: int) -> None:
        self.bounds = [(0.0, 1.0)] * dim

    def optimize(
        self, f: Any = None, df: Any = None, f_df: Any = None, duplicate_manager: Any = None
    ) -> tuple[np.ndarray, np.ndarray]:
        from scipy.optimize import minimize

        samples = np.random.uniform(size=(_ANCHOR_SAMPLES, len(self.bounds)))
        anchors = samples[np.argsort(f(samples).ravel(), kind="stable")[:_ANCHORS]]

        def value_and_gradient(x: np.ndarray) -> tuple[float, np.ndarray]:
            value, gradient = f_df(x[None, :])
            return float(value[0, 0]), gradient[0]

        runs = [minimize(value_and_gradient, a, jac=True, method="L-BFGS-B", bounds=self.bounds) for a in anchors]
        best = min(runs, key=lambda r: r.fun)
        return best.x[None, :], np.atleast_2d(best.fun)

