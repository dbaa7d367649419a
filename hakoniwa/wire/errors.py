"""The one error base of the bench's programs (`hako`, `hakoniwa-physics`, `athrill-sim`, `testctl`).

Every error that means "bad input" or "the bench cannot go on" derives from `HakoError`, and its message is
the one line the user sees: each command line turns it into that line in one place
(`hakoniwa.conventions.OneLineErrors`), so a command need not list what its callees may raise. Signals that
steer a loop rather than report a failure (a test's `AthrillCrash`, `ControllerGone`, `KernelExit`) are not
errors and do not derive from it. Standard library only: the wire layer's own errors derive from it too.
"""

from __future__ import annotations


class HakoError(Exception):
    """Bad input or a bench that cannot go on; `str()` is one line for the user."""
