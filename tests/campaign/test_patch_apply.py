"""best.patch applied from wherever the user stands: the command the campaign's summary prints works inside a
git repository (every team's layout, and the README's example inside the clone), where `cd APP && git apply`
skips every file, says nothing and exits 0, and it checks that each file then holds the tuned values."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from testctl.campaign.patch import BEST_JSON, BEST_PATCH, PatchError, PatchInfo, apply_patch, unified_diff
from tests.helpers.commands import hako, one_line_error

OLD = "// gains\n#define KP 1.0f\n#define KD 2.0f\n"
NEW = "// gains\n#define KP 1.539f\n#define KD 2.0f\n"
SETS = ("Kp=1.539 (#define KP) in gains.h",)


def campaign_dir(tmp_path: Path, app: Path, diffs: dict[str, tuple[str | None, str]]) -> Path:
    """A run directory as a campaign leaves it: best.patch and best.json's `patch`."""
    run = tmp_path / "runs" / "x"
    run.mkdir(parents=True)
    (run / BEST_PATCH).write_text("".join(unified_diff(old, new, rel) for rel, (old, new) in diffs.items()))
    info = PatchInfo(app, tuple(diffs), SETS, ())
    (run / BEST_JSON).write_text(json.dumps({"patch": info.to_dict()}))
    return run


def repository(tmp_path: Path) -> Path:
    """A team's repository with the program two folders down; the program's folder."""
    if shutil.which("git") is None:
        pytest.skip("needs git")
    repo = tmp_path / "team"
    app = repo / "robot" / "app"
    app.mkdir(parents=True)
    (app / "gains.h").write_text(OLD)
    subprocess.run(["git", "init", "-q", str(repo)], check=True)
    return app


def test_the_summarys_command_sets_the_values_inside_a_repository(tmp_path):
    app = repository(tmp_path)
    run = campaign_dir(tmp_path, app, {"gains.h": (OLD, NEW)})
    line = PatchInfo(app, ("gains.h",), SETS, ()).describe(run / BEST_PATCH)
    command = line.split("apply with ", 1)[1]
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    r = subprocess.run(command, shell=True, cwd=app, capture_output=True, text=True, env=env, timeout=120)
    assert r.returncode == 0, r.stderr
    assert (app / "gains.h").read_text() == NEW
    assert r.stdout.splitlines() == [f"set {SETS[0]} (in {app})"]


def test_it_applies_from_anywhere_says_when_already_applied_and_refuses_an_edited_file(tmp_path):
    app = repository(tmp_path)
    run = campaign_dir(tmp_path, app, {"gains.h": (OLD, NEW), "sdcard/gains.csv": (None, "kp\n1.539\n")})
    assert apply_patch(run, check=True) == [f"would set {SETS[0]} (in {app})"]
    assert (app / "gains.h").read_text() == OLD and not (app / "sdcard").exists()
    r = hako("patch", "apply", str(run), cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (app / "gains.h").read_text() == NEW and (app / "sdcard" / "gains.csv").read_text() == "kp\n1.539\n"
    assert apply_patch(run) == [f"{app / 'gains.h'} already holds best.patch's values",
                                f"{app / 'sdcard' / 'gains.csv'} already holds best.patch's values"]
    (app / "gains.h").write_text(OLD.replace("1.0f", "0.9f"))
    r = hako("patch", "apply", str(run))
    one_line_error(r, str(app / "gains.h"), "line 2", "edited after the campaign")
    assert (app / "gains.h").read_text() == OLD.replace("1.0f", "0.9f")


def test_a_program_moved_since_the_campaign_is_one_line(tmp_path):
    app = tmp_path / "app"
    app.mkdir()
    run = campaign_dir(tmp_path, app, {"gains.h": (OLD, NEW)})
    one_line_error(hako("patch", "apply", str(run)), f"{app / 'gains.h'}: no such file", "moved")


def test_a_run_directory_without_a_patch_is_one_line(tmp_path):
    r = hako("patch", "apply", str(tmp_path))
    one_line_error(r, "best.json")
    (tmp_path / BEST_JSON).write_text("{}")
    with pytest.raises(PatchError, match="wrote no best.patch"):
        apply_patch(tmp_path)


LINES = st.lists(st.text(st.characters(codec="ascii", exclude_characters="\r\n\x00"), max_size=12), max_size=12)


@settings(max_examples=60, deadline=None)
@given(old=LINES, new=LINES, old_nl=st.booleans(), new_nl=st.booleans())
def test_a_diff_applies_and_gives_the_new_text(tmp_path_factory, old, new, old_nl, new_nl):
    app = tmp_path_factory.mktemp("app")
    before = "\n".join(old) + ("\n" if old_nl and old else "")
    after = "\n".join(new) + ("\n" if new_nl and new else "")
    (app / "gains.h").write_text(before)
    run = campaign_dir(app, app, {"gains.h": (before, after)})
    apply_patch(run)
    assert (app / "gains.h").read_text() == after
