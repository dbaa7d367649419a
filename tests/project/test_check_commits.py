"""scripts/check_commits.py: the commit-message rule, on a history of its own and on one message as the hook sees it."""

import subprocess
import sys
from pathlib import Path

from tests.helpers.paths import SCRIPTS

SCRIPT = SCRIPTS / "check_commits.py"


def _git(repo: Path, *args: str) -> str:
    return subprocess.run(["git", "-C", str(repo), *args], check=True, capture_output=True, text=True).stdout.strip()


def _commit(repo: Path, message: str) -> str:
    _git(repo, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "--allow-empty", "--cleanup=verbatim",
         "-m", message)
    return _git(repo, "rev-parse", "HEAD")


def _check(cwd: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, str(SCRIPT), *args], cwd=cwd, capture_output=True, text=True)


def test_only_the_commits_after_the_baseline_are_checked(tmp_path):
    _git(tmp_path, "init", "-q")
    _commit(tmp_path, "An old subject far longer than seventy-two characters, from before the rule was made")
    base = _commit(tmp_path, "The baseline\n\nwhy")
    good = _check(tmp_path, "--base", base)
    assert good.returncode == 0 and "0 commit(s) after" in good.stdout
    _commit(tmp_path, "Short\n\nBecause it says why.")
    _commit(tmp_path, "x" * 73 + "\n\nwhy")
    _commit(tmp_path, "No body")
    _commit(tmp_path, "Subject\nno blank line")
    r = _check(tmp_path, "--base", base)
    assert r.returncode == 1
    assert r.stdout.count("\n") == 4, r.stdout
    assert "a subject of 73 characters (at most 72)" in r.stdout
    assert "'No body': no body saying why" in r.stdout
    assert "'Subject': no blank line after the subject" in r.stdout


def test_a_clone_without_the_baseline_is_skipped_with_its_reason(tmp_path):
    _git(tmp_path, "init", "-q")
    _commit(tmp_path, "No body")
    r = _check(tmp_path, "--base", "0" * 40)
    assert r.returncode == 0 and r.stdout.startswith("check_commits: skipped: the baseline ")


def test_the_hook_reads_the_message_as_git_will_record_it(tmp_path):
    message = tmp_path / "COMMIT_EDITMSG"
    message.write_text("Short subject\n\nThe reason.\n# Please enter the commit message\n")
    assert _check(tmp_path, "--message", str(message)).returncode == 0
    message.write_text("Short subject\n# Please enter the commit message\n"
                       "# ------------------------ >8 ------------------------\ndiff --git a/x b/x\n")
    r = _check(tmp_path, "--message", str(message))
    assert r.returncode == 1 and "commit message: no body saying why" in r.stderr
    r = _check(tmp_path, "--message", str(tmp_path / "missing"))
    assert r.returncode == 2 and "Traceback" not in r.stderr and "cannot read" in r.stderr
