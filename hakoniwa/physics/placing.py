"""Where a person sets the robot down: a scenario's `[[place]]` entries as poses on the course.

A calibrating program asks for the robot over the line's black, then over the white floor, then back at the
start. A team sets its robot down in the start area with its colour sensor on the edge of the line its program
traces (`edge`), or on the line's centre. A person does either by sliding the robot sideways from the start:
the spot is searched on the line through the colour sensor's start position, across the start heading,
nearest first (`spot_over`, `spot_on_edge`: an edge is where the floor reads half way between the course's
black and white, the point a tracer steers for), and the robot keeps the start heading. Every pose, found or
given, must be one the robot can stand at, checked as the start pose is (`course_check`): on the floor image,
colour sensor too, clear of every wall and of the areas out of bounds.
"""

from __future__ import annotations

import math

import numpy as np

from hakoniwa.physics.course import Course, Pose
from hakoniwa.physics.course_check import color_sensor_xy, off_floor, wall_touched
from hakoniwa.physics.robot import Body
from hakoniwa.physics.scenario import Place, Scenario, ScenarioError
from hakoniwa.wire.protocol import ColorId

SEARCH_M = 0.3  # how far to either side of the start a person looks for the line or the white floor
SEARCH_STEP_M = 0.001  # the search's step across the start heading: half a pixel of the oval's floor
WHITE_CLEAR_M = 0.03  # white is looked for this far inside the white floor, where a person puts it, clear
# of the grey edge of the line


def shade_at(course: Course, x: float, y: float) -> float:
    """What the colour sensor sees of the floor at (x, y): 0 on the course's black, 1 on its white, from the
    reflect lookup the sensor itself reads."""
    return (course.reflect_at(x, y) - course.reflect_black) / (course.reflect_white - course.reflect_black)


def spot_over(course: Course, body: Body, over: str) -> Pose | None:
    """The start pose slid sideways until the colour sensor is over `over` ("black" or "white"), or None if
    there is no such floor within SEARCH_M: the middle of the nearest stretch of black (the line's centre), or
    the nearest point WHITE_CLEAR_M inside a stretch of white (the middle of one narrower than twice that).
    Black and white are what the colour sensor's colour mode calls them (`Course.reading_at`): on a grey floor
    the darkest and the lightest third of the way from the course's black to its white; on a colour floor a blue
    section of the line is no black."""
    offsets, points = _search_line(course, body)
    steps = len(offsets) // 2
    colour = ColorId.BLACK if over == "black" else ColorId.WHITE
    runs = _runs(np.array([course.reading_at(x, y).color == colour for x, y in points]))
    if not runs:
        return None
    inset = 0 if over == "black" else round(WHITE_CLEAR_M / SEARCH_STEP_M)
    spots = []
    for first, last in runs:
        if over == "black" or last - first < 2 * inset:
            spots.append((first + last) // 2)
        else:
            spots.append(min(max(steps, first + inset), last - inset))  # the start's own index, held inside
    best = min(spots, key=lambda i: (abs(i - steps), i))
    return _slid(course, float(offsets[best]))


def spot_on_edge(course: Course, body: Body, edge: str) -> Pose | None:
    """The start pose slid sideways until the colour sensor is over the `edge` ("left", "right" as the robot
    faces, or "centre") of the stretch of line nearest to it, or None if no whole stretch of line lies within
    SEARCH_M. The edge is interpolated between the search's steps: where the floor's shade crosses one half."""
    offsets, points = _search_line(course, body)
    steps = len(offsets) // 2
    shades = np.array([shade_at(course, x, y) for x, y in points])
    runs = [(a, b) for a, b in _runs(shades < 0.5) if a > 0 and b < len(offsets) - 1]  # both edges in reach
    if not runs:
        return None
    first, last = min(runs, key=lambda r: (max(r[0] - steps, steps - r[1], 0), r[0]))
    right = offsets[first - 1] + SEARCH_STEP_M * (shades[first - 1] - 0.5) / (shades[first - 1] - shades[first])
    left = offsets[last] + SEARCH_STEP_M * (0.5 - shades[last]) / (shades[last + 1] - shades[last])
    return _slid(course, float({"left": left, "right": right, "centre": (left + right) / 2}[edge]))


def _search_line(course: Course, body: Body) -> tuple[np.ndarray, list[tuple[float, float]]]:
    """The offsets to the left of the start heading a person tries, SEARCH_M either side in SEARCH_STEP_M
    steps (the middle one 0), and where the colour sensor looks at the floor at each (float64 scalars: the
    floor's lookup then weighs its float32 texels in double precision)."""
    left = _left(course)
    sx, sy = color_sensor_xy(body, course.start)
    steps = round(SEARCH_M / SEARCH_STEP_M)
    offsets = np.arange(-steps, steps + 1) * SEARCH_STEP_M
    return offsets, list(zip(sx + offsets * left[0], sy + offsets * left[1]))


def _left(course: Course) -> tuple[float, float]:
    """The unit vector across the start heading, to its left."""
    yaw = math.radians(course.start.yaw_deg)
    return -math.sin(yaw), math.cos(yaw)


def _slid(course: Course, d: float) -> Pose:
    """The start pose moved `d` metres to the left of its heading (right for a negative `d`)."""
    s, left = course.start, _left(course)
    return Pose(s.x + d * left[0], s.y + d * left[1], s.yaw_deg)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """The stretches of True in `mask`, as (first, last) index pairs."""
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    return list(zip(np.flatnonzero(edges == 1).tolist(), (np.flatnonzero(edges == -1) - 1).tolist()))


def place_pose(course: Course, body: Body, place: Place) -> Pose:
    """Where `place` sets the robot down (ScenarioError naming the entry where it cannot stand there)."""
    if place.over == "start" and place.edge is not None:
        on_edge = spot_on_edge(course, body, place.edge)
        if on_edge is None:
            raise ScenarioError(f"{place.where}: no line within {SEARCH_M * 100:g} cm of the colour sensor's start "
                                f"position, across the start heading, for edge = {place.edge!r}")
        pose = on_edge
    elif place.over == "start":
        pose = course.start
    elif place.over is not None:
        found = spot_over(course, body, place.over)
        if found is None:
            raise ScenarioError(f"{place.where}: no {place.over} floor within {SEARCH_M * 100:g} cm of the "
                                f"colour sensor's start position, across the start heading")
        pose = found
    else:
        pose = Pose(place.x, place.y, place.yaw_deg)
    off = off_floor(course, body, pose, "the place")
    if off is not None:
        raise ScenarioError(f"{place.where}: {off}")
    wall = wall_touched(course, body, pose)
    if wall is not None:
        raise ScenarioError(f"{place.where}: the robot at ({pose.x:g}, {pose.y:g}, {pose.yaw_deg:g} deg) is "
                            f"inside or touching wall {wall.name!r}")
    return pose


def placements(course: Course, body: Body, scenario: Scenario) -> tuple[tuple[int, Pose], ...]:
    """Each place of the scenario as (at_us, pose), in the order they happen."""
    return tuple((p.at_us, place_pose(course, body, p)) for p in scenario.places)
