"""The options that film a test (`hako try --video`, `hako replay`), declared once and imported cheaply: the
renderer itself (`video.py`: MuJoCo's OpenGL, the video writer) loads only when a film is made."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import click

from hakoniwa.conventions import option_group, writable_file

CAMERAS = ("chase", "top")
FORMATS = (".mp4", ".gif")
DEFAULT_FPS = 30
GIF_FPS_MAX = 50  # a GIF's frame delay is in hundredths of a second, and viewers slow anything shorter than 2


class Speed(click.ParamType):
    """A playback speed: `4x`, `4` or `0.5x`, a finite number > 0 (1 is real time)."""

    name = "SPEED"

    def convert(self, value, param, ctx) -> float:
        if isinstance(value, float):
            return value
        text = str(value).strip().lower().removesuffix("x")
        try:
            speed = float(text)
        except ValueError:
            self.fail(f"{value!r} is not a speed such as 1x, 4x or 0.5x", param, ctx)
        if not (math.isfinite(speed) and speed > 0):
            self.fail(f"{value!r}: a speed must be a number > 0 (1x is real time)", param, ctx)
        return speed


@dataclass(frozen=True)
class VideoOptions:
    path: Path
    camera: str = CAMERAS[0]
    fps: int = DEFAULT_FPS
    speed: float = 1.0


def check_video_path(path: Path, fps: int, option: str = "--video") -> None:
    """One line before anything runs: a format we write, a folder we can write into, a frame rate it holds."""
    if path.suffix.lower() not in FORMATS:
        raise click.BadParameter(f"{path}: a video is {' or '.join(FORMATS)}", param_hint=option)
    writable_file(path, option)
    if path.suffix.lower() == ".gif" and fps > GIF_FPS_MAX:
        raise click.BadParameter(f"a GIF holds at most {GIF_FPS_MAX} frames/s, got {fps}", param_hint="--fps")


film_options = option_group([
    click.option("--camera", type=click.Choice(CAMERAS), default=CAMERAS[0], show_default=True,
                 help="chase: behind the robot, as a follow camera; top: the whole course from above."),
    click.option("--fps", type=click.IntRange(1, 120), default=DEFAULT_FPS, show_default=True,
                 help="Frames per second of the video."),
    click.option("--speed", type=Speed(), default="1x", show_default=True,
                 help="Playback speed: 1x is real time, 4x a quick look (also paces --view)."),
])
