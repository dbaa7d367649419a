"""Writing results without losing data: no output may be one of the inputs, and every file appears whole or not
at all (a temporary file in the same folder, then a rename), so a crash or a full disk never leaves half a log.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO

from .errors import MazeError


def _same(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:  # one does not exist yet: only the same name can clash
        return os.path.abspath(a) == os.path.abspath(b)


def refuse_overwrite(inputs: dict[str, Path | None], outputs: dict[str, Path | None]) -> None:
    """Same file, not just same name: a hard link or another spelling of the path is caught too."""
    given_in = [(k, p) for k, p in inputs.items() if p is not None]
    given_out = [(k, p) for k, p in outputs.items() if p is not None]
    for name, out in given_out:
        for source, path in given_in:
            if _same(out, path):
                raise MazeError(f"{name} {out} is the input {source} {path}: refusing to overwrite it")
    for i, (name, out) in enumerate(given_out):
        for other, path in given_out[i + 1:]:
            if _same(out, path):
                raise MazeError(f"{name} and {other} are the same file {out}: give each its own")


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextmanager
def atomic_open(path: Path, mode: str = "wb") -> Iterator[IO]:
    """A file object whose contents replace `path` only when the block ends without an error."""
    folder = path.parent if str(path.parent) else Path(".")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    except OSError as e:  # name the output the user gave, not our temporary file
        raise MazeError(f"{path}: cannot write there ({e.strerror})") from None
    os.chmod(tmp, 0o666 & ~_umask())  # mkstemp's 0600 would make every output private
    try:
        with os.fdopen(fd, mode, encoding=None if "b" in mode else "utf-8") as fp:
            yield fp
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def write_bytes(path: Path, data: bytes) -> None:
    with atomic_open(path) as fp:
        fp.write(data)


def write_text(path: Path, text: str) -> None:
    with atomic_open(path, "w") as fp:
        fp.write(text)
