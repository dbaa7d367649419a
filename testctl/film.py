"""The film a person looks at first when a campaign ends or a CI case fails: the test again, as a video, beside
its trajectory picture. A film that cannot be made here (no OpenGL) is a note, never the campaign's failure:
its results are all written by then."""

from __future__ import annotations

from pathlib import Path

import click

# The best set's lap, and a failing case's worst run: from behind the robot at twice real time (a 35 s lap
# is an 18 s clip); `hako replay OUT --video FILE` films the same run folder at any speed.
LAP_VIDEO = "best_lap.mp4"
CASE_VIDEO = "lap.mp4"
FILM_FPS = 15
FILM_SPEED = 2.0


def film_run(run_dir: Path, out: Path, title: str) -> Path | None:
    """Film the last test of `run_dir` into `out`; None, with a one-line note, when it cannot be made."""
    from hakoniwa.physics.replay import ReplayError, read_replay
    from hakoniwa.pictures.video import VideoError, film
    from hakoniwa.pictures.video_options import VideoOptions

    try:
        film(read_replay(run_dir), VideoOptions(out, "chase", FILM_FPS, FILM_SPEED), title=title)
    except (ReplayError, VideoError, OSError) as e:
        out.unlink(missing_ok=True)  # an older film there would show another run
        click.echo(f"note: no {out.name}: {e}", err=True)
        return None
    return out
