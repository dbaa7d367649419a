"""The optimizers a campaign can use, by the name the user gives: the one list that `--optimizer`, the
journal and the campaign all read. Naming a class rather than holding it keeps NumPy, GPyOpt and Optuna out
of `hako --help`; an optimizer whose extra dependency is missing is named with the command that installs it,
before any bench starts."""

from __future__ import annotations

import importlib
import importlib.util
from typing import TYPE_CHECKING

from hakoniwa.wire.errors import HakoError

if TYPE_CHECKING:
    from testctl.search.sampler import Sampler

# name -> "module:class"; gpyopt, the paper's, is the default
OPTIMIZERS = {
    "gpyopt": "testctl.search.sampler:GPyOptSampler",
    "random": "testctl.search.sampler:RandomSampler",
    "tpe": "testctl.search.optuna_samplers:TPESampler",
    "cmaes": "testctl.search.optuna_samplers:CmaEsSampler",
    "optuna-gp": "testctl.search.optuna_samplers:GPSampler",
}
HELP = ("gpyopt: Bayesian optimization with EI (the paper's); tpe, cmaes, optuna-gp: Optuna's TPE, CMA-ES and "
        "GP samplers; random: uniform random search, the baseline")
# name -> (modules it needs beyond the project's dependencies, what installs them)
_NEEDS = {"optuna-gp": (("torch",), "pip install -e '.[gp]' (PyTorch, CPU build enough)")}


class OptimizerUnavailable(HakoError, ValueError):
    """The optimizer's extra dependency is not installed; the message says what to install."""


def missing(name: str) -> str | None:
    """Why optimizer `name` cannot run here, in one line, or None when it can."""
    modules, install = _NEEDS.get(name, ((), ""))
    absent = [m for m in modules if importlib.util.find_spec(m) is None]
    if not absent:
        return None
    return f"--optimizer {name} needs {', '.join(absent)}, which is not installed: {install}"


def make_sampler(name: str, seed: int) -> Sampler:
    if (why := missing(name)) is not None:
        raise OptimizerUnavailable(why)
    module, cls = OPTIMIZERS[name].split(":")
    return getattr(importlib.import_module(module), cls)(seed)
