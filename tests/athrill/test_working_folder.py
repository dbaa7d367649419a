"""A native program runs in a scratch copy of its workspace, one per test, as `make app=NAME start` runs it on the
robot: its relative paths and getcwd() resolve as there, what it writes is kept in the run directory, and the
user's own tree is never written."""

from __future__ import annotations

import hashlib
from pathlib import Path

import pytest

from athrill_sim.programs.working_folder import MAX_BYTES, WorkingFolder, WorkingFolderError
from hakoniwa.wire.rundir import WORKSPACE_DIR, WORKSPACES_DIR
from tests.helpers.bench_fixtures import PAPER, physics
from tests.helpers.native_fixtures import need_cc


def workspace(tmp_path: Path) -> Path:
    """ws/ holding a root file, another app, and the app `tracer` with a hidden folder and an SD card."""
    ws = tmp_path / "ws"
    app = ws / "tracer"
    (app / "datafiles").mkdir(parents=True)
    (app / ".git").mkdir()
    (app / ".git" / "HEAD").write_text("ref: main\n")
    (app / "sdcard").mkdir()
    (app / "sdcard" / "card.txt").write_text("on the card\n")
    (app / "datafiles" / "gains.csv").write_text("LineTrace,1.5\n")
    (app / "app.h").write_text('#include "ev3api.h"\nvoid main_task(intptr_t exinf);\n')
    (app / "app.cfg").write_text('#include "app.h"\nCRE_TSK(MAIN_TASK, { TA_ACT, 0, main_task, 2, 4096, NULL });\n')
    (ws / "tracer.ini").write_text("[pid]\nkp = 1\n")
    (ws / "other_app").mkdir()
    (ws / "other_app" / "big.bin").write_bytes(b"x" * 1000)
    return ws


def test_a_copy_holds_the_workspaces_files_the_app_folder_and_the_sd_card_at_its_root(tmp_path):
    ws = workspace(tmp_path)
    folder = WorkingFolder.of(ws / "tracer", ws / "tracer" / "sdcard").make(tmp_path / "copy")
    found = sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file())
    assert found == ["card.txt", "tracer.ini", "tracer/app.cfg", "tracer/app.h", "tracer/datafiles/gains.csv",
                     "tracer/sdcard/card.txt"]


def test_an_app_c_beside_its_app_cfg_is_its_app_folder_and_a_lone_file_has_no_workspace(tmp_path):
    ws = workspace(tmp_path)
    (ws / "tracer" / "app.c").write_text("")
    assert WorkingFolder.of(ws / "tracer" / "app.c", None).app == (ws / "tracer").resolve()
    (tmp_path / "lone.c").write_text("")
    lone = WorkingFolder.of(tmp_path / "lone.c", None)
    assert lone.app is None and lone.root_files == ()
    assert lone.app_folder(tmp_path / "copy") == tmp_path / "copy"


def test_a_workspace_too_large_to_copy_for_every_test_is_one_line(tmp_path, monkeypatch):
    ws = workspace(tmp_path)
    monkeypatch.setattr("athrill_sim.programs.working_folder.MAX_BYTES", 10)
    with pytest.raises(WorkingFolderError, match=r"tracer: its workspace holds 0 MiB, copied for every test; keep it "
                                                 r"under 0 MiB \(large data outside the app folder"):
        WorkingFolder.of(ws / "tracer", None)
    assert MAX_BYTES >= 2**20


PROGRAM = r"""
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include "ev3api.h"

static volatile sig_atomic_t stop;
static void on_interrupt(int sig) { (void)sig; stop = 1; }

void main_task(intptr_t unused)
{
    char path[512], line[64] = "";
    FILE *gains = fopen("./tracer/datafiles/gains.csv", "r");
    if (gains != NULL) { fgets(line, sizeof line, gains); fclose(gains); }
    getcwd(path, sizeof path);
    strcat(path, "/tracer.ini");
    const char *where = access(path, R_OK) == 0 ? "the workspace" : "nowhere";
    printf("read %s and tracer.ini from %s\n", strtok(line, "\n"), where);
    FILE *changed = fopen("./tracer/datafiles/gains.csv", "a");
    fprintf(changed, "written by a test\n");
    fclose(changed);
    signal(SIGINT, on_interrupt);
    FILE *log = fopen("./tracer/run.log", "w");
    while (!stop) { fprintf(log, "tick\n"); tslp_tsk(100 * 1000); }
    fprintf(log, "closed on interrupt\n");
    fclose(log);
}
"""


def tree_digest(folder: Path) -> str:
    h = hashlib.sha256()
    for p in sorted(folder.rglob("*")):
        h.update(str(p.relative_to(folder)).encode())
        if p.is_file():
            h.update(p.read_bytes())
    return h.hexdigest()


@pytest.mark.slow
def test_each_test_runs_in_a_fresh_copy_kept_after_it_and_the_users_tree_is_never_written(tmp_path, monkeypatch):
    need_cc()
    ws = workspace(tmp_path)
    (ws / "tracer" / "app.c").write_text(PROGRAM)
    before = tree_digest(ws)
    monkeypatch.chdir(tmp_path)
    run_dir = Path("run")  # relative, as `hako test --out build/x` gives it; the program starts elsewhere
    with physics(run_dir, app=str(ws / "tracer")) as (_, runner):
        for _ in range(2):
            runner.run_test(PAPER)
    assert tree_digest(ws) == before
    log = (run_dir / "athrill.log").read_text()
    assert log.count("read LineTrace,1.5 and tracer.ini from the workspace") == 2  # not the first test's line
    kept = run_dir / WORKSPACE_DIR
    assert (kept / "tracer" / "datafiles" / "gains.csv").read_text() == "LineTrace,1.5\nwritten by a test\n"
    assert (kept / "tracer" / "run.log").read_text().endswith("tick\nclosed on interrupt\n")
    assert (kept / "card.txt").is_file() and not (kept / "tracer" / ".git").exists()
    assert not any((run_dir / WORKSPACES_DIR).iterdir())
