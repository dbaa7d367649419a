"""`python -m athrill_sim.v850.check ATHRILL2 IMAGE SYNC`: can this image run as a robot program?

Run before the first test (`Program.check_argv`), in a scratch folder of its own, exactly as a test starts
athrill2: the image runs, the physics side holding still, until it first writes into the mapped files (the TX
body starts filled with a pattern no EV3RT driver writes; EV3RT itself writes there as it boots). It fails,
with one line saying why, when athrill2 exits first (a broken emulator, an image it cannot load), or when the
program has written nothing by CHECK_SIM_US of simulated time, or when the emulated clock stands still or
creeps (an image whose start-up blocks): such an image would turn every test into a crash or a TIME_OVER
charged to the parameters, or hang, while the fault is the image's.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

from athrill_sim.programs.athrill2 import athrill_argv, athrill_config
from hakoniwa.wire.protocol import EXT_OFF, MappedFile, SyncMode, Tx, open_athrill, open_unity
from hakoniwa.wire.timebase import US_PER_S
from hakoniwa.wire.wallclock import WallCeiling

CHECK_SIM_US = US_PER_S // 5  # how far an image may run before it writes (EV3RT's boot writes within ms)
CHECK_WALL_S = 60.0  # the least wall time that may take on a loaded machine (a busy loop runs at ~10 sim-ms
# per s); more where the clock is measured to run slower (`WallCeiling`)
CLOCK_STILL_S = 10.0  # an emulated clock that has not moved this long is not going to
POLL_S = 0.01
UNTOUCHED = -0x5A5A5A5B  # 0xA5A5A5A5, the TX body's fill: no LED bits, power or flag an EV3RT driver writes
TX_WORDS = EXT_OFF // 4  # the TX body before our extension area
STOP_WORDS = range(Tx.STOPPED_AT // 4, Tx.STOPPED_AT // 4 + 2)  # where the patched athrill2 stops: not the program's
OUTPUT_LINES = 3
DWARF_ASSERTION = "elf_dwarf_"  # athrill2's DWARF reader asserts on C++ debug information
DWARF_HINT = (" (athrill2 cannot read a C++ image's debug information: strip it with v850-elf-strip --strip-debug, "
              "as hako build does)")


def check(exe: str, image: Path, sync: SyncMode) -> str | None:
    """Why the image cannot run, or None."""
    with tempfile.TemporaryDirectory(prefix="hako-check-") as tmp:
        run_dir = Path(tmp)
        for name, text in athrill_config(sync).items():
            (run_dir / name).write_text(text)
        with open_unity(run_dir, create=True) as unity, open_athrill(run_dir, create=True) as athrill:
            athrill.write_i32s(0, [UNTOUCHED] * TX_WORDS)
            unity.snapshot_end_us = unity.unity_time_us = CHECK_SIM_US  # the files as they stand are the inputs
            log = run_dir / "athrill.log"
            try:
                with open(log, "w") as out:
                    proc = subprocess.Popen(athrill_argv(exe, image), cwd=run_dir, stdin=subprocess.DEVNULL,
                                            stdout=out, stderr=subprocess.STDOUT)
            except OSError as e:
                return f"cannot start {exe}: {e.strerror}"
            exited, stalled = _watch(proc, athrill)
            if not _untouched(athrill):
                return None
            name, reached = f"{Path(exe).name} {image}", athrill.athrill_time_us
            if stalled is not None:
                return f"{name}: {stalled} (its start-up blocks?), and the program wrote nothing to the mapped files"
            if exited is not None:
                said = " / ".join(line.strip() for line in log.read_text(errors="replace").splitlines()[-OUTPUT_LINES:]
                                  if line.strip())
                hint = DWARF_HINT if DWARF_ASSERTION in said else ""
                return (f"{name}: athrill2 exited at once (status {exited}) after {reached} us of simulated time"
                        + (f": {said}" if said else "") + hint)
            return (f"{name}: the program wrote nothing to the mapped files in its first {CHECK_SIM_US // 1000} "
                    "simulated ms (no motor power, LED or flag): not an EV3RT robot program?")


def _untouched(athrill: MappedFile) -> bool:
    return all(word == UNTOUCHED for i, word in enumerate(athrill.read_i32s(0, TX_WORDS)) if i not in STOP_WORDS)


def _watch(proc: subprocess.Popen, athrill: MappedFile) -> tuple[int | None, str | None]:
    """Let athrill2 run until the program writes, its clock reaches CHECK_SIM_US, it exits, its clock stands
    still for CLOCK_STILL_S or runs past its wall-clock ceiling; then stop it. Returns its exit status if it
    exited by itself first, and what stalled if the clock did."""
    ceiling = WallCeiling(CHECK_SIM_US, floor_s=CHECK_WALL_S)
    clock, moved = athrill.athrill_time_us, time.monotonic()
    try:
        while _untouched(athrill) and athrill.athrill_time_us < CHECK_SIM_US and proc.poll() is None:
            time.sleep(POLL_S)
            now, seen = time.monotonic(), athrill.athrill_time_us
            if seen != clock:
                clock, moved = seen, now
            elif now - moved > CLOCK_STILL_S:
                return None, f"the emulator's clock did not move for {now - moved:.0f} s, at {seen} us"
            if (why := ceiling.exceeded(seen)) is not None:
                return None, why
        return proc.poll(), None
    finally:
        proc.kill()
        proc.wait()


def main() -> None:
    exe, image, sync = sys.argv[1:]
    why = check(exe, Path(image), SyncMode[sync.upper()])
    if why is not None:
        print(why)
        sys.exit(1)


if __name__ == "__main__":
    main()
