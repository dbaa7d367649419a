#!/usr/bin/env python3
"""Checks commit messages: a subject of at most 72 characters, a blank line, then a body that says why.

`git log --oneline`, `git shortlog` and every web view cut a subject at about 72 characters, and the diff already says
what changed, so the reason has to live in the body. The history before BASELINE was written without this rule and
cannot be rewritten, so only the commits after it are checked. A merge needs no body: its reasons are its commits'.

    python scripts/check_commits.py                 # every commit after BASELINE up to HEAD (what .ci/run does)
    python scripts/check_commits.py --base REV TIP  # the commits after REV up to TIP
    python scripts/check_commits.py --message FILE  # one message, as the commit-msg hook in .githooks/ passes it

A clone without BASELINE in its history (a shallow one) is skipped with a line that says so, not failed.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

BASELINE = "540a608"  # the head of main when the rule was made; the commits after it follow it
MAX_SUBJECT = 72
SCISSORS = "# ------------------------ >8 ------------------------"  # git's cut line under `commit -v`


def problems(message: str, merge: bool = False) -> list[str]:
    """What is wrong with one commit message (none when it keeps the rule)."""
    lines = message.rstrip().splitlines()
    subject = lines[0].strip() if lines else ""
    found = []
    if not subject:
        found.append("no subject")
    elif len(subject) > MAX_SUBJECT:
        found.append(f"a subject of {len(subject)} characters (at most {MAX_SUBJECT})")
    if len(lines) > 1 and lines[1].strip():
        found.append("no blank line after the subject")
    if not merge and not any(line.strip() for line in lines[1:]):
        found.append("no body saying why")
    return found


def editor_text(raw: str) -> str:
    """The message git will record from a commit-msg hook's file: without its comment lines and what `-v` adds."""
    kept = []
    for line in raw.splitlines():
        if line == SCISSORS:
            break
        if not line.startswith("#"):
            kept.append(line)
    return "\n".join(kept).strip("\n")


def git(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(["git", *args], capture_output=True, text=True)


def commits(base: str, tip: str) -> list[tuple[str, bool, str]]:
    """(hash, is a merge, message) for each commit after base up to tip, oldest first."""
    out = git("log", "-z", "--reverse", "--format=%H %P%n%B", f"{base}..{tip}")
    if out.returncode != 0:
        raise SystemExit(f"check_commits: git log {base}..{tip}: {out.stderr.strip()}")
    found = []
    for record in filter(None, out.stdout.split("\0")):
        head, _, message = record.lstrip("\n").partition("\n")
        sha, *parents = head.split()
        found.append((sha, len(parents) > 1, message))
    return found


def skip_reason(base: str, tip: str) -> str | None:
    """Why the history cannot be checked against base here, or None when it can."""
    if git("rev-parse", "--is-inside-work-tree").returncode != 0:
        return "not in a git work tree"
    if git("cat-file", "-e", f"{base}^{{commit}}").returncode != 0:
        return f"the baseline {base} is not in this clone's history (a shallow clone?)"
    if git("merge-base", "--is-ancestor", base, tip).returncode != 0:
        return f"{tip} does not descend from the baseline {base}"
    return None


def check_history(base: str, tip: str) -> int:
    reason = skip_reason(base, tip)
    if reason:
        print(f"check_commits: skipped: {reason}")
        return 0
    bad = 0
    checked = commits(base, tip)
    for sha, merge, message in checked:
        for problem in problems(message, merge):
            print(f"{sha[:9]} {message.partition(chr(10))[0][:50]!r}: {problem}")
            bad += 1
    if bad:
        print(f"check_commits: {bad} problem(s) in the commits after {base}; a subject of at most {MAX_SUBJECT} "
              "characters, a blank line, then a body that says why")
        return 1
    print(f"check_commits: {len(checked)} commit(s) after {base}, all with a short subject and a body")
    return 0


def check_message(path: Path) -> int:
    try:
        message = editor_text(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as e:
        print(f"check_commits: cannot read {path}: {e}", file=sys.stderr)
        return 2
    found = problems(message)
    for problem in found:
        print(f"commit message: {problem}", file=sys.stderr)
    if found:
        print(f"commit message: a subject of at most {MAX_SUBJECT} characters, a blank line, then a body that says "
              f"why (your text is kept in {path})", file=sys.stderr)
    return 1 if found else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.partition("\n")[0])
    parser.add_argument("tip", nargs="?", default="HEAD", help="the last commit to check [default: HEAD]")
    parser.add_argument("--base", default=BASELINE, help=f"check the commits after this one [default: {BASELINE}]")
    parser.add_argument("--message", type=Path, metavar="FILE", help="check the one message in FILE instead")
    args = parser.parse_args()
    return check_message(args.message) if args.message else check_history(args.base, args.tip)


if __name__ == "__main__":
    sys.exit(main())
