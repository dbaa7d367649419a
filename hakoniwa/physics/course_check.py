"""Whether a robot can run a course at all, checked before any test.

A course whose start pose puts the robot into a wall, off its floor image or into an area out of bounds, or
whose checkpoints it cannot reach would end every test the same way (HIT_WALL or COURSE_OUT at 0.00 m, or
TIME_OVER with no checkpoint), and a campaign would score every parameter set as a failure of the parameters
while the fault is the course's.
So the course is refused in one line naming its file, as any other bad course file is.

Reachability is a geometric check, kept cheap (a few ms on the oval): the floor image is cut into
CELL_M squares, a square is free when its centre is at least the robot's half width (across its wheels,
the narrowest it gets when it drives through a gap) from every wall, less one square for the grid's
coarseness, and free squares connected to the start are flooded. It errs on the side of letting a course
through: a gap that the flood squeezes through may still be too tight to steer through.
"""

from __future__ import annotations

import math
from collections import deque
from pathlib import Path

import numpy as np

from hakoniwa.physics.course import Box, Course, CourseError, Pose
from hakoniwa.physics.robot import CHASSIS_BACK_M, Body

CELL_M = 0.02  # the flood fill's grid
TOUCH_M = 0.001  # a start closer to a wall than this touches it: the first event check would see the contact


def check_course(course: Course, body: Body, file: Path) -> None:
    """Raise CourseError (one line, naming `file`) if `body` cannot start on `course` or reach its
    checkpoints."""
    where = f"{file}: "
    s = course.start
    xmin, xmax, ymin, ymax = course.extent
    off = off_floor(course, body, s, "the start")
    if off is not None:
        raise CourseError(where + off)
    wall = wall_touched(course, body, s)
    if wall is not None:
        raise CourseError(f"{where}the robot at the start pose ({s.x:g}, {s.y:g}, {s.yaw_deg:g} deg) is inside "
                          f"or touching wall {wall.name!r}: every test would end HIT_WALL at 0.00 m")
    for cp in course.checkpoints:
        if not (xmin <= cp.x <= xmax and ymin <= cp.y <= ymax):
            raise CourseError(f"{where}checkpoint {cp.name!r} at ({cp.x:g}, {cp.y:g}) is outside the floor image")
    reached, xs, ys = _flood(course, body)
    for i, cp in enumerate(course.checkpoints):
        inside = ((np.abs(xs - cp.x) <= cp.hx + CELL_M / 2)[None, :]
                  & (np.abs(ys - cp.y) <= cp.hy + CELL_M / 2)[:, None])
        if not (reached & inside).any():
            raise CourseError(f"{where}checkpoint {i + 1} ({cp.name!r}) cannot be reached from the start: it is "
                              f"walled off, inside a wall, or behind a gap narrower than the robot "
                              f"({2 * _half_width(body) * 1000:.0f} mm)")


def color_sensor_xy(body: Body, pose: Pose) -> tuple[float, float]:
    """Where the colour sensor of `body` standing at `pose` looks at the floor."""
    yaw = math.radians(pose.yaw_deg)
    return pose.x + body.color_sensor_forward * math.cos(yaw), pose.y + body.color_sensor_forward * math.sin(yaw)


def off_floor(course: Course, body: Body, pose: Pose, at: str) -> str | None:
    """Why `body` cannot stand at `pose` for being off the floor image (`at` names the pose: "the start"),
    or None: the robot there, or its colour sensor, would read the image's border; or in an area the course
    marks out of bounds, where the first event check would end the test COURSE_OUT."""
    xmin, xmax, ymin, ymax = course.extent
    for what, (x, y) in ((f"{at} pose", (pose.x, pose.y)), (f"the colour sensor at {at}", color_sensor_xy(body, pose))):
        if not (xmin <= x <= xmax and ymin <= y <= ymax):
            return f"{what} ({x:.3f}, {y:.3f}) is off the floor image (x {xmin:g}..{xmax:g}, y {ymin:g}..{ymax:g})"
    area = course.out.area_at(pose.x, pose.y)
    if area is not None:
        return (f"{at} pose ({pose.x:.3f}, {pose.y:.3f}) is in out-of-bounds area {area.name!r}: the test would "
                f"end COURSE_OUT at once")
    return None


def wall_touched(course: Course, body: Body, pose: Pose) -> Box | None:
    """The first wall that `body` standing at `pose` is inside or touching, or None: the first event check
    would end the test HIT_WALL."""
    yaw = math.radians(pose.yaw_deg)
    return next((w for w in course.walls if _footprint_touches(body, pose.x, pose.y, yaw, w)), None)


def _half_width(body: Body) -> float:
    """Half the robot's width across its wheels (the wheels collide as spheres of the wheel's radius)."""
    return max(body.chassis_half[1], body.track_width / 2 + body.wheel_radius)


def _footprint_touches(body: Body, x: float, y: float, yaw: float, wall: Box) -> bool:
    """Whether the robot's chassis box or a wheel, placed at (x, y, yaw), overlaps `wall` or comes within
    TOUCH_M of it."""
    c, s = math.cos(yaw), math.sin(yaw)
    for side in (1, -1):
        wx, wy = x - s * side * body.track_width / 2, y + c * side * body.track_width / 2
        if wall.distance(wx, wy) <= body.wheel_radius + TOUCH_M:
            return True
    hx, hy = body.chassis_half[0], body.chassis_half[1]
    cx, cy = x - CHASSIS_BACK_M * c, y - CHASSIS_BACK_M * s
    # Separating axes of two rectangles: the world's (the wall's) and the chassis's own.
    for ax, ay in ((1.0, 0.0), (0.0, 1.0), (c, s), (-s, c)):
        chassis_r = hx * abs(ax * c + ay * s) + hy * abs(-ax * s + ay * c)
        wall_r = wall.hx * abs(ax) + wall.hy * abs(ay)
        if abs((cx - wall.x) * ax + (cy - wall.y) * ay) > chassis_r + wall_r + TOUCH_M:
            return False
    return True


def _flood(course: Course, body: Body) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The grid squares the robot can reach from the start (rows by y, columns by x), and their centres."""
    xmin, xmax, ymin, ymax = course.extent
    xs = np.arange(xmin + CELL_M / 2, xmax, CELL_M)
    ys = np.arange(ymin + CELL_M / 2, ymax, CELL_M)
    clearance = np.full((len(ys), len(xs)), np.inf)
    for w in course.walls:
        dx = np.maximum(np.abs(xs - w.x) - w.hx, 0.0)[None, :]
        dy = np.maximum(np.abs(ys - w.y) - w.hy, 0.0)[:, None]
        clearance = np.minimum(clearance, np.hypot(dx, dy))
    free = clearance >= _half_width(body) - CELL_M
    # Seeds: the free squares the robot covers at its start (it may turn on the spot to leave it).
    s = course.start
    reach = math.hypot(body.chassis_half[0] + CHASSIS_BACK_M, _half_width(body))
    seeds = free & (np.hypot(xs[None, :] - s.x, ys[:, None] - s.y) <= reach)
    reached = seeds.copy()
    rows, cols = free.shape
    queue = deque(zip(*np.nonzero(seeds)))
    free_list = free.tolist()
    done = reached.tolist()
    while queue:
        i, j = queue.popleft()
        for a, b in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)):
            if 0 <= a < rows and 0 <= b < cols and free_list[a][b] and not done[a][b]:
                done[a][b] = True
                queue.append((a, b))
    return np.array(done, dtype=bool), xs, ys
