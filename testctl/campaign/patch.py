"""best.patch: the tuned values, set in the user's own files, as a unified diff `git apply` takes.

A campaign over a program tuned as it is written (`athrill_sim.tuning`) ends with the values in the bench's
slots; the user wants them in the program: the `#define`, the global's initializer, the data file, the
`source` match. The diff's paths are relative to the program's folder (the folder of `--app`, or the
common folder of every file it changes, when a file lies above it). `hako patch apply RUN_DIR` applies it
from wherever the user stands and checks that every file it names now holds the tuned values: git's own
`git apply`, run in that folder inside a repository, takes the paths as relative to the repository's top,
skips every file, says nothing and exits 0 (inside a repository it is `git apply --directory=APP_FROM_TOP`
from the top).
"""

from __future__ import annotations

import dataclasses
import difflib
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from athrill_sim.tuning.forms.form import file_bytes, file_text
from athrill_sim.tuning.tune import Tuning, apply_edits
from hakoniwa.wire.errors import HakoError

BEST_PATCH = "best.patch"
BEST_JSON = "best.json"  # the report's, whose `patch` says where best.patch applies and what it sets
_NO_NEWLINE = "\\ No newline at end of file\n"
_HUNK = re.compile(r"^@@ -(\d+)(?:,(\d+))? \+(\d+)(?:,(\d+))? @@")


class PatchError(HakoError, ValueError):
    """best.patch cannot be applied as it is: the one line says which file and why."""


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
        line = f"{BEST_PATCH} sets {what}: apply with hako patch apply {patch.parent.resolve()}"
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


def apply_patch(run_dir: Path, check: bool = False) -> list[str]:
    """Set the tuned values in the user's files as `run_dir`'s best.patch says, all files or none, and check
    that each then holds them; the lines that say what was set. With `check`, only whether it applies."""
    info = _patch_info(run_dir)
    root = Path(info["apply_in"])
    changed: dict[Path, str] = {}
    done = []
    for rel, hunks in _diffs(file_text(run_dir / BEST_PATCH)).items():
        path = root / rel
        old = file_text(path) if path.is_file() else None
        if old is None and hunks and hunks[0].old_start != 0:
            raise PatchError(f"{path}: no such file, which best.patch changes (was the program moved?)")
        try:
            changed[path] = _applied(old, hunks)
        except PatchError as e:
            if old is not None and _undoes(old, hunks):
                done.append(f"{path} already holds best.patch's values")
                continue
            raise PatchError(f"{path}: {e}: was it edited after the campaign?") from None
    if not check:
        for path, text in changed.items():
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(file_bytes(text))
        for path, text in changed.items():
            if file_text(path) != text:
                raise PatchError(f"{path}: does not hold what was written to it")
    verb = "would set" if check else "set"
    return [*done, *(f"{verb} {what} (in {root})" for what in info["sets"] if changed)]


def _undoes(text: str, hunks: list[_Hunk]) -> bool:
    """Whether `text` is what the hunks make: they undo on it."""
    try:
        _applied(text, hunks, reverse=True)
    except PatchError:
        return False
    return True


def _patch_info(run_dir: Path) -> dict[str, Any]:
    """best.json's `patch`: where best.patch applies and what it sets."""
    import json

    try:
        info = json.loads((run_dir / BEST_JSON).read_text()).get("patch")
    except (OSError, ValueError, AttributeError) as e:
        raise PatchError(f"{run_dir}: no campaign's {BEST_JSON} to read ({e})") from None
    if not isinstance(info, dict) or not (run_dir / BEST_PATCH).is_file():
        raise PatchError(f"{run_dir}: the campaign wrote no {BEST_PATCH} (its program's parameters are not set "
                         "in files: a space of offsets, or no set reached the goal)")
    return info


@dataclass(frozen=True)
class _Hunk:
    old_start: int  # 1-based; 0 where the old file has no lines (a new file)
    new_start: int
    lines: tuple[tuple[str, str], ...]  # (" ", "-" or "+"; the line with its newline, where it has one)


def _diffs(text: str) -> dict[str, list[_Hunk]]:
    """The hunks of each file of a diff as `unified_diff` writes it."""
    files: dict[str, list[_Hunk]] = {}
    hunks: list[_Hunk] = []
    for line in _lines(text):
        if line.startswith("diff --git a/"):
            hunks = files.setdefault(line.rstrip("\n").split(" b/", 1)[1], [])
        elif m := _HUNK.match(line):
            hunks.append(_Hunk(int(m[1]), int(m[3]), ()))
        elif line == _NO_NEWLINE and hunks and hunks[-1].lines:
            *before, (sign, last) = hunks[-1].lines
            hunks[-1] = dataclasses.replace(hunks[-1], lines=(*before, (sign, last.removesuffix("\n"))))
        elif hunks and line[:1] in (" ", "-", "+") and not line.startswith(("--- ", "+++ ")):
            hunks[-1] = dataclasses.replace(hunks[-1], lines=(*hunks[-1].lines, (line[0], line[1:])))
    return files


def _applied(old: str | None, hunks: list[_Hunk], reverse: bool = False) -> str:
    """`old` with the hunks applied (`reverse`: undone); PatchError naming the first line that differs."""
    removed = "+" if reverse else "-"
    have = _lines(old or "")
    out: list[str] = []
    at = 0
    for hunk in hunks:
        if hunk.old_start == 0 and have and not reverse:
            raise PatchError("best.patch makes it a new file, and it is there with other lines")
        start = max((hunk.new_start if reverse else hunk.old_start) - 1, 0)
        out += have[at:start]
        at = max(start, at)
        for sign, line in hunk.lines:
            if sign == " " or sign == removed:
                if at >= len(have) or have[at] != line:
                    raise PatchError(f"line {at + 1} is not the line best.patch changes")
                at += 1
            if sign != removed:
                out.append(line)
    return "".join(out + have[at:])
