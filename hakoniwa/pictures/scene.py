"""The course and the robot as a person looks at them: a MuJoCo model for rendering only, never stepped.

The physics model (`world.py`) is built to be cheap to step: a white plane, sphere wheels, a box. This one is
built to be recognised: the floor image as the floor's texture (the line and the colour areas the sensor
reads), the walls, the checkpoints (shaded once passed), and a robot dressed as the one simulated, on the
same body sizes (its chassis, wheels with a tyre and a spoke that shows them turning, the colour sensor and
the spot it reads, the ultrasonic sensor's eyes, an EV3 brick's screen or a SPIKE hub's light matrix), and
the course's objects (a bottle with its neck and cap). A replay state (`replay.State`) sets its robot's joints
directly, and its objects' states theirs, so a frame shows each exactly where the physics had it.
"""

from __future__ import annotations

import math
import os
import sys
import tempfile
from ctypes.util import find_library
from dataclasses import dataclass
from pathlib import Path

# MuJoCo picks its OpenGL backend when imported: headless EGL unless told, where its library is found. Without
# it, MUJOCO_GL=egl breaks `import mujoco` itself (PyOpenGL's EGL module fails with an AttributeError), where
# MuJoCo's own default fails only when a film asks for a context, which `video.gl_problem` turns into a note.
if "mujoco" not in sys.modules and "MUJOCO_GL" not in os.environ and find_library("EGL") is not None:
    os.environ["MUJOCO_GL"] = "egl"

import mujoco

from hakoniwa.physics.course import Course
from hakoniwa.physics.replay import STATE_SIZE, RobotLook, State
from hakoniwa.physics.robots import SPIKE

WIDTH, HEIGHT = 640, 360  # the default frame: 16:9, even sides for H.264's 4:2:0
CHECKPOINT_RGBA = (0.2, 0.8, 0.3, 0.18)  # still to pass: a faint green square, as the paper's transparent ones
PASSED_RGBA = (0.1, 0.85, 0.25, 0.55)  # passed: solid
# The robot's colours: an EV3 brick's light grey and dark frame; a SPIKE Prime hub's white and yellow.
BODY_RGBA = {"ev3": ".82 .83 .80 1", SPIKE: ".96 .78 .10 1"}
TOP_RGBA = {"ev3": ".20 .22 .24 1", SPIKE: ".95 .95 .93 1"}


