"""What every command line of the bench shares: `-h` as well as `--help`, its errors as one line, and the
checks on numbers that end up as float32 in the mapped files."""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click

from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.protocol import MAX_NOISE_SCALE

HELP = {"help_option_names": ["-h", "--help"]}
FLOAT32_MAX = 3.4028234663852886e38


class OneLineErrors(click.Command):
    """The one place a command line turns a `HakoError`, from whatever its command called, into click's
    one-line error and exit status 1. A command catches an error itself only to say more, or to exit
    otherwise (`hako test`'s status 2)."""

    def invoke(self, ctx: click.Context) -> object:
        try:
            return super().invoke(ctx)
        except HakoError as e:
            raise click.ClickException(str(e)) from None


class OneLineErrorsGroup(OneLineErrors, click.Group):
    """`OneLineErrors` for a group: its subcommands run inside its `invoke`."""


class Float32(click.ParamType):
    """A finite number that fits a float32 and lies in [low, high]: NaN, infinity and 1e40 are refused here,
    with the range named, instead of turning into a crashed test or a traceback later."""

    name = "number"

    def __init__(self, low: float = -FLOAT32_MAX, high: float = FLOAT32_MAX) -> None:
        self.low, self.high = low, high

    def convert(self, value, param, ctx) -> float:
        try:
            x = float(value)
        except (TypeError, ValueError):
            self.fail(f"{value!r} is not a number", param, ctx)
        if not math.isfinite(x):
            self.fail(f"{value!r} is not a finite number", param, ctx)
        if not self.low <= x <= self.high:
            self.fail(f"{value!r} is outside {self.low:g}..{self.high:g}", param, ctx)
        return x


SECONDS = Float32(0.001, 1e6)  # a time limit or timeout: positive, finite
NOISE_SCALE = Float32(0.0, MAX_NOISE_SCALE)


_Decorated = TypeVar("_Decorated", bound=Callable[..., Any])


def option_group(options: list[Callable]) -> Callable[[_Decorated], _Decorated]:
    """One decorator for a list of click options that several commands share."""

    def decorate(f: _Decorated) -> _Decorated:
        for option in reversed(options):
            f = option(f)
        return f

    return decorate


def writable_file(path: Path, option: str) -> None:
    """An output file's folder is checked before the test, so a typo costs a line, not the run."""
    if path.is_dir():
        raise click.BadParameter(f"{path} is a folder", param_hint=option)
    parent = path.parent.resolve()
    if not parent.is_dir():
        raise click.BadParameter(f"folder {path.parent} does not exist", param_hint=option)
    if not os.access(parent, os.W_OK):
        raise click.BadParameter(f"folder {path.parent} is not writable", param_hint=option)
