"""User mice run unchanged through `mazelog explore --mouse`: the mms templates, a floodfill mouse, and mice that
break the protocol (one line each, exit 1, the log of what was sensed so far kept)."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from maze.files.builtin import builtin_path
from maze.files.mazefile import parse_maze
from maze.log.restore import load_log, restore
from tests.helpers.commands import mazelog
from tests.helpers.paths import MICE
from tests.helpers.processes import interruptible

PY = sys.executable


def field(output: str, name: str) -> str:
    return next(line.split(":", 1)[1].strip() for line in output.splitlines() if line.startswith(name + ":"))


def sensed_walls_are_true(log: Path, maze_name: str) -> int:
    truth = parse_maze(builtin_path(maze_name).read_text())
    restored, contradictions = restore(load_log(log.read_bytes(), truth.size, strict=True).records, truth.size)
    assert contradictions == 0
    known = [(x, y, d) for x, y, d in truth.inner_walls() if restored.is_known(x, y, d)]
    assert all(restored.is_wall(x, y, d) == truth.is_wall(x, y, d) for x, y, d in known)
    return len(known)


def test_mms_python_template_runs_unchanged(tmp_path: Path) -> None:
    log = tmp_path / "py.bin"
    r = mazelog("explore", "japan2019hef", "--mouse", f"{PY} {MICE / 'mms_python' / 'Main.py'}", "--max-steps", 2000,
            "--log", log)
    assert r.exit_code == 0, r.output
    assert "--max-steps 2000 reached" in r.output and field(r.output, "steps") == "2000"
    assert sensed_walls_are_true(log, "japan2019hef") > 100
    assert (tmp_path / "py.stderr.txt").read_text().startswith("Running...")


def test_mms_cpp_template_runs_unchanged(tmp_path: Path) -> None:
    gxx = shutil.which("g++")
    if gxx is None:
        pytest.skip("g++ is not on PATH: the mms-cpp template cannot be built")
    exe = tmp_path / "mouse"
    src = MICE / "mms_cpp"
    subprocess.run([gxx, "-O1", "-o", exe, src / "Main.cpp", src / "API.cpp"], check=True)
    log = tmp_path / "cpp.bin"
    r = mazelog("explore", "japan2019hef", "--mouse", exe, "--max-steps", 2000, "--log", log)
    assert r.exit_code == 0, r.output
    assert field(r.output, "steps") == "2000"
    assert sensed_walls_are_true(log, "japan2019hef") > 100


def test_floodfill_mouse_knows_the_path_that_mazelog_path_finds_on_its_log(tmp_path: Path) -> None:
    log = tmp_path / "ff.bin"
    maze = "alljapan-010-1989-fin"
    r = mazelog("explore", maze, "--mouse", f"{PY} {MICE / 'floodfill.py'}", "--objective", "time", "--diagonal",
            "--log", log)
    assert r.exit_code == 0, r.output
    assert "the program exited, status 0" in r.output
    found = field(r.output, "fastest path").split()[1]  # "found 7.929 s, true ..."
    p = mazelog("path", log, "--maze", maze, "--objective", "time", "--diagonal")
    assert p.exit_code == 0, p.output
    assert field(p.output, "time").split()[0] == found
    assert "best-run-distance -1" not in r.output  # it reached the goal: mms recorded a run
    belief = (tmp_path / "ff.belief.bin").read_bytes()
    assert len(belief) > 0 and sensed_walls_are_true(log, maze) > 50


@pytest.mark.parametrize("mouse, words", [
    ("bad/garbage.py", "line 3 of the program's output: unknown command 'hello simulator'"),
    ("bad/exits.py", "the program exited with status 3: my mouse: out of memory"),
    ("bad/badcoords.py", "line 4 of the program's output: N must be an integer, got 'x'"),
    ("bad/flood.py", "line 2 of the program's output is longer than 65536 bytes (no mms command is)"),
    ("bad/killed.py", "the program was killed by signal 9"),
])
def test_a_broken_mouse_gets_one_line_and_its_log_is_kept(tmp_path: Path, mouse: str, words: str) -> None:
    log = tmp_path / "bad.bin"
    r = mazelog("explore", "minimaze", "--mouse", f"{PY} {MICE / mouse}", "--log", log)
    assert r.exit_code == 1
    error = [line for line in r.output.splitlines() if line.startswith("Error:")]
    assert len(error) == 1 and words in error[0], r.output
    if "flood" not in mouse:
        assert len(log.read_bytes()) >= 2  # the walls sensed in cell (0, 1) before it broke
    assert log.exists()


def test_a_mouse_that_never_reads_its_answers_times_out(tmp_path: Path) -> None:
    r = mazelog("explore", "minimaze", "--mouse", f"{PY} {MICE / 'bad' / 'deaf.py'}", "--timeout", "0.5",
            "--log", tmp_path / "d.bin")
    assert r.exit_code == 1
    assert "Error: --mouse: the program read none of its answers for 0.5 s" in r.output
    assert len((tmp_path / "d.bin").read_bytes()) >= 2


def test_a_mouse_that_never_answers_times_out(tmp_path: Path) -> None:
    r = mazelog("explore", "minimaze", "--mouse", f"{PY} {MICE / 'bad' / 'silent.py'}", "--timeout", "0.5",
            "--log", tmp_path / "s.bin")
    assert r.exit_code == 1
    assert "Error: --mouse: the program sent no command for 0.5 s (last command: 'wallFront' (line 1))" in r.output


def test_a_slow_start_up_is_not_a_silence(tmp_path: Path) -> None:
    """--timeout is the wait for each next command; the first one also waits for the program to start."""
    r = mazelog("explore", "minimaze", "--mouse", f"{PY} {MICE / 'bad' / 'slowstart.py'}", "--timeout", "0.5",
            "--log", tmp_path / "slow.bin")
    assert r.exit_code == 0, r.output


def test_a_mouse_that_never_starts_talking_times_out(tmp_path: Path, monkeypatch) -> None:
    import maze.mouse.harness

    monkeypatch.setattr(maze.mouse.harness, "STARTUP_S", 1.0)
    r = mazelog("explore", "minimaze", "--mouse", f"{PY} {MICE / 'bad' / 'mute.py'}", "--timeout", "0.2",
            "--log", tmp_path / "m.bin")
    assert r.exit_code == 1
    assert "Error: --mouse: the program sent no command for 1 s (last command: (none yet))" in r.output


def test_bad_coordinates_are_a_warning_as_mms_ignores_them(tmp_path: Path) -> None:
    r = mazelog("explore", "minimaze", "--mouse", f"{PY} {MICE / 'bad' / 'badcoords.py'}", "--log",
                str(tmp_path / "b.bin"))
    assert "warning: setColor 99 99: outside the 16x16 maze (ignored, as mms does)" in r.stderr


@pytest.mark.parametrize("command, words", [
    ("nosuchmouse --fast", "'nosuchmouse' is not found on PATH"),
    ("./not/here", "'./not/here' is not an executable file"),
    ("'unclosed", "No closing quotation"),
])
def test_mouse_naming_no_program(tmp_path: Path, command: str, words: str) -> None:
    r = mazelog("explore", "minimaze", "--mouse", command, "--log", tmp_path / "x.bin")
    assert r.exit_code == 1 and words in r.output and "Traceback" not in r.output


def test_strategy_and_mouse_exclude_each_other(tmp_path: Path) -> None:
    r = mazelog("explore", "minimaze", "--mouse", "true", "--strategy", "full", "--log", tmp_path / "x.bin")
    assert r.exit_code == 2 and "exclude each other" in r.output
    r = mazelog("explore", "minimaze", "--max-steps", 5, "--log", tmp_path / "x.bin")
    assert r.exit_code == 2 and "--max-steps needs --mouse" in r.output


def test_reset_and_power_cut_leave_the_log_a_restore_path_must_handle(tmp_path: Path) -> None:
    log = tmp_path / "cut.bin"
    r = mazelog("explore", "alljapan-010-1989-fin", "--mouse", f"{PY} {MICE / 'floodfill.py'}", "--reset-at", 20,
            "--power-cut", "reset", "--log", log)
    assert r.exit_code == 0, r.output
    assert field(r.output, "resets") == "1"
    assert "records written before the power cut at byte" in r.output and " byte of the next;" in r.output
    assert "reset: restarting from the start" in (tmp_path / "cut.stderr.txt").read_text()
    assert "best-run-distance -1" not in r.output  # it still reached the goal after the reset
    loaded = load_log(log.read_bytes(), 16)
    assert any("torn" in a.reason for a in loaded.anomalies)
    written = int(field(r.output, "wall log").split()[0])
    assert len(loaded.records) == written


def test_time_budget_ends_the_run(tmp_path: Path) -> None:
    r = mazelog("explore", "japan2019hef", "--mouse", f"{PY} {MICE / 'mms_python' / 'Main.py'}", "--time-budget", 20,
            "--log", tmp_path / "b.bin")
    assert r.exit_code == 0 and "--time-budget 20 s of modelled search time used up" in r.output
    assert 20 < float(field(r.output, "search time").split()[0]) < 22


def test_a_film_shows_the_mouse_marks(tmp_path: Path) -> None:
    import numpy as np
    from PIL import Image

    gif, png = tmp_path / "ff.gif", tmp_path / "ff.png"
    r = mazelog("explore", "alljapan-010-1989-fin", "--mouse", f"{PY} {MICE / 'floodfill.py'}", "--log",
            tmp_path / "ff.bin", "--animate", gif, "--png", png)
    assert r.exit_code == 0, r.output
    with Image.open(gif) as film:
        assert film.n_frames > 100
    pixels = np.array(Image.open(png).convert("RGB"))
    assert np.all(pixels == (0, 255, 255), axis=2).sum() > 1000  # the mouse's setColor 'c'


def test_ctrl_c_keeps_the_logs_and_exits_130(tmp_path: Path) -> None:
    import signal
    import time

    log = tmp_path / "int.bin"
    exe = shutil.which("mazelog")
    assert exe is not None
    proc = subprocess.Popen([exe, "explore", "minimaze", "--mouse", f"{PY} {MICE / 'bad' / 'silent.py'}",
                             "--timeout", "30", "--log", str(log)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, preexec_fn=interruptible)
    deadline = time.monotonic() + 60
    stderr = tmp_path / "int.stderr.txt"
    while not (stderr.exists() and stderr.read_text()) and time.monotonic() < deadline:
        time.sleep(0.05)  # until the mouse has had the answer to its one question, and gone quiet
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=20)
    assert proc.returncode == 130
    assert "Error: --mouse: interrupted (Ctrl-C) after 1 command (" in err and "Traceback" not in err
    assert log.exists()


def test_power_cut_at_a_reset_that_never_came_cuts_nothing(tmp_path: Path) -> None:
    log = tmp_path / "whole.bin"
    r = mazelog("explore", "minimaze", "--mouse", f"{PY} {MICE / 'floodfill.py'}", "--reset-at", 100000,
            "--power-cut", "reset", "--log", log)
    assert r.exit_code == 0, r.output
    assert "(no reset happened, so no power cut)" in r.output
    assert not load_log(log.read_bytes(), 16).anomalies


def test_a_chatty_mouse_s_stderr_is_capped_keeping_head_and_tail(tmp_path: Path, monkeypatch) -> None:
    import maze.mouse.harness

    cap = 2000
    monkeypatch.setattr(maze.mouse.harness, "LOG_CAP_BYTES", cap)
    r = mazelog("explore", "minimaze", "--mouse", f"{PY} {MICE / 'bad' / 'chatty.py'}", "--log", tmp_path / "c.bin")
    assert r.exit_code == 1
    assert "Error: --mouse: the program exited with status 3: last words" in r.output  # read from the kept tail
    kept = (tmp_path / "c.stderr.txt").read_bytes()
    printed = len(b"first words\nlast words\n") + sum(len(f"debug line {i}: still thinking\n") for i in range(5000))
    assert kept.startswith(b"first words\n") and kept.endswith(b"debug line 4999: still thinking\nlast words\n")
    assert f"[c.stderr.txt: the program printed {printed} bytes, more than the {cap} kept: ".encode() in kept
    assert len(kept) < cap + 200


def test_a_mouse_cut_at_the_command_cap_exits_with_its_own_status(tmp_path: Path, monkeypatch) -> None:
    import maze.mouse.harness
    from hakoniwa.wire.exits import EXIT_COMMAND_CAP

    monkeypatch.setattr(maze.mouse.harness, "MAX_COMMANDS", 300)
    log = tmp_path / "cap.bin"
    r = mazelog("explore", "japan2019hef", "--mouse", f"{PY} {MICE / 'mms_python' / 'Main.py'}", "--log", log)
    assert r.exit_code == EXIT_COMMAND_CAP != 0
    errors = [line for line in r.stderr.splitlines() if line.startswith("Error:")]
    assert errors == [f"Error: --mouse: cut at 300 commands, its search unfinished (give --max-steps or "
                      f"--time-budget to end it sooner); the log of what it sensed so far is kept in {log}"]
    assert "300 commands sent (a program that never ends its search" in r.stdout
    assert len(log.read_bytes()) >= 2
