"""Where the next parameter set comes from: random search or GPyOpt's Bayesian optimization with EI.

Every suggestion is a pure function of (seed, set index, X, Y). That is what makes `--resume` exact: a
resumed campaign rebuilds X and Y from the journal and so proposes the very points an uninterrupted one
would have, instead of depending on how much random state an earlier process had consumed.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np

from testctl.space import ParameterSpace


class Sampler(Protocol):
    def suggest(self, space: ParameterSpace, X: np.ndarray, Y: np.ndarray, index: int) -> tuple[float, ...]:
        """The point (in `space.names` order) for set `index`, given the finished sets' points `X` (n x d)
        and objective values `Y` (n x 1, minimized)."""
        ...


def _rng(seed: int, index: int) -> np.random.Generator:
    return np.random.default_rng([seed, index])


class RandomSampler:
    """Uniform random search: the paper's initial design, and the honest baseline to compare BO against."""

    def __init__(self, seed: int) -> None:
        self.seed = seed

    def suggest(self, space: ParameterSpace, X: np.ndarray, Y: np.ndarray, index: int) -> tuple[float, ...]:
        rng = _rng(self.seed, index)
        return tuple(float(rng.uniform(p.low, p.high)) for p in space.params)


class GPyOptSampler:
    """Sequential Bayesian optimization with Expected Improvement, as in the paper (section 4.1).

    GPyOpt draws from numpy's global random state (GP restarts, acquisition anchor points), so it is seeded
    per suggestion and the caller's global state is restored afterwards. GPyOpt is imported here, lazily:
    the import takes seconds and random search does not need it.
    """

    def __init__(self, seed: int) -> None:
        self.seed = seed

    def suggest(self, space: ParameterSpace, X: np.ndarray, Y: np.ndarray, index: int) -> tuple[float, ...]:
        if len(X) == 0:
            raise ValueError("Bayesian optimization needs at least one finished set (an initial point)")
        from GPyOpt.methods import BayesianOptimization

        domain = [{"name": p.name, "type": "continuous", "domain": (p.low, p.high)} for p in space.params]
        saved = np.random.get_state()
        np.random.seed(int(_rng(self.seed, index).integers(2**32)))
        try:
            bo = BayesianOptimization(f=None, domain=domain, X=X, Y=Y, acquisition_type="EI")
            x = bo.suggest_next_locations()
        finally:
            np.random.set_state(saved)
        return tuple(float(v) for v in x[0])


SAMPLERS: dict[str, Callable[[int], Sampler]] = {"gpyopt": GPyOptSampler, "random": RandomSampler}
