"""Optuna's samplers as campaign optimizers: TPE, CMA-ES and Optuna's GP, driven by ask and tell.

They keep the contract of `testctl/search/sampler.py`: a round's batch is a pure function of (seed, round, the
decided sets before it, q), and the first k points of a batch of q are the batch of k, so a resumed campaign
proposes what an uninterrupted one would have. Each round therefore builds its Optuna study afresh, in memory,
from the decided sets; nothing of an earlier process's sampler survives into it.

- TPE and the GP sampler hold no state but their random generator. The round's study holds the decided sets
  as finished trials (`create_trial`, with the space's distributions), the sampler is seeded from (seed,
  round), and q trials are asked one after the other, each earlier one still RUNNING: Optuna's own way of
  proposing for parallel workers (TPE's constant liar, the GP's pending points).
- CMA-ES keeps its search distribution in the trials' system attributes, updated generation by generation
  as trials are told. So the round replays the campaign's history through ask and tell: the initial sets
  added, then each earlier round's q trials asked and told the values the journal holds, then this round's q
  asked. Its generator is seeded from the campaign's seed alone, so the replay is the campaign's own run.
  It starts as Optuna's does, at the centre of the space with a sixth of the range as its step (the initial
  sets inform TPE and the GP, not CMA-ES's first generation; Optuna has deprecated setting its start).

The campaign's `--init-points` random sets are every sampler's start-up (`n_startup_trials = 0`): GPyOpt's
design and Optuna's, one design for all. Optuna is imported lazily: `hako --help` must stay fast.
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Any

import numpy as np

from testctl.search.sampler import Point, SeededSampler, _check_q, _rng
from testctl.search.space import ParameterSpace

if TYPE_CHECKING:
    import optuna


def distributions(space: ParameterSpace) -> dict[str, Any]:
    """Each searched parameter's Optuna distribution: an integer one (`type = "int"`, an integer storage
    type) is an IntDistribution, the rest FloatDistributions over their ranges."""
    from optuna.distributions import FloatDistribution, IntDistribution

    return {p.name: IntDistribution(int(p.low), int(p.high)) if p.integer else FloatDistribution(p.low, p.high)
            for p in space.params}


def params_of(space: ParameterSpace, x: Point) -> dict[str, float | int]:
    """A point as Optuna's params, integers as ints (their distributions hold nothing else)."""
    return {p.name: int(round(v)) if p.integer else float(v) for p, v in zip(space.params, x, strict=True)}


def quiet_optuna() -> None:
    """Optuna logs every finished trial at INFO on stderr, which would tear the campaign's progress line."""
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)


class _OptunaSampler(SeededSampler):
    """Asks q trials of an in-memory study that `_study` builds for the round."""

    def suggest_batch(
        self, space: ParameterSpace, X: np.ndarray, Y: np.ndarray, round_index: int, q: int
    ) -> list[Point]:
        _check_q(q)
        if len(X) == 0:
            raise ValueError(f"{type(self).__name__} needs at least one finished set (an initial point)")
        quiet_optuna()
        X = np.asarray(X, dtype=float).reshape(len(X), space.dim)
        Y = np.asarray(Y, dtype=float).reshape(len(X))
        dists = distributions(space)
        with _one_thread():
            study = self._study(space, dists, X, Y, round_index, q)
            trials = [study.ask(dists) for _ in range(q)]
        return [tuple(float(t.params[n]) for n in space.names) for t in trials]

    def _study(self, space: ParameterSpace, dists: dict[str, Any], X: np.ndarray, Y: np.ndarray,
               round_index: int, q: int) -> optuna.Study:
        raise NotImplementedError


class _StatelessOptunaSampler(_OptunaSampler):
    """A sampler whose only state is its generator: the decided sets are added as they are."""

    def _make(self, seed: int) -> Any:
        raise NotImplementedError

    def _study(self, space: ParameterSpace, dists: dict[str, Any], X: np.ndarray, Y: np.ndarray,
               round_index: int, q: int) -> optuna.Study:
        import optuna

        seed = int(_rng(self.seed, round_index, 0).integers(2**31))
        study = optuna.create_study(sampler=self._make(seed), direction="minimize")
        study.add_trials([optuna.trial.create_trial(params=params_of(space, x), distributions=dists, value=float(y))
                          for x, y in zip(X, Y)])
        return study


class TPESampler(_StatelessOptunaSampler):
    """Optuna's default sampler, the tree-structured Parzen estimator, with its defaults (independent per
    parameter, constant liar for pending trials)."""

    def _make(self, seed: int) -> Any:
        import optuna

        return optuna.samplers.TPESampler(seed=seed, n_startup_trials=0)


class GPSampler(_StatelessOptunaSampler):
    """Optuna's Gaussian-process sampler (log EI, its own kernel and priors); it needs PyTorch."""

    def suggest_batch(
        self, space: ParameterSpace, X: np.ndarray, Y: np.ndarray, round_index: int, q: int
    ) -> list[Point]:
        import torch  # noqa: F401  (before the thread limit, which then covers it)

        return super().suggest_batch(space, X, Y, round_index, q)

    def _make(self, seed: int) -> Any:
        import optuna

        return optuna.samplers.GPSampler(seed=seed, n_startup_trials=0)


class CmaEsSampler(_OptunaSampler):
    """Optuna's CMA-ES, replayed from the campaign's start each round (see the module's docstring)."""

    def _study(self, space: ParameterSpace, dists: dict[str, Any], X: np.ndarray, Y: np.ndarray,
               round_index: int, q: int) -> optuna.Study:
        import optuna

        n_init = len(X) - (round_index - 1) * q
        if round_index < 1 or n_init < 1:
            raise ValueError(f"round {round_index} of {q} after {len(X)} sets leaves no initial design")
        sampler = optuna.samplers.CmaEsSampler(seed=self.seed, n_startup_trials=0, warn_independent_sampling=False)
        study = optuna.create_study(sampler=sampler, direction="minimize")
        study.add_trials([optuna.trial.create_trial(params=params_of(space, x), distributions=dists, value=float(y))
                          for x, y in zip(X[:n_init], Y[:n_init])])
        for first in range(n_init, len(X), q):
            asked = [study.ask(dists) for _ in range(q)]
            for trial, y in zip(asked, Y[first:first + q]):
                study.tell(trial, float(y))
        return study


class _one_thread:
    """One thread for BLAS, OpenMP and PyTorch while a sampler works: the matrices are small, threads mostly
    wait for each other on a loaded machine, and the last bits of a proposal would depend on how many threads
    shared a sum."""

    def __enter__(self) -> None:
        from threadpoolctl import threadpool_limits

        self._limits = threadpool_limits(limits=1)
        self._torch = sys.modules.get("torch")  # imported by the GP sampler before it enters
        if self._torch is not None:
            self._threads = self._torch.get_num_threads()
            self._torch.set_num_threads(1)

    def __exit__(self, *exc: object) -> None:
        if self._torch is not None:
            self._torch.set_num_threads(self._threads)
        self._limits.restore_original_limits()
