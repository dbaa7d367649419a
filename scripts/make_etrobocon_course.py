"""Draw the built-in ET Robocon-style courses: hakoniwa/physics/courses/etrobocon-l and etrobocon-r.

Our own layout in the style and at the size of ET Robocon's mat (5.46 x 3.64 m; the competition's exact layout
goes to participants only): two lanes, L on the mat's left half and R its mirror image, each a black line with
blue sections, a start line, three checkpoints and a LAP gate (red gate lines that stop short of the black line,
as the regulation's 5.2.2 and 5.2.3 draw them), a double loop (two round loops; ours do not cross themselves,
so that a program following one edge of the line, as the official samples do, runs through them), then past
the LAP gate an ET sumo ring with its bottle and a garage (white, bordered grey, 5.2.4) at the line's end.

One image serves both lanes; each lane is a course folder whose course.toml this script writes too, with the
start, the gates as checkpoints (the LAP gate the last), the zones, the bottle and the sensor calibration.
The path is drawn by a turtle: straights and arcs, each black or blue, with named marks along the way.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import click
import numpy as np
from PIL import Image

from hakoniwa.physics.course import COURSES_DIR

MAT_M = (5.46, 3.64)  # the mat (gihyo.jp's description of ET Robocon's field: 5460 x 3640 mm, about 12 tatami)
MPP = 0.004  # metres per pixel: 1365 x 910 pixels
LINE_M = 0.02  # the black line's width (an assumption: the regulation gives none)
EDGE_M = 0.01  # the grey ramp across each edge, as a texture-filtered camera sees it
# What a SPIKE colour sensor reads on each of the mat's colours (10-bit r, g, b, the course's [sensor.spike]):
# white, black, blue and red as one team published them for the real mat (docs/DESIGN-NOTES.md, "The ET
# Robocon-style course"); the yellow and grey are ours (no measurement published): the colours the image always had.
SPIKE_READS = {"white": (1000, 1000, 1000), "black": (50, 50, 50), "blue": (70, 200, 400), "red": (800, 300, 350),
               "yellow": (981, 851, 199), "grey": (609, 609, 609)}


def pixel(name: str) -> tuple[int, int, int]:
    """The image colour that reads SPIKE_READS[name]: each channel where the reading sits between black and
    white (the course's channels are each their place between the two, `color_response.py`)."""
    white, black = SPIKE_READS["white"], SPIKE_READS["black"]
    r, g, b = (round(255 * (c - lo) / (hi - lo)) for c, hi, lo in zip(SPIKE_READS[name], white, black))
    return r, g, b


WHITE, BLACK = pixel("white"), pixel("black")
BLUE = pixel("blue")  # the line's blue sections: dark enough that a tracer keeps following them
RED = pixel("red")  # start and gate lines
YELLOW = pixel("yellow")  # the sumo ring's outline
GREY = pixel("grey")  # the garage's border
GATE_GAP_M = 0.06  # how far from the line's centre a gate line stops (it never crosses the black line)
GATE_HALF_M = 0.22  # how far a gate line reaches from the line's centre
GATE_WIDTH_M = 0.015
RING_RADIUS_M = 0.32
RING_OFFSET_M = 0.25  # the ring's centre from the line, on the line's left (the side the robot does not run on)
GARAGE_HALF_M = (0.16, 0.18)  # across, along the line
GARAGE_BORDER_M = 0.02
BOTTLE = {"radius": 0.0325, "height": 0.205, "mass": 0.3, "friction": 0.3}  # a 500 ml PET bottle, part full
START_SIDE_M = 0.02  # the robot starts with its colour sensor on the line's right edge
START_LINE_M = 0.30  # from the start to the start line

# The L lane: from the start heading north, a left turn into the top straight (a blue section there), the
# first loop, the west straight (checkpoints 2 and 3), the second loop, the LAP gate, then the sumo ring on the
# line's left, a second blue section and the garage. ("A", degrees, radius): an arc, positive to the left.
LOOP = [("A", -90, 0.22), ("A", 270, 0.36), ("A", -90, 0.22)]
LANE = [("mark", "start"), ("S", START_LINE_M), ("mark", "startline"), ("S", 1.0), ("mark", "cp1"), ("S", 0.9),
        ("A", 90, 0.45), ("S", 0.10), ("blue", 0.25), ("S", 0.05), *LOOP, ("S", 0.2), ("mark", "cp2"), ("S", 1.2),
        ("mark", "cp3"), ("S", 0.2), *LOOP, ("S", 0.15), ("mark", "lap"), ("S", 0.05), ("A", 90, 0.3),
        ("S", 0.27), ("mark", "ring"), ("S", 0.73), ("blue", 0.25), ("S", 0.1), ("mark", "garage")]
LANE_START = (-0.45, -1.50, 90.0)  # the L lane's line at the start, and its heading


@dataclass
class Lane:
    points: np.ndarray  # (n, 2) along the line, 2 mm apart
    blue: np.ndarray  # (n,) bool: a blue section
    marks: dict[str, tuple[float, float, float]]  # name: x, y, heading (degrees)


def walk(start: tuple[float, float, float], steps: list, step_m: float = 0.002) -> Lane:
    x, y, heading = start[0], start[1], math.radians(start[2])
    pts, blue, marks = [(x, y)], [False], {}
    for kind, *args in steps:
        if kind == "mark":
            marks[args[0]] = (x, y, math.degrees(heading) % 360)
        elif kind in ("S", "blue"):
            n = max(1, round(args[0] / step_m))
            for i in range(1, n + 1):
                pts.append((x + math.cos(heading) * args[0] * i / n, y + math.sin(heading) * args[0] * i / n))
                blue.append(kind == "blue")
            x, y = pts[-1]
        else:
            angle, radius = math.radians(args[0]), args[1]
            side = 1 if angle > 0 else -1
            cx, cy = x - side * radius * math.sin(heading), y + side * radius * math.cos(heading)
            a0 = math.atan2(y - cy, x - cx)
            n = max(1, round(abs(angle) * radius / step_m))
            for i in range(1, n + 1):
                a = a0 + angle * i / n
                pts.append((cx + radius * math.cos(a), cy + radius * math.sin(a)))
                blue.append(False)
            x, y = pts[-1]
            heading += angle
    return Lane(np.array(pts), np.array(blue), marks)


def left_of(mark: tuple[float, float, float], d: float) -> tuple[float, float]:
    x, y, h = mark
    return x - d * math.sin(math.radians(h)), y + d * math.cos(math.radians(h))


def draw(lane: Lane) -> np.ndarray:
    """The mat: the L lane drawn on its left half, the right half its mirror image (the R lane)."""
    from scipy.spatial import cKDTree

    w, h = round(MAT_M[0] / MPP), round(MAT_M[1] / MPP)
    assert w % 2 == 1, "the centre column is the mirror line"
    xs = -MAT_M[0] / 2 + (np.arange(w) + 0.5) * MPP
    ys = MAT_M[1] / 2 - (np.arange(h) + 0.5) * MPP  # row 0 is the top of the image
    gx, gy = np.meshgrid(xs, ys)
    img = np.empty((h, w, 3), dtype=np.float64)
    img[:] = WHITE
    for name in ("startline", "cp1", "cp2", "cp3", "lap"):
        _gate(img, gx, gy, lane.marks[name])
    ring = left_of(lane.marks["ring"], RING_OFFSET_M)
    img[np.abs(np.hypot(gx - ring[0], gy - ring[1]) - RING_RADIUS_M) <= GATE_WIDTH_M / 2] = YELLOW
    _garage(img, gx, gy, lane.marks["garage"])
    d, nearest = cKDTree(lane.points).query(np.column_stack([gx.ravel(), gy.ravel()]))
    d, nearest = d.reshape(h, w), nearest.reshape(h, w)
    white = np.clip((d - LINE_M / 2) / EDGE_M + 0.5, 0.0, 1.0)[:, :, None]  # as the oval's edge ramp
    ink = np.where(lane.blue[nearest][:, :, None], np.array(BLUE, dtype=float), np.array(BLACK, dtype=float))
    img = img * white + ink * (1 - white)
    half = w // 2
    img[:, half + 1:] = img[:, :half][:, ::-1]
    return np.round(img).astype(np.uint8)


def _gate(img: np.ndarray, gx: np.ndarray, gy: np.ndarray, mark: tuple[float, float, float]) -> None:
    """A red gate line across the lane at `mark`, split where the black line runs."""
    x, y, heading = mark
    t = math.radians(heading)
    along = (gx - x) * math.cos(t) + (gy - y) * math.sin(t)
    across = np.abs(-(gx - x) * math.sin(t) + (gy - y) * math.cos(t))
    img[(np.abs(along) <= GATE_WIDTH_M / 2) & (across >= GATE_GAP_M) & (across <= GATE_HALF_M)] = RED


def _garage(img: np.ndarray, gx: np.ndarray, gy: np.ndarray, mark: tuple[float, float, float]) -> None:
    """The garage: white, bordered grey on three sides, open towards the line that leads in."""
    cx, cy, half = garage_box(mark)
    outer = (np.abs(gx - cx) <= half[0] + GARAGE_BORDER_M) & (np.abs(gy - cy) <= half[1] + GARAGE_BORDER_M)
    inner = (np.abs(gx - cx) <= half[0]) & (np.abs(gy - cy) <= half[1])
    t = math.radians(mark[2])
    entrance = ((gx - mark[0]) * math.cos(t) + (gy - mark[1]) * math.sin(t)) < GARAGE_BORDER_M  # the near side
    img[outer & ~inner & ~entrance] = GREY


def garage_box(mark: tuple[float, float, float]) -> tuple[float, float, tuple[float, float]]:
    """The garage's centre and half sizes (x, y): it starts where the line ends, along its heading."""
    x, y, heading = mark
    t = math.radians(heading)
    across, along = GARAGE_HALF_M
    cx, cy = x + along * math.cos(t), y + along * math.sin(t)
    vertical = abs(math.sin(t)) > 0.5
    return cx, cy, (across, along) if vertical else (along, across)


def gate_box(mark: tuple[float, float, float]) -> tuple[float, float, float, float]:
    """The checkpoint box of a gate: thin along the lane, wide across it (the gates sit on straights)."""
    x, y, heading = mark
    along, across = 0.04, 0.25
    vertical = abs(math.sin(math.radians(heading))) > 0.5
    return x, y, (across if vertical else along), (along if vertical else across)


def course_toml(lane: Lane, name: str, image: str, mirror: bool) -> str:
    """The course file of one lane: the L lane's, or (`mirror`) its mirror image's, the R lane."""
    sign = -1 if mirror else 1
    sx, sy, heading = lane.marks["start"]  # the lane starts heading north: its mirror image does too
    lines = [
        f"# ET Robocon-style course, lane {name[-1].upper()}: made by scripts/make_etrobocon_course.py (edit the",
        "# script, not this file). Our own layout at the competition mat's size, not ET Robocon's",
        "# (docs/DESIGN-NOTES.md, \"The ET Robocon-style course\").",
        f'name = "{name}"',
        f'floor_image = "{image}"',
        f"meters_per_pixel = {MPP}",
        f"origin = [{-MAT_M[0] / 2}, {-MAT_M[1] / 2}]",
        "time_limit_s = 120            # ET Robocon's maximum measuring time (regulation 5.4.7)",
        "",
        "[sensor.ev3]                  # what ET Robocon's simulator's HackEV colour sensor reads (its sample_c4)",
        "reflect_white = 23",
        "reflect_black = 0",
        "",
        "[sensor.spike]                # a SPIKE sensor's 10-bit r, g, b (docs/DESIGN-NOTES.md)",
        *(f"{name} = [{r}, {g}, {b}]" for name, (r, g, b) in SPIKE_READS.items()),
        "",
        "# The start area (regulation 5.2.2): the black line and the white beside it, out to the start line's",
        f"# ends ({GATE_HALF_M:g} m either side of the line's centre), before the start line, which crosses the lane",
        f"# {START_LINE_M:g} m ahead of the start. A scenario's [[place]] over = \"start\" with edge = \"left\",",
        "# \"right\" or \"centre\" slides the robot across it until its colour sensor is there on the line.",
        "[start]                       # the axle centre, heading along the line; the colour sensor 2 cm right",
        f"{f'x = {sign * sx + START_SIDE_M:.4f}':30s}# of the line's centre, just clear of its right edge",
        f"y = {sy:.4f}",
        f"yaw_deg = {heading:g}",
        "",
        "[course_out]                  # the run ends COURSE_OUT (コースアウト) with the axle past the mat's edge",
        "margin_m = 0",
    ]
    for gate in ("cp1", "cp2", "cp3", "lap"):
        x, y, hx, hy = gate_box(lane.marks[gate])
        label = "LAP gate: the last checkpoint" if gate == "lap" else f"checkpoint {gate[-1]}"
        heading = lane.marks[gate][2] if not mirror else (180 - lane.marks[gate][2]) % 360
        lines += ["", f"[[checkpoint]]                # {label}", f'name = "{gate}"', f"x = {sign * x:.4f}",
                  f"y = {y:.4f}", f"hx = {hx}", f"hy = {hy}",
                  f"{f'heading_deg = {heading:g}':30s}# the gate's arrow: passed this way only (5.12, 5.13)"]
    gx, gy, (ghx, ghy) = garage_box(lane.marks["garage"])
    rx, ry = left_of(lane.marks["ring"], RING_OFFSET_M)
    lines += ["", "[[zone]]                      # the white inside of the garage (regulation 5.2.4)",
              'name = "garage"', f"x = {sign * gx:.4f}", f"y = {gy:.4f}", f"hx = {ghx}", f"hy = {ghy}",
              "", "[[zone]]                      # the ET sumo ring (regulation 5.15)", 'name = "ring"',
              f"x = {sign * rx:.4f}", f"y = {ry:.4f}", f"radius = {RING_RADIUS_M}",
              "", "[[object]]                    # the sumo bottle: a 500 ml PET bottle with a black label (5.15.1)",
              'name = "bottle"', 'shape = "cylinder"', *(f"{k} = {v}" for k, v in BOTTLE.items()),
              "color = [40, 40, 40]", f"x = {sign * rx:.4f}", f"y = {ry:.4f}",
              "", "[score]                       # --objective etrobocon: ET Robocon's result points",
              'class = "applied"             # a robot of no class (an EV3): HackSPi\'s class (regulation 3, 表 3-1)',
              'garage = "garage"', 'sumo_ring = "ring"', 'sumo_bottle = "bottle"', ""]
    return "\n".join(lines)


@click.command()
@click.option("--out", "out_dir", type=click.Path(file_okay=False, path_type=Path), default=COURSES_DIR,
              show_default=True, help="Where the etrobocon-l and etrobocon-r folders go.")
def main(out_dir: Path) -> None:
    lane = walk(LANE_START, LANE)
    folders = {name: out_dir / name for name in ("etrobocon-l", "etrobocon-r")}
    for folder in folders.values():
        folder.mkdir(parents=True, exist_ok=True)
    png = folders["etrobocon-l"] / "floor.png"
    Image.fromarray(draw(lane), mode="RGB").save(png, optimize=True)
    (folders["etrobocon-l"] / "course.toml").write_text(course_toml(lane, "etrobocon-l", "floor.png", False))
    (folders["etrobocon-r"] / "course.toml").write_text(
        course_toml(lane, "etrobocon-r", "../etrobocon-l/floor.png", True))
    click.echo(f"wrote {png} and the two course.toml files")


if __name__ == "__main__":
    main()
