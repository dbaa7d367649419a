"""A program's own failures are its outcome, shown to the user: a Python program's error (its last lines, in
the result and on stderr), an exit with any status (3 included), and a log that cannot fill the disk. Only a
marked exit is the bench's fault."""

from __future__ import annotations

import json
import os
import subprocess
import threading
from pathlib import Path

import pytest

from hakoniwa.wire.exits import EXIT_BENCH_FAULT
from hakoniwa.wire.output import CappedOutput
from hakoniwa.wire.processes import BENCH_FAULT_MARKER
from hakoniwa.wire.protocol import ATHRILL_FILE
from tests.helpers.commands import hako, one_line_error, run_module
from tests.helpers.native_fixtures import FakePhysics, build, need_cc

APPS = '''
import sys


def raises(api):
    api.tslp_tsk(100_000)
    raise RuntimeError("the program's own error")


def exits(api):
    api.tslp_tsk(100_000)
    sys.exit(3)
'''


def trial(tmp_path: Path, app: str, *extra: str) -> subprocess.CompletedProcess:
    (tmp_path / "failing_apps.py").write_text(APPS)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path), os.environ.get("PYTHONPATH", "")]))
    return hako("try", "--app", app, "--time-limit", "2", "--json", *extra, env=env)


def test_a_python_program_that_raises_shows_its_own_error(tmp_path):
    r = trial(tmp_path, "failing_apps:raises")
    assert r.returncode == 0, r.stderr
    result = json.loads(r.stdout)
    assert result["crash"] == "program"
    assert "RuntimeError: the program's own error" in result["program_output"].splitlines()[-1]
    assert "RuntimeError: the program's own error" in r.stderr and "program's last lines" in r.stderr


def test_a_python_program_that_cannot_take_the_api_shows_why(tmp_path):
    r = trial(tmp_path, "os:getcwd")
    assert json.loads(r.stdout)["program_output"].splitlines()[-1].startswith("TypeError: ")


def test_a_python_app_that_is_no_function_is_one_line_before_any_test(tmp_path):
    one_line_error(trial(tmp_path, "math:pi"), "--app math:pi", "is not a function")


def test_exit_3_in_a_python_program_is_the_programs_outcome(tmp_path):
    result = json.loads(trial(tmp_path, "failing_apps:exits").stdout)
    assert (result["event"], result["crash"], result["crash_detail"]) == ("CRASH", "program", 3)


def test_exit_3_in_a_c_program_is_the_programs_outcome(tmp_path):
    app = tmp_path / "exits.c"
    need_cc()
    app.write_text('#include <stdlib.h>\n#include "ev3api.h"\n'
                   'void main_task(intptr_t u) { tslp_tsk(100000); exit(3); }\n')
    result = json.loads(hako("try", "--app", str(app), "--time-limit", "2", "--json").stdout)
    assert (result["event"], result["crash"], result["crash_detail"]) == ("CRASH", "program", 3)


def damaged_run_dir(tmp_path: Path) -> Path:
    bench = FakePhysics(tmp_path / "run")
    bench.close()
    (tmp_path / "run" / ATHRILL_FILE).write_bytes(b"ETTX" + bytes(100))
    return tmp_path / "run"


def test_the_c_runtime_marks_its_bench_faults(tmp_path):
    exe = build(tmp_path / "app", '#include "ev3api.h"\nvoid main_task(intptr_t unused) { }\n')
    run_dir = damaged_run_dir(tmp_path)
    proc = subprocess.run([str(exe), "--run-dir", str(run_dir)], capture_output=True, timeout=30)
    assert proc.returncode == EXIT_BENCH_FAULT
    assert "size 104 bytes, expected 8192" in (run_dir / f"{BENCH_FAULT_MARKER}{proc_pid(run_dir)}").read_text()


def test_the_mock_marks_its_bench_faults(tmp_path):
    run_dir = damaged_run_dir(tmp_path)
    proc = run_module("athrill_sim.mock.main", "--app", "line_trace", "--run-dir", str(run_dir), timeout=60)
    assert proc.returncode == EXIT_BENCH_FAULT
    assert "size 104 bytes, expected 8192" in (run_dir / f"{BENCH_FAULT_MARKER}{proc_pid(run_dir)}").read_text()


def proc_pid(run_dir: Path) -> int:
    """The pid in the one marker the process left."""
    (marker,) = run_dir.glob(f"{BENCH_FAULT_MARKER}*")
    return int(marker.name.removeprefix(BENCH_FAULT_MARKER))


@pytest.mark.parametrize("sizes", [[10], [60, 60], [1] * 300, [1000], [49, 2, 49]])
def test_the_log_keeps_head_and_tail_within_its_cap_and_says_so(tmp_path, sizes):
    cap = 100
    data = b"".join(bytes([65 + i % 26]) * n for i, n in enumerate(sizes))
    read, write = os.pipe()
    with open(tmp_path / "log", "wb") as log:
        out = CappedOutput(open(read, "rb"), log, threading.Lock(), "test 1", cap=cap)
        with open(write, "wb") as w:
            for i, n in enumerate(sizes):
                w.write(bytes([65 + i % 26]) * n)
                w.flush()
        out.join()
    written = (tmp_path / "log").read_bytes()
    if len(data) <= cap:
        assert written == data
    else:
        head, note, tail = written[:cap // 2], written[cap // 2:-(cap - cap // 2)], written[-(cap - cap // 2):]
        assert head == data[:cap // 2] and tail == data[-(cap - cap // 2):]
        assert f"test 1 printed {len(data)} bytes".encode() in note
        assert f"{len(data) - cap} bytes in the middle were left out".encode() in note


@pytest.mark.slow
def test_a_program_that_prints_without_end_leaves_a_capped_log(tmp_path):
    from hakoniwa.wire.output import LOG_CAP_BYTES

    (tmp_path / "noisy_app.py").write_text('def main_task(api):\n    while True:\n'
                                           '        print("x" * 65535, flush=True)\n        api.tslp_tsk(100_000)\n')
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    run_dir = tmp_path / "run"
    r = hako("try", "--app", "noisy_app:main_task", "--time-limit", "20", "--run-dir", str(run_dir), env=env)
    assert r.returncode == 0, r.stderr
    log = (run_dir / "athrill.log").read_bytes()
    assert LOG_CAP_BYTES < len(log) < LOG_CAP_BYTES + 1000
    assert b"bytes in the middle were left out" in log


def test_an_empty_c_program_is_told_it_defines_no_task_function(tmp_path):
    need_cc()
    (tmp_path / "app.c").write_text("")
    one_line_error(hako("try", "--app", str(tmp_path / "app.c")),
                   "defines no function main_task, a task or handler function that app.cfg names")
