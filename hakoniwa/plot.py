"""Pictures a person would rather look at than read: the course with the robot's path."""

from __future__ import annotations

import csv
from pathlib import Path

from hakoniwa.course import Course


def read_trajectory(path: Path) -> list[tuple[float, float]]:
    with open(path, newline="") as f:
        return [(float(r["x"]), float(r["y"])) for r in csv.DictReader(f)]


def draw_trajectory(course: Course, path_xy: list[tuple[float, float]], out: Path, title: str = "") -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    fig, ax = plt.subplots(figsize=(9, 5.6))
    ax.imshow(course.floor, cmap="gray", extent=course.extent, vmin=0, vmax=100, origin="upper")
    for w in course.walls:
        ax.add_patch(Rectangle((w.x - w.hx, w.y - w.hy), 2 * w.hx, 2 * w.hy, color="slategray"))
    for i, c in enumerate(course.checkpoints, 1):
        ax.add_patch(Rectangle((c.x - c.hx, c.y - c.hy), 2 * c.hx, 2 * c.hy, color="limegreen", alpha=0.3))
        ax.annotate(str(i), (c.x, c.y), ha="center", va="center", color="darkgreen", fontsize=12)
    if path_xy:
        xs, ys = zip(*path_xy)
        ax.plot(xs, ys, color="crimson", lw=1.2, label="robot path")
        ax.plot(xs[:1], ys[:1], "o", color="crimson")
        ax.plot(xs[-1:], ys[-1:], "x", color="crimson", ms=10)
        ax.legend(loc="upper right")
    ax.set_title(title or f"course {course.name}")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