def _robot(look: RobotLook) -> str:
    b = look.body
    hx, hy, hz = b.chassis_half
    r = b.wheel_radius
    half_track = b.track_width / 2
    tyre = min(0.022, half_track - hy - 0.002) / 2 if half_track - hy > 0.006 else 0.01
    spike = look.hub == SPIKE
    # An EV3 brick is the robot's whole top; a SPIKE hub (88 x 56 mm) sits on a frame of the robot's colour.
    top = (min(0.044, hx * .9), min(0.028, hy * .9)) if spike else (hx * .98, hy * .98)
    body_rgba, top_rgba = BODY_RGBA[look.hub], TOP_RGBA[look.hub]
    if spike:  # the hub's 5 x 5 light matrix, lit in a smile
        lit = {(1, 1), (1, 3), (3, 0), (3, 4), (4, 1), (4, 2), (4, 3)}
        screen = (f'<geom type="box" size=".019 .019 .0015" pos="-0.01 0 {2 * hz + .001}" rgba=".1 .1 .1 1"/>'
                  + "".join(f'<geom type="box" size=".0028 .0028 .001" pos="{-0.01 + (2 - i) * .007} '
                            f'{(2 - j) * .007} {2 * hz + .003}" rgba="1 .9 .6 1"/>' for i, j in sorted(lit)))
    else:  # the EV3 brick's screen and its buttons
        screen = (f'<geom type="box" size="{hx * .35} {hy * .5} .0015" pos="{-0.01 + hx * .35} 0 {2 * hz + .001}" '
                  f'rgba=".55 .65 .55 1"/>'
                  f'<geom type="box" size="{hx * .12} {hy * .2} .002" pos="{-0.01 - hx * .35} 0 {2 * hz + .001}" '
                  f'rgba=".15 .15 .15 1"/>')
    front = -0.01 + hx
    eyes = (f'<geom type="box" size="{(b.ultrasonic_forward - front) / 2 + .004} .028 .012" '
            f'pos="{(b.ultrasonic_forward + front) / 2 - .004} 0 {hz}" rgba=".12 .12 .12 1"/>' + "".join(
                f'<geom type="cylinder" size=".010 .006" pos="{b.ultrasonic_forward} {side * .015} {hz}" '
                f'euler="0 90 0" rgba=".85 .15 .1 1"/>' for side in (-1, 1))) if "ultrasonic" in look.sensors else ""
    sensor_z = -r + 0.012  # the colour sensor: a dark block on a bracket, its lens 12 mm above the floor
    wheels = ""
    for name, y in (("wheel_left", half_track), ("wheel_right", -half_track)):
        wheels += f"""
      <body name="{name}" pos="0 {y} 0">
        <joint name="{name}" type="hinge" axis="0 1 0"/>
        <geom type="cylinder" size="{r} {tyre}" euler="90 0 0" rgba=".08 .08 .08 1"/>
        <geom type="cylinder" size="{r * .62} {tyre + .0008}" euler="90 0 0" rgba="{body_rgba}"/>
        <geom type="box" size="{r * .6} .001 {r * .1}" pos="0 {tyre + .001 if y > 0 else -tyre - .001} 0"
              rgba=".1 .1 .1 1"/>
      </body>"""
    return f"""
    <body name="robot">
      <freejoint/>
      <geom type="box" size="{hx} {hy} {hz}" pos="-0.01 0 {hz}" rgba="{body_rgba}"/>
      <geom type="box" size="{top[0]} {top[1]} .004" pos="-0.01 0 {2 * hz - .003}" rgba="{top_rgba}"/>
      {screen}{eyes}
      <geom type="sphere" size=".012" pos="{-hx + 0.005} 0 {0.012 - r}" rgba=".3 .3 .3 1"/>
      <geom type="box" size=".012 .012 {-sensor_z / 2}" pos="{b.color_sensor_forward} 0 {sensor_z / 2}"
            rgba=".12 .12 .12 1"/>
      <geom type="box" size="{(b.color_sensor_forward - front) / 2 + .004} .006 .003"
            pos="{(b.color_sensor_forward + front) / 2 - .004} 0 -.003"
            rgba=".3 .3 .3 1"/>
      <geom type="cylinder" size=".014 .0005" pos="{b.color_sensor_forward} 0 {0.0015 - r}" rgba="1 .1 .1 .45"/>
      {wheels}
    </body>"""


def _objects(course: Course) -> str:
    """The course's objects as free bodies after the robot, in course order (a replay's `object_states`): a
    bottle (a cylinder) gets a neck and a white cap."""
    bodies = []
    for o in course.objects:
        a, b, h = o.size
        rgba = " ".join(f"{c / 255:.4g}" for c in o.rgb) + " 1"
        if o.shape == "cylinder":
            geoms = (f'<geom type="cylinder" size="{a} {h * .4}" pos="0 0 {-h * .1}" rgba="{rgba}"/>'
                     f'<geom type="cylinder" size="{a * .95} {h * .1}" pos="0 0 {h * .3}" rgba=".85 .9 .95 .6"/>'
                     f'<geom type="cylinder" size="{a * .4} {h * .05}" pos="0 0 {h * .45}" rgba=".95 .95 .95 1"/>')
        else:
            geoms = f'<geom type="box" size="{a / 2} {b / 2} {h / 2}" rgba="{rgba}"/>'
        bodies.append(f'<body name="object_{o.name}"><freejoint/>{geoms}</body>')
    return "\n".join(bodies)


