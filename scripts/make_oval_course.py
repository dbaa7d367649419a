"""Draw the floor image of the built-in oval course (paper Fig. 6) into hakoniwa/physics/courses/oval/floor.png.

The image is data the course folder ships; this script documents how it was made and remakes it. The line
edge is a linear ramp, as a texture-filtered camera would see it, so the reflect value varies smoothly
across the edge and a proportional controller has something to work with.
"""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np
from PIL import Image

from hakoniwa.physics.course import COURSES_DIR

FOLDER = COURSES_DIR / "oval"


def oval_distance(x: np.ndarray, y: np.ndarray, half_straight: float, radius: float) -> np.ndarray:
    """Distance from (x, y) to a stadium-shaped path: straights at y = +-radius joined by half circles."""
    cx = np.clip(x, -half_straight, half_straight)
    return np.abs(np.hypot(x - cx, y) - radius)


@click.command()
@click.option("--mpp", default=0.002, show_default=True, help="Metres per pixel.")
@click.option("--width", "size_x", default=3.0, show_default=True, help="Floor width [m].")
@click.option("--height", "size_y", default=1.8, show_default=True, help="Floor height [m].")
@click.option("--half-straight", default=0.75, show_default=True, help="Half length of each straight [m].")
@click.option("--radius", default=0.5, show_default=True, help="Curve radius of the line centre [m].")
@click.option("--line-width", default=0.04, show_default=True, help="Black line width [m].")
@click.option("--edge", default=0.07, show_default=True, help="Width of the grey ramp at each edge [m].")
@click.option("--out", type=click.Path(dir_okay=False, path_type=Path), default=FOLDER / "floor.png",
              show_default=True, help="Where to write the PNG.")
def main(out: Path, mpp: float, size_x: float, size_y: float, half_straight: float, radius: float, line_width: float,
         edge: float) -> None:
    w, h = round(size_x / mpp), round(size_y / mpp)
    xs = -size_x / 2 + (np.arange(w) + 0.5) * mpp
    ys = size_y / 2 - (np.arange(h) + 0.5) * mpp  # row 0 is the top of the image
    d = oval_distance(xs[None, :], ys[:, None], half_straight, radius)
    luminance = np.clip((d - line_width / 2) / edge + 0.5, 0.0, 1.0)
    Image.fromarray(np.round(luminance * 255).astype(np.uint8), mode="L").save(out, optimize=True)
    click.echo(f"wrote {out} ({w}x{h} px)")


if __name__ == "__main__":
    main()
