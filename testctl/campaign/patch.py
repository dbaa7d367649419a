"""best.patch: the tuned values, set in the user's own files, as a unified diff `git apply` takes.

A campaign over a program tuned as it is written (`athrill_sim.tuning`) ends with the values in the bench's
slots; the user wants them in the program: the `#define`, the global's initializer, the data file, the
`source` match. The diff's paths are relative to the program's folder (the folder of `--app`, or the
common folder of every file it changes, when a file lies above it), so it applies from there:
`cd APP && git apply runs/x/best.patch`, in a repository (where git takes the paths as relative to the
folder it runs in) or not.
"""

from __future__ import annotations

import difflib
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from athrill_sim.forms.form import file_bytes, file_text
from athrill_sim.tuning import Tuning, apply_edits

BEST_PATCH = "best.patch"
_NO_NEWLINE = "\\ No newline at end of file\n"


@dataclass(frozen=True)
class PatchInfo:
    """What best.patch does, for best.json and the summary."""

    root: Path  # where it applies
    files: tuple[str, ...]  # relative to `root`
    sets: tuple[str, ...]  # "Kp=1.539 (#define KP) in app.h"
    missing: tuple[str, ...]  # values no file holds, and what to do about them

    def to_dict(self) -> dict[str, Any]:
        return {"file": BEST_PATCH, "apply_in": str(self.root), "files": list(self.files), "sets": list(self.sets),
                **({"not_in_the_patch": list(self.missing)} if self.missing else {})}

    def describe(self, patch: Path) -> str:
        what = "; ".join(self.sets) if self.sets else "nothing"
        line = f"{BEST_PATCH} sets {what}: apply with cd {self.root} && git apply {patch.resolve()}"
        return line + "".join(f"\nnot in {BEST_PATCH}: {m}" for m in self.missing)


def write_patch(path: Path, tuning: Tuning, values: dict[str, float]) -> PatchInfo:
    """Write the diff that gives the program `values` into `path`."""
    edits, missing = tuning.edits(values)
    by_file: dict[Path, list] = {}
    for e in edits:
        by_file.setdefault(e.path, []).append(e)
    root = Path(os.path.commonpath([tuning.root, *(p.parent for p in by_file)]))
    chunks, sets = [], []
    for f in sorted(by_file):
        old = file_text(f) if f.is_file() else None
        new = apply_edits(old or "", [(e.start, e.end, e.text) for e in by_file[f]])
        rel = f.relative_to(root).as_posix()
        sets += [f"{e.what} in {rel}" for e in by_file[f]]
        chunks.append(unified_diff(old, new, rel))
    path.write_bytes(file_bytes("".join(chunks)))
    return PatchInfo(root, tuple(f.relative_to(root).as_posix() for f in sorted(by_file)), tuple(sets),
                     tuple(missing))


def unified_diff(old: str | None, new: str, rel: str) -> str:
    """The git-style diff of one file (`old` None: a new file); empty when nothing changes."""
    if old == new:
        return ""
    a, b = _lines(old or ""), _lines(new)
    header = f"diff --git a/{rel} b/{rel}\n" + ("new file mode 100644\n" if old is None else "")
    body = list(difflib.unified_diff(a, b, "/dev/null" if old is None else f"a/{rel}", f"b/{rel}", n=3))
    return header + "".join(line if line.endswith("\n") else line + "\n" + _NO_NEWLINE for line in body)


def _lines(text: str) -> list[str]:
    """Lines as git counts them: split at newlines only (str.splitlines also splits at \\x1c, \\x85, ...)."""
    return re.findall(r"[^\n]*\n|[^\n]+$", text)
