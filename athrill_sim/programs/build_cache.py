"""A build product cached in a folder named by the hash of its inputs, shared by every bench on the machine.

The build happens in a scratch folder beside the entry and is renamed into place when it is whole, so two
benches building the same program at once both end up with a good product and no one sees half of one.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path

from athrill_sim.native import NativeBuildError
from athrill_sim.v850 import ImageError

CACHE_ENV = "XDG_CACHE_HOME"


def cache_root() -> Path:
    """`${XDG_CACHE_HOME:-~/.cache}/hakoniwa-py`: native binaries, v850 images and the unpacked toolchain."""
    base = os.environ.get(CACHE_ENV) or str(Path.home() / ".cache")
    return Path(base) / "hakoniwa-py"


class CacheUnwritable(ImageError, NativeBuildError):
    """The cache folder cannot be made (a read-only HOME): one line naming the variable that moves it, for the
    native and the v850 build alike."""


class CacheKey:
    """The name of a cache entry: every input hashed as its label, its length and its bytes, so that no two
    different sets of inputs run together into the same stream."""

    def __init__(self) -> None:
        self._hash = hashlib.sha256()

    def add(self, label: str, data: bytes) -> None:
        self._hash.update(f"{label}\0{len(data)}\0".encode())
        self._hash.update(data)

    def name(self) -> str:
        return self._hash.hexdigest()[:32]


def cached_build(entry: Path, product: str, build: Callable[[Path], None]) -> Path:
    """`entry/product`, made by `build(scratch)` unless the entry already holds it."""
    cached_folder(entry, lambda folder: folder / product if (folder / product).is_file() else None, build)
    return entry / product


def cached_folder(entry: Path, find: Callable[[Path], Path | None], build: Callable[[Path], None]) -> Path | None:
    """`find(entry)`, the entry made whole by `build(scratch)` first unless it already is. None when a build
    that just succeeded left nothing `find` finds (the build's inputs lack it)."""
    done = find(entry)
    if done is not None:
        return done
    try:
        entry.parent.mkdir(parents=True, exist_ok=True)
        scratch = Path(tempfile.mkdtemp(prefix=entry.name + ".tmp-", dir=entry.parent))
    except OSError as e:
        raise CacheUnwritable(f"cannot write the build cache at {entry.parent} ({e.strerror}): set {CACHE_ENV} "
                              f"to a writable folder (the cache is ${CACHE_ENV}/hakoniwa-py, by default "
                              f"~/.cache/hakoniwa-py)") from None
    try:
        build(scratch)
        try:
            scratch.rename(entry)
        except OSError:  # another build of the same inputs finished first; it made the same product
            if find(entry) is None:
                raise
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    return find(entry)
