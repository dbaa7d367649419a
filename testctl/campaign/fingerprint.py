"""What a campaign's results depend on besides its options: the files of its program (with every file a
parameter's kind reads or rewrites: a define's or a source match's header, a data file's template, and every
file a test's copy of its workspace holds: the app folder's command files and the workspace's own files) and of
its course (the course folder holds the robot's wiring too), hashed into the journal's header.

A resume that runs another program gives sets measured with two programs under one name (the issue's case:
sets 1-2 lapped at 37 s with the old app.c, sets 3-5 at 23 s with the new one), so `--resume` compares the
hashes and refuses, naming the files that changed. Every recorded bench option that names a file or folder
is covered, so options added later are too. What a journal did not record is not checked: one written before
the workspace's files were hashed (`WORKSPACE`) still resumes, on the files it did record.
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Iterable, Mapping
from pathlib import Path

from testctl.bench_options import BenchOptions

FILES_KEY = "files"  # where the hashes live in the journal header's "bench"
WORKSPACE = "workspace"  # beside the options' own: the files of the program's workspace a test's copy holds


def file_hashes(files: Iterable[Path]) -> dict[str, str]:
    """{name relative to the files' common folder: sha256}."""
    paths = sorted({Path(f).resolve() for f in files})
    if not paths:
        return {}
    root = Path(os.path.commonpath([p.parent for p in paths]))
    return {str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest() for p in paths}


def folder_files(path: Path) -> list[Path]:
    if path.is_file():
        return [path]
    return [f for f in sorted(path.rglob("*")) if f.is_file() and not f.name.startswith(".")]


def fingerprint(bench: BenchOptions, fields: Iterable[str]) -> dict[str, dict[str, str]]:
    """The hashes of what each of `fields` names: the program's files for `app` (and, under WORKSPACE, the
    other files each test's copy of its workspace holds), the course folder for `course`, and the file or
    folder any other option names."""
    from athrill_sim.programs.program import card_files
    from athrill_sim.programs.resolve import resolve_program
    from hakoniwa.physics.course import course_file

    out: dict[str, dict[str, str]] = {}
    for field in fields:
        value = getattr(bench, field)
        if field == "app":
            program = resolve_program(value, athrill2=bench.athrill2, emulator=bench.emulator, sync=bench.sync,
                                      bindings=bench.bindings)
            files = [*program.files, *card_files(program.sdcard)]
            if program.working_folder is not None and program.working_folder.app is not None:
                seen = {f.resolve() for f in files}
                out[WORKSPACE] = file_hashes(f for f in program.working_folder.files() if f.resolve() not in seen)
        elif field == "course":
            files = folder_files(course_file(value).parent)
        elif isinstance(value, str) and Path(value).exists():
            files = folder_files(Path(value))
        else:
            continue
        out[field] = file_hashes(files)
    return out


def changes(stored: Mapping[str, Mapping[str, str]], now: Mapping[str, Mapping[str, str]],
            bench: BenchOptions) -> list[str]:
    """What differs, per option, in words: `--app app.c: app.c changed`. What the journal did not record
    (one written before the workspace was hashed) cannot be checked, and is not."""
    out = []
    for field in sorted(stored):
        before, after = stored[field], now.get(field, {})
        what = [f"{name} {'changed' if name in before and name in after else 'added' if name in after else 'removed'}"
                for name in sorted(set(before) | set(after)) if before.get(name) != after.get(name)]
        if what:
            option = f"--app {bench.app} (its workspace)" if field == WORKSPACE else \
                f"--{field.replace('_', '-')} {getattr(bench, field)}"
            out.append(f"{option}: {', '.join(what)}")
    return out
