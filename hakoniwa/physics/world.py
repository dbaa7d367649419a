"""The MuJoCo world: course geometry plus robot, stepped in fixed 1 ms steps.

This is the physics half of the dm_control split: it knows bodies, motors and sensors, not checkpoints or
events (that is `task.py`). Sensors are computed on demand, at the instants Athrill wakes up, so that the
hot loop is MuJoCo's own C stepping.

A course's objects (`[[object]]`) are free bodies after the robot: the robot pushes and knocks them over,
the ultrasonic ray sees them, and the colour sensor reads an object's colour where one is under it (a ray
down through the objects alone, at the sensor's spot). They are not walls: touching one is no HIT_WALL. They
start asleep (MuJoCo's sleeping trees) and wake when the robot touches them, so a bottle standing far from
the robot costs its contacts nothing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from hakoniwa.physics import robot
from hakoniwa.physics.course import Course, Pose
from hakoniwa.physics.course_items import CourseObject
from hakoniwa.physics.noise import StartOffset
from hakoniwa.wire.timebase import PHYSICS_STEP_US, US_PER_S

SETTLE_STEPS = 200  # physics steps a robot with an IMU rests on the floor before its saved start state


def build_mjcf(course: Course, body: robot.Body = robot.EV3_BODY, imu: bool = False) -> str:
    xmin, xmax, ymin, ymax = course.extent
    cx, cy = (xmin + xmax) / 2, (ymin + ymax) / 2
    hz = course.wall_height / 2
    walls = "\n".join(
        f'<geom name="wall_{w.name}" type="box" size="{w.hx} {w.hy} {hz}" pos="{w.x} {w.y} {hz}" rgba=".6 .6 .7 1"/>'
        for w in course.walls
    )
    # Checkpoints are transparent, non-colliding volumes: they never block the robot or the ultrasonic ray.
    checkpoints = "\n".join(
        f'<site name="cp_{c.name}" type="box" size="{c.hx} {c.hy} 0.001" pos="{c.x} {c.y} 0.001" rgba="0 1 0 .2"/>'
        for c in course.checkpoints
    )
    objects = "\n".join(_object_mjcf(o) for o in course.objects)
    s = course.start
    # Walls live in one static body so that a single contact sensor can watch robot-wall contact inside
    # MuJoCo's own step; reading it costs nothing compared with scanning the contact list in Python.
    imu_sensor = robot.imu_sensor_mjcf() if imu else ""
    # Objects sleep until the robot touches them (MuJoCo's sleeping trees): an object at rest then costs no
    # contacts in a step. The robot never sleeps; a course without objects is stepped as it always was.
    sleep = '><flag sleep="enable"/></option' if course.objects else "/"
    return f"""
<mujoco model="hakoniwa-{course.name}">
  <option timestep="{PHYSICS_STEP_US / US_PER_S}" integrator="implicitfast"{sleep}>
  <default><geom friction="1 0.005 0.0001"/></default>
  <worldbody>
    <geom name="floor" type="plane" size="{(xmax - xmin) / 2} {(ymax - ymin) / 2} 0.1" pos="{cx} {cy} 0"
          rgba="1 1 1 1"/>
    <body name="walls">
    {walls}
    </body>
    {checkpoints}
    {robot.robot_mjcf(s.x, s.y, s.yaw_deg, body, imu, sleeps=not course.objects)}
    {objects}
  </worldbody>
  <actuator>{robot.actuators_mjcf(body)}
  </actuator>
  <sensor>
    <contact name="wall_contact" subtree1="robot" body2="walls" data="found" reduce="mindist"/>{imu_sensor}
  </sensor>
