"""The done-when test of interrupts in a validation: Ctrl-C (or SIGTERM) at random moments while the best set
is validated on two Dask benches ends `hako run` within a second, with one line and 130 (143), and the
journal then resumes the validation where it stopped, never running a draw twice."""

from __future__ import annotations

import json
import os
import random
import signal
import subprocess
import sys
import threading
import time

import pytest

from testctl.campaign.journal import JOURNAL_FILE, PHASE_VALIDATION, read_journal
from tests.helpers.processes import interruptible

DRAWS = 20  # about 4 s on two benches: signals sent 0-1.5 s into it mostly land inside it
VALIDATING = "validating the best set"


def start(args: list[str]) -> tuple[subprocess.Popen, list[str]]:
    proc = subprocess.Popen([sys.executable, "-m", "testctl.hako", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True, preexec_fn=interruptible)
    lines: list[str] = []
    threading.Thread(target=lambda: lines.extend(proc.stderr), daemon=True).start()
    return proc, lines


def validation_reps(out) -> list[int]:
    return [r.rep for r in read_journal(out / JOURNAL_FILE)[1] if r.phase == PHASE_VALIDATION]


@pytest.mark.slow
def test_a_signal_at_any_moment_of_a_validation_ends_it_at_once_and_it_resumes(tmp_path):
    seed = int.from_bytes(os.urandom(4), "little")
    rng = random.Random(seed)
    out = tmp_path / "c"
    args = ["run", "--smoke", "--validate", str(DRAWS), "--benches", "2", "--out", str(out)]
    stopped = 0
    for signum, status, word in [(signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143, "terminated"),
                                 (signal.SIGINT, 130, "interrupted")]:
        proc, lines = start(args)
        deadline = time.monotonic() + 300
        while not any(VALIDATING in line for line in lines):
            assert proc.poll() is None and time.monotonic() < deadline, "".join(lines)
            time.sleep(0.02)
        time.sleep(rng.uniform(0.0, 1.5))  # before the first draw, mid-draw, between draws
        if proc.poll() is not None:
            break  # the validation finished first
        sent = time.monotonic()
        os.killpg(proc.pid, signum)
        proc.wait(timeout=30)
        took = time.monotonic() - sent
        time.sleep(0.2)  # the reader's last lines
        err = "".join(lines)
        assert proc.returncode == status, f"seed {seed}: {err}"
        assert took < 1.0, f"seed {seed}: {took:.2f} s"
        said = [line for line in err[err.index(VALIDATING):].splitlines()[1:] if line.strip()]
        assert said == [f"{word}: every finished test is in {out / JOURNAL_FILE}; continue with: "
                        f"hako run --resume {out}"], f"seed {seed}: {err}"
        assert "Traceback" not in err and "Exception ignored" not in err and "leaked" not in err, err
        reps = validation_reps(out)
        assert len(set(reps)) == len(reps) and len(reps) <= DRAWS, f"seed {seed}: {reps}"
        if len(reps) == DRAWS:
            break  # the validation had finished; the signal stopped the report after it
        args = ["run", "--resume", str(out)]  # keeps --validate and --benches' default
        stopped += 1
    assert stopped, "the validation always finished before the signal: make it longer"
    before = len(validation_reps(out))
    proc, lines = start(["run", "--resume", str(out)])
    proc.wait(timeout=600)
    assert proc.returncode == 0, "".join(lines)
    reps = validation_reps(out)
    assert sorted(reps) == sorted(set(reps)) and len(reps) == DRAWS and before <= DRAWS  # none ran twice
    validation = json.loads((out / "best.json").read_text())["validation"]
    assert validation["draws"] == DRAWS and sorted(validation["noise_seeds"]) == sorted(
        r.noise_seed for r in read_journal(out / JOURNAL_FILE)[1] if r.phase == PHASE_VALIDATION)
