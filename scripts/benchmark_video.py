"""What filming a test costs: frames rendered per second (MuJoCo offscreen, with and without the overlay),
per camera and size, and the writers' cost per frame; and what recording the replay costs each test.

Usage: MUJOCO_GL=egl python scripts/benchmark_video.py [--frames N]
Runs one noise-free lap of the paper's tracer (`hako try`) to get a real replay, then renders N frames of
it spread over the lap for each setting (after one unmeasured frame that uploads the textures).
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import click

os.environ.setdefault("MUJOCO_GL", "egl")


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--frames", type=click.IntRange(min=5), default=60, show_default=True, help="Frames per setting.")
def main(frames: int) -> None:
    from hakoniwa.physics.replay import REPLAY_FILE, read_replay, write_replay
    from hakoniwa.pictures.video import Filmer, write_video

    with tempfile.TemporaryDirectory() as tmp:
        run = Path(tmp) / "run"
        subprocess.run([sys.executable, "-m", "testctl.hako", "try", "--noise", "0", "--run-dir", str(run)],
                       check=True, stdout=subprocess.DEVNULL)
        replay = read_replay(run)
        t0 = time.perf_counter()
        for _ in range(20):
            write_replay(Path(tmp) / REPLAY_FILE, replay)
        write_ms = (time.perf_counter() - t0) / 20 * 1000
        print(f"replay of a {replay.duration_us / 1e6:.2f} s lap: {len(replay.times_us)} samples, "
              f"{(run / REPLAY_FILE).stat().st_size / 1024:.0f} KiB, written in {write_ms:.1f} ms")
        print(f"{'camera':7} {'size':8} {'render fps':>10} {'+overlay':>9}")
        times = [replay.duration_us * i / (frames - 1) for i in range(frames)]
        for camera in ("chase", "top"):
            for w, h in ((640, 360), (480, 270), (1280, 720)):
                filmer = Filmer(replay, camera, w, h)
                filmer.render(0)
                rates = []
                for overlay in (False, True):
                    t0 = time.perf_counter()
                    for t in times:
                        filmer.render(t, overlay)
                    rates.append(frames / (time.perf_counter() - t0))
                filmer.close()
                print(f"{camera:7} {w}x{h:<4} {rates[0]:10.1f} {rates[1]:9.1f}")
        filmer = Filmer(replay, "chase")
        shots = [filmer.render(t) for t in times]
        filmer.close()
        for suffix in (".mp4", ".gif"):
            out = Path(tmp) / f"lap{suffix}"
            t0 = time.perf_counter()
            write_video(out, iter(shots), 15, (640, 360))
            dt = time.perf_counter() - t0
            print(f"writing {suffix}: {frames / dt:.0f} frames/s, {out.stat().st_size / frames / 1024:.1f} KiB/frame")


if __name__ == "__main__":
    main()