</mujoco>"""


OBJECT_GROUP = 3  # the geom group of objects alone: what the colour sensor's downward ray looks at
UPRIGHT_COS = 0.9  # an object stands while its axis is within about 25 degrees of the vertical


def _object_mjcf(o: CourseObject) -> str:
    """An object as a free body standing on the floor. Its geom's priority makes its own friction the one of
    every contact it has (MuJoCo otherwise takes the larger of the two geoms')."""
    a, b, h = o.size
    size = f"{a} {h / 2}" if o.shape == "cylinder" else f"{a / 2} {b / 2} {h / 2}"
    rgba = " ".join(f"{c / 255:.4g}" for c in o.rgb)
    return (f'<body name="object_{o.name}" pos="{o.x} {o.y} {h / 2}" euler="0 0 {o.yaw_deg}" sleep="init">'
            f'<freejoint/>'
            f'<geom name="object_{o.name}" type="{o.shape}" size="{size}" mass="{o.mass}" group="{OBJECT_GROUP}" '
            f'priority="1" friction="{o.friction} 0.005 0.0001" rgba="{rgba} 1"/></body>')


@dataclass(frozen=True)
class ObjectState:
    """Where an object is: its centre, whether it still stands, and how fast it moves."""

    x: float
    y: float
    upright: bool
    speed: float  # m/s, of its centre


def _turned(quaternion: np.ndarray, deg: float) -> np.ndarray:
    """`quaternion` turned by `deg` about the world's z axis (counter-clockwise seen from above)."""
    half = math.radians(deg) / 2
    turned = np.empty(4)
    mujoco.mju_mulQuat(turned, np.array([math.cos(half), 0.0, 0.0, math.sin(half)]), np.array(quaternion))
    return turned


@dataclass(frozen=True)
class Inertial:
    """What a hub IMU fixed in the robot would measure, in the robot's frame (x forward, y left, z up)."""

    angular_velocity_dps: tuple[float, float, float]  # right-handed about x, y, z: z counter-clockwise from above
    acceleration_mm_s2: tuple[float, float, float]  # specific force: at rest (0, 0, +g)


@dataclass(frozen=True)
class Measurement:
    """What the robot's sensors would read at one instant if they were perfect (`sensors.py` makes them
    EV3 sensors)."""

    reflect: float  # 0..100 under the colour sensor: the red channel, in the EV3's scale
    sensor_xy: tuple[float, float]  # where the colour sensor looks at the floor
    rate_dps: float  # clockwise positive, as the gyro angle
    ultrasonic_mm: int
    gyro_angle_deg: float  # heading in (-180, 180], clockwise positive seen from above
    touch: bool  # the robot's bumper: the body touching a wall
    wheel_angles_deg: tuple[float, float]  # left, right encoder
    colour: tuple[float, float, float] | None = None  # green, blue, mean channels; None on a grey


class World:
    def __init__(self, course: Course, body: robot.Body = robot.EV3_BODY, imu: bool = False) -> None:
        """`imu`: give the robot a hub IMU (`inertial`); only a robot that has one pays for its sensor."""
        self.course = course
        self.body = body
        self.model = mujoco.MjModel.from_xml_string(build_mjcf(course, body, imu))
        self.data = mujoco.MjData(self.model)
        m = self.model
        self._robot_body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "robot")
        self._color_site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, "color_sensor")
        self._sonar_site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, "ultrasonic")
        self._wheel_qpos = [m.jnt_qposadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, n)]
                            for n in ("wheel_left", "wheel_right")]
        self._wall_contact = m.sensor_adr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SENSOR, "wall_contact")]
        self._accel = m.sensor_adr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SENSOR, "imu_accel")] if imu else None
        # Views of MjData's arrays, made once: each attribute access makes a new numpy view, and the lockstep
        # reads and writes these at every tick and snapshot. MjData is never reallocated, so they stay valid.
        d = self.data
        self._qpos, self._ctrl, self._sensordata = d.qpos, d.ctrl, d.sensordata
        self._color_xpos, self._sonar_xpos = d.site_xpos[self._color_site], d.site_xpos[self._sonar_site]
        self._ray_direction = np.zeros(3)  # mj_ray's arguments, filled in place at each reading
        self._ray_geom = np.zeros(1, dtype=np.int32)
        self._wheel_dof = [m.jnt_dofadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, n)]
                           for n in ("wheel_left", "wheel_right")]
        bodies = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"object_{o.name}") for o in course.objects]
        # Each object's free joint: where its qpos (7) and qvel (6) start.
        self._objects = {o.name: (m.jnt_qposadr[m.body_jntadr[b]], m.jnt_dofadr[m.body_jntadr[b]])
                         for o, b in zip(course.objects, bodies)}
        self._object_rgb = {mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, f"object_{o.name}"): o.rgb
                            for o in course.objects}
        self._groups = np.zeros(mujoco.mjNGROUP, dtype=np.uint8)
        self._groups[OBJECT_GROUP] = 1
        self._down = np.array([0.0, 0.0, -1.0])
        mujoco.mj_forward(m, self.data)
        if imu:  # settled on its wheels before the test starts: at t = 0 an IMU reads a robot at rest, not one
            self.step(SETTLE_STEPS)  # put down in free fall (for an EV3 robot nothing reads it; left as it was)
        self._initial = self._snapshot()

    # -- state ---------------------------------------------------------------------------------------
    def _snapshot(self) -> tuple[np.ndarray, ...]:
        d = self.data
        return d.qpos.copy(), d.qvel.copy(), d.act.copy(), d.ctrl.copy()

    def reset(self) -> None:
        """Back to the state saved at start-up (the paper saves Robot and env once and restores them)."""
        mujoco.mj_resetData(self.model, self.data)
        qpos, qvel, act, ctrl = self._initial
        d = self.data
        d.qpos[:], d.qvel[:], d.act[:], d.ctrl[:] = qpos, qvel, act, ctrl
        mujoco.mj_forward(self.model, d)

    def step(self, n: int) -> None:
        mujoco.mj_step(self.model, self.data, n)

    # -- actuators -----------------------------------------------------------------------------------
    def set_motor_power(self, left: int, right: int, gains: tuple[float, float] | None = None) -> None:
        """Motor power in percent, -100..100, as EV3RT takes it; `gains` (noise) multiply the wheel speeds
        the powers command."""
        scale = self.body.max_wheel_speed / 100.0
        left_speed, right_speed = max(-100, min(100, left)) * scale, max(-100, min(100, right)) * scale
        if gains is not None:
            left_speed, right_speed = left_speed * gains[0], right_speed * gains[1]
        self._ctrl[:2] = left_speed, right_speed

    def put_down(self, offset: StartOffset) -> None:
        """Back to the saved start state, with the robot put down `offset` away from the start pose (a
        person placing it by hand), at rest."""
        self.reset()
        q = self.data.qpos
        q[0] += offset.dx_m
        q[1] += offset.dy_m
        q[3:7] = _turned(q[3:7], offset.dyaw_deg)
        mujoco.mj_forward(self.model, self.data)

    def place(self, pose: Pose, offset: StartOffset) -> None:
        """Lift the robot and set it down at `pose`, `offset` away (a person's aim), at rest and standing as it
        stood at the start (its saved height and lean, turned to the new heading). Only the free joint moves:
        the wheels keep their angles, so the encoders count on, and the motors keep their commands."""
        q, d = self.data.qpos, self.data
        start = self._initial[0]
        q[0], q[1], q[2] = pose.x + offset.dx_m, pose.y + offset.dy_m, start[2]
        q[3:7] = _turned(start[3:7], pose.yaw_deg + offset.dyaw_deg - self.course.start.yaw_deg)
        d.qvel[:6] = 0.0  # the robot's free joint; the course's objects go on as they were
        d.qvel[self._wheel_dof] = 0.0
        mujoco.mj_forward(self.model, d)

    # -- geometry ------------------------------------------------------------------------------------
    def position(self) -> tuple[float, float]:
        """Axle centre (x, y): all the lap checks need, ten times a simulated second."""
        x, y = self._qpos[:2].tolist()
        return x, y

    def pose(self) -> tuple[float, float, float]:
        """Axle centre (x, y) and heading [rad], counter-clockwise from +x."""
        x, y, _, w, x_, y_, z = self._qpos[:7].tolist()
        yaw = math.atan2(2 * (w * z + x_ * y_), 1 - 2 * (y_ * y_ + z * z))
        return x, y, yaw

    def state(self) -> tuple[float, ...]:
        """The robot's free joint (position, orientation quaternion) and wheel angles [rad]: what a replay
        needs to show the robot as it was."""
        q = self._qpos
        return (*q[:7].tolist(), *q[self._wheel_qpos].tolist())

    def touching_wall(self) -> bool:
        return self._sensordata[self._wall_contact] > 0

    def object_states(self) -> tuple[float, ...]:
        """Every object's free joint (position, orientation quaternion), in course order: what a replay needs
        to show them as they were."""
        q = self._qpos
        return tuple(v for a, _ in self._objects.values() for v in q[a:a + 7].tolist())

    def object_state(self, name: str) -> ObjectState:
        a, dof = self._objects[name]
        x, y, _, _, qx, qy, _ = self._qpos[a:a + 7].tolist()
        vx, vy, vz = self.data.qvel[dof:dof + 3].tolist()  # a free joint's linear velocity, in world axes
        axis_z = 1 - 2 * (qx * qx + qy * qy)  # the z component of the object's own vertical axis
        return ObjectState(x, y, axis_z >= UPRIGHT_COS, math.sqrt(vx * vx + vy * vy + vz * vz))

    def wheel_speeds(self) -> tuple[float, float]:
        """The wheels' turning speeds [rad/s]: both near 0 is the robot at a complete stop."""
        left, right = self.data.qvel[self._wheel_dof].tolist()
        return left, right

    # -- sensors -------------------------------------------------------------------------------------
    def measure(self) -> Measurement:
        sx, sy = self._color_xpos[:2].tolist()
        _, _, yaw = self.pose()
        reflect, colour = self._floor_under(sx, sy)
        return Measurement(
            reflect=reflect,
            colour=colour,
            sensor_xy=(sx, sy),
            rate_dps=-math.degrees(float(self.data.qvel[5])),
            ultrasonic_mm=self._ultrasonic_mm(yaw),
            gyro_angle_deg=self.gyro_angle_deg(yaw),
            touch=self.touching_wall(),
            wheel_angles_deg=self.wheel_angles_deg(),
        )

    def _floor_under(self, x: float, y: float) -> tuple[float, tuple[float, float, float] | None]:
        """The colour channels at the sensor's spot: an object's where one is under it, else the floor's."""
        course = self.course
        if self._object_rgb:
            origin = np.array([x, y, 10.0])
            if mujoco.mj_ray(self.model, self.data, origin, self._down, self._groups, 1, -1, self._ray_geom) >= 0:
                ev3 = course.ev3
                rgb = self._object_rgb[int(self._ray_geom[0])]
                r, g, b = (ev3.black + (ev3.white - ev3.black) * c / 255 for c in rgb)
                return r, (g, b, (r + g + b) / 3)
        return course.reflect_at(x, y), course.colour_at(x, y)

    def inertial(self) -> Inertial:
        """The hub IMU's reading: the free joint's angular velocity, which MuJoCo gives in the body's own
        frame, and the accelerometer's specific force (as of the last step, which computed it)."""
        assert self._accel is not None, "this world's robot has no IMU"
        d = self.data
        wx, wy, wz = (math.degrees(float(v)) for v in d.qvel[3:6])
        ax, ay, az = (float(v) * 1000.0 for v in d.sensordata[self._accel:self._accel + 3])
        return Inertial((wx, wy, wz), (ax, ay, az))

    def wheel_angles_deg(self) -> tuple[float, float]:
        q = self._qpos
        left, right = (math.degrees(q[a]) for a in self._wheel_qpos)
        return left, right

    def gyro_angle_deg(self, yaw: float | None = None) -> float:
        """Heading in (-180, 180]: EV3's gyro counts clockwise seen from above; the world's yaw is
        counter-clockwise."""
        return -math.degrees(self.pose()[2] if yaw is None else yaw)

    def _ultrasonic_mm(self, yaw: float) -> int:
        direction = self._ray_direction
        direction[:2] = math.cos(yaw), math.sin(yaw)
        dist = mujoco.mj_ray(self.model, self.data, self._sonar_xpos, direction, None, 1, self._robot_body,
                             self._ray_geom)
        if dist < 0:
            return robot.ULTRASONIC_MAX_MM
        return min(robot.ULTRASONIC_MAX_MM, round(dist * 1000))
