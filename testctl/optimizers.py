"""The optimizers a campaign can use, by the name the user gives: the one list that `--optimizer`, the
journal and the campaign all read. Naming a class rather than holding it keeps NumPy and GPyOpt out of
`hako --help`."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from testctl.sampler import Sampler

OPTIMIZERS = {"gpyopt": "GPyOptSampler", "random": "RandomSampler"}  # name -> its class in testctl.sampler


def make_sampler(name: str, seed: int) -> Sampler:
    from testctl import sampler

    return getattr(sampler, OPTIMIZERS[name])(seed)
