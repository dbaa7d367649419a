"""Pictures a person would rather look at than read: the course with the robot's path."""

from __future__ import annotations

import csv
import math
from pathlib import Path

from hakoniwa.physics.course import Course


def read_trajectory(path: Path) -> list[tuple[float, float]]:
    """The path's points; where two share a time the robot was carried (a scenario's place), and a point of
    NaNs between them makes the drawn path jump there instead of crossing the course."""
    points: list[tuple[float, float]] = []
    last_us = None
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if r["time_us"] == last_us:
                points.append((math.nan, math.nan))
            points.append((float(r["x"]), float(r["y"])))
            last_us = r["time_us"]
    return points


def draw_trajectory(course: Course, path_xy: list[tuple[float, float]], out: Path, title: str = "") -> None:
    """Drawn on a bare Figure (Agg), never through pyplot's global state: a campaign draws improving sets on
    a thread of its own while its loop goes on."""
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    fig = Figure(figsize=(11, 5))
    ax = fig.subplots()
    ax.imshow(course.floor, cmap="gray", extent=course.extent, vmin=0, vmax=100, origin="upper")
    for i, w in enumerate(course.walls):
        ax.add_patch(Rectangle((w.x - w.hx, w.y - w.hy), 2 * w.hx, 2 * w.hy, color="slategray",
                               label="wall" if i == 0 else None))
    for i, c in enumerate(course.checkpoints, 1):
        ax.add_patch(Rectangle((c.x - c.hx, c.y - c.hy), 2 * c.hx, 2 * c.hy, color="limegreen", alpha=0.3,
                               label="checkpoint, passed in the order numbered" if i == 1 else None))
        ax.annotate(str(i), (c.x, c.y), ha="center", va="center", color="darkgreen", fontsize=12)
    for area in course.color_areas:
        b = area.box
        ax.add_patch(Rectangle((b.x - b.hx, b.y - b.hy), 2 * b.hx, 2 * b.hy, color=area.color.name.lower(),
                               alpha=0.6, label=f"{area.color.name.lower()} area"))
    if path_xy:
        xs, ys = zip(*path_xy)
        ax.plot(xs, ys, color="crimson", lw=1.2, label="robot path")
        ax.plot(xs[:1], ys[:1], "o", color="crimson", label="start")
        ax.plot(xs[-1:], ys[-1:], "x", color="crimson", ms=10, label="where the test ended")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=9)
    ax.set_title(title or f"course {course.name}")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal")
    fig.tight_layout()
    fig.savefig(out, dpi=110, bbox_inches="tight")
