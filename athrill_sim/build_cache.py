"""A build product cached in a folder named by the hash of its inputs, shared by every bench on the machine.

The build happens in a scratch folder beside the entry and is renamed into place when it is whole, so two
benches building the same program at once both end up with a good product and no one sees half of one.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path
from typing import Callable


def cached_build(entry: Path, product: str, build: Callable[[Path], None]) -> Path:
    """`entry/product`, made by `build(scratch)` unless the entry already holds it."""
    done = entry / product
    if done.is_file():
        return done
    entry.parent.mkdir(parents=True, exist_ok=True)
    scratch = Path(tempfile.mkdtemp(prefix=entry.name + ".tmp-", dir=entry.parent))
    try:
        build(scratch)
        try:
            scratch.rename(entry)
        except OSError:  # another build of the same inputs finished first; it made the same product
            if not done.is_file():
                raise
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    return done