def scene_mjcf(course: Course, look: RobotLook, floor_png: Path, width: int = WIDTH, height: int = HEIGHT,
               samples: int = 0) -> str:
    xmin, xmax, ymin, ymax = course.extent
    cx, cy = (xmin + xmax) / 2, (ymin + ymax) / 2
    hz = course.wall_height / 2
    walls = "\n".join(f'<geom type="box" size="{w.hx} {w.hy} {hz}" pos="{w.x} {w.y} {hz}" material="wall"/>'
                      for w in course.walls)
    checkpoints = "\n".join(
        f'<geom name="cp_{i}" type="box" size="{c.hx} {c.hy} 0.0006" pos="{c.x} {c.y} 0.0008" '
        f'rgba="{" ".join(map(str, CHECKPOINT_RGBA))}"/>' for i, c in enumerate(course.checkpoints))
    size = max(xmax - xmin, ymax - ymin)
    return f"""
<mujoco model="hakoniwa-{course.name}-scene">
  <visual>
    <global offwidth="{width}" offheight="{height}"/>
    <quality shadowsize="1024" offsamples="{samples}"/>
    <map znear="0.01" zfar="50" shadowclip="{size}"/>
    <headlight ambient=".45 .45 .45" diffuse=".4 .4 .4" specular="0 0 0"/>
  </visual>
  <asset>
    <texture name="sky" type="skybox" builtin="gradient" rgb1=".62 .74 .86" rgb2=".95 .96 .98" width="64" height="64"/>
    <texture name="floor" type="2d" file="{floor_png}"/>
    <material name="floor" texture="floor" texrepeat="1 1" specular="0" shininess="0"/>
    <texture name="ground" type="2d" builtin="checker" rgb1=".55 .57 .55" rgb2=".5 .52 .5" width="64" height="64"/>
    <material name="ground" texture="ground" texrepeat="{size * 4} {size * 4}" texuniform="false"/>
    <material name="wall" rgba=".45 .5 .62 1" specular=".1"/>
  </asset>
  <default><geom contype="0" conaffinity="0"/></default>
  <worldbody>
    <light directional="true" pos="{cx} {cy} 4" dir=".3 .2 -1" diffuse=".5 .5 .5" castshadow="true"/>
    <geom type="plane" size="{size * 3} {size * 3} 0.1" pos="{cx} {cy} -0.002" material="ground"/>
    <geom name="floor" type="box" size="{(xmax - xmin) / 2} {(ymax - ymin) / 2} 0.001" pos="{cx} {cy} -0.001"
          material="floor"/>
    {walls}
    {checkpoints}
    {_robot(look)}
    {_objects(course)}
  </worldbody>
</mujoco>"""


@dataclass
class Scene:
    """The render model and its data; `show` puts the robot in a replay state and shades what is passed."""

    course: Course
    look: RobotLook
    model: mujoco.MjModel
    data: mujoco.MjData

    def show(self, state: State, passed: int, objects: tuple[float, ...] = ()) -> None:
        """Put the robot in `state` and the objects where `objects` (their free joints, course order) has
        them (none given: where they stand at the start)."""
        assert len(state) == STATE_SIZE
        self.data.qpos[:STATE_SIZE] = state
        start = [v for o in self.course.objects for v in (o.x, o.y, o.height / 2, *_yaw_quat(o.yaw_deg))]
        self.data.qpos[STATE_SIZE:] = objects or start
        mujoco.mj_kinematics(self.model, self.data)
        n = len(self.course.checkpoints)
        # Under the `completed` objective laps go on: a new lap starts with its checkpoints unshaded.
        this_lap = passed - n * ((passed - 1) // n) if passed else 0  # as the overlay counts them
        for i in range(n):
            gid = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_GEOM, f"cp_{i}")
            self.model.geom_rgba[gid] = PASSED_RGBA if i < this_lap else CHECKPOINT_RGBA


def _yaw_quat(yaw_deg: float) -> tuple[float, float, float, float]:
    half = math.radians(yaw_deg) / 2
    return math.cos(half), 0.0, 0.0, math.sin(half)


def build_scene(course: Course, look: RobotLook, width: int = WIDTH, height: int = HEIGHT, samples: int = 0) -> Scene:
    from PIL import Image

    with tempfile.TemporaryDirectory(prefix="hako-scene-") as tmp:
        png = Path(tmp) / "floor.png"
        Image.fromarray(course.picture()).save(png)
        model = mujoco.MjModel.from_xml_string(scene_mjcf(course, look, png, width, height, samples))
    return Scene(course, look, model, mujoco.MjData(model))
