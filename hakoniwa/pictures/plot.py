"""Pictures a person would rather look at than read: the course, with its gates, zones, objects and start,
and the robot's path on it."""

from __future__ import annotations

import csv
import math
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from hakoniwa.physics.course import Course

FIGURE_PIXELS = 4_000_000  # of the floor drawn under a figure: more than its own pixels, whatever the mat's size


def read_trajectory(path: Path) -> list[tuple[float, float]]:
    """The points of a run directory's trajectory.csv (`trajectory_points`)."""
    with open(path, newline="") as f:
        return trajectory_points(f)


def trajectory_points(lines: Iterable[str]) -> list[tuple[float, float]]:
    """The path's points from its CSV lines (a file's, or a result's `trajectory`); where two share a time the
    robot was carried (a scenario's place), and a point of NaNs between them makes the drawn path jump there
    instead of crossing the course."""
    points: list[tuple[float, float]] = []
    last_us = None
    for r in csv.DictReader(lines):
        if r["time_us"] == last_us:
            points.append((math.nan, math.nan))
        points.append((float(r["x"]), float(r["y"])))
        last_us = r["time_us"]
    return points


def draw_trajectory(course: Course, path_xy: list[tuple[float, float]], out: Path, title: str = "") -> None:
    """Drawn on a bare Figure (Agg), never through pyplot's global state: a campaign draws improving sets on
    a thread of its own while its loop goes on."""
    fig, ax = _course_figure(course)
    if path_xy:
        xs, ys = zip(*path_xy)
        ax.plot(xs, ys, color="crimson", lw=1.2, label="robot path")
        ax.plot(xs[:1], ys[:1], "o", color="crimson", label="start")
        ax.plot(xs[-1:], ys[-1:], "x", color="crimson", ms=10, label="where the test ended")
    _finish(fig, ax, out, title or f"course {course.name}")


def draw_course(course: Course, out: Path) -> None:
    """The course alone, for a person to check before a campaign: its floor, walls, gates (checkpoints, in
    their order), areas out of bounds, zones, objects and the start pose."""
    fig, ax = _course_figure(course)
    s = course.start
    yaw = math.radians(s.yaw_deg)
    ax.annotate("", (s.x + 0.15 * math.cos(yaw), s.y + 0.15 * math.sin(yaw)), (s.x, s.y),
                arrowprops={"arrowstyle": "-|>", "color": "crimson", "lw": 2})
    ax.plot([s.x], [s.y], "o", color="crimson", label=f"start ({s.x:g}, {s.y:g}, {s.yaw_deg:g} deg)")
    _finish(fig, ax, out, f"course {course.name} ({course.folder})")


def _course_figure(course: Course) -> tuple[Any, Any]:
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle, Rectangle

    xmin, xmax, ymin, ymax = course.extent
    fig = Figure(figsize=(5 + 6 * (xmax - xmin) / max(ymax - ymin, 1e-9) / 1.6, 5))
    ax = fig.subplots()
    ax.imshow(course.picture(FIGURE_PIXELS), extent=course.extent, origin="upper")
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
    for i, b in enumerate(course.out.areas):
        ax.add_patch(Rectangle((b.x - b.hx, b.y - b.hy), 2 * b.hx, 2 * b.hy, fill=False, hatch="xx", color="red",
                               label="out of bounds (COURSE_OUT)" if i == 0 else None))
    for i, z in enumerate(course.zones):
        shape = (Circle((z.x, z.y), z.radius) if z.radius is not None
                 else Rectangle((z.x - z.hx, z.y - z.hy), 2 * z.hx, 2 * z.hy))
        shape.set(fill=False, ls="--", lw=1.5, color="darkorange", label="zone" if i == 0 else None)
        ax.add_patch(shape)
        ax.annotate(z.name, (z.x, z.bounds()[3]), ha="center", va="bottom", color="darkorange", fontsize=9)
    for i, o in enumerate(course.objects):
        colour = tuple(c / 255 for c in o.rgb)
        footprint = (Circle((o.x, o.y), o.size[0]) if o.shape == "cylinder"
                     else Rectangle((o.x - o.size[0] / 2, o.y - o.size[1] / 2), o.size[0], o.size[1],
                                    angle=o.yaw_deg, rotation_point="center"))
        footprint.set(color=colour, ec="magenta", lw=1.5, label="object" if i == 0 else None)
        ax.add_patch(footprint)
        ax.annotate(o.name, (o.x, o.y - o.half_extent), ha="center", va="top", color="magenta", fontsize=9)
    return fig, ax


def _finish(fig: Any, ax: Any, out: Path, title: str) -> None:
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=9)
    ax.set_title(title)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal")
    fig.tight_layout()
    fig.savefig(out, dpi=110, bbox_inches="tight")
