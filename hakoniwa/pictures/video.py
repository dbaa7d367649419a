"""A test's replay filmed: MuJoCo renders each frame offscreen (EGL by default, or MUJOCO_GL=osmesa), Pillow
writes the overlay (simulated time, lap, checkpoints, the event) and a GIF, imageio-ffmpeg an MP4.

Under ET Robocon's score the overlay shows the LAP time once it is reached and the score at the end.
It runs after the test, from the replay file, never inside the lockstep loop, so a film changes nothing a
test measures. Frame i of N shows simulated time duration x i / (N - 1), N = round(duration x fps / speed):
the first frame is the start, the last the moment the test ended, and the film plays at `speed` times real
time (to within one frame over the whole film).
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from hakoniwa.pictures.scene import HEIGHT, WIDTH, Scene, build_scene  # before mujoco: it picks the OpenGL backend

# isort: split
import mujoco
import numpy as np

from hakoniwa.physics.course import Course, load_course
from hakoniwa.physics.replay import Replay
from hakoniwa.pictures.video_options import VideoOptions
from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.etrobocon_rules import Score
from hakoniwa.wire.timebase import US_PER_S

CHASE_DISTANCE_M = 0.9
CHASE_ELEVATION_DEG = -32.0
CHASE_LAG_S = 0.5  # the chase camera turns after the robot with this time constant: a tracer's wobble
# would swing a rigidly mounted one
CHECKPOINT_NOTE_S = 1.5  # how long "checkpoint 2 at 10.35 s" stays on screen


class VideoError(HakoError, RuntimeError):
    """No film can be made here (no OpenGL, no writer); the message says why and what to install."""


def gl_problem() -> str | None:
    """Why MuJoCo cannot render offscreen here, or None when it can. The probe goes as far as MuJoCo's own
    rendering context: GLFW without a display only warns when its GL context is made, and fails there."""
    try:
        ctx = mujoco.GLContext(16, 16)
        ctx.make_current()
        try:
            mujoco.MjrContext(mujoco.MjModel.from_xml_string("<mujoco/>"), mujoco.mjtFontScale.mjFONTSCALE_100)
        finally:
            ctx.free()
    except Exception as e:  # the backends raise what their libraries raise: ImportError, OSError, RuntimeError
        backend = os.environ.get("MUJOCO_GL", "glfw")
        why = str(e).splitlines()[0] if str(e) else type(e).__name__
        return (f"MuJoCo cannot render here (MUJOCO_GL={backend}: {why}); "
                "install EGL (apt-get install libegl1 libgl1-mesa-dri) or OSMesa (libosmesa6, with MUJOCO_GL=osmesa)")
    return None


def frame_times_us(duration_us: int, fps: int, speed: float) -> list[float]:
    n = max(1, round(duration_us / US_PER_S * fps / speed))
    if n == 1:
        return [0.0]
    return [duration_us * i / (n - 1) for i in range(n)]


def yaw_of(state) -> float:
    w, x, y, z = state[3:7]
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


@dataclass
class Camera:
    """Where the camera is for each frame: `top` fixed over the course, `chase` behind the robot, turning
    after it with a lag."""

    kind: str
    course: Course
    aspect: float
    fovy_deg: float
    _yaw: float | None = None
    _t_us: float = 0.0

    def place(self, cam: mujoco.MjvCamera, state, t_us: float) -> None:
        cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        if self.kind == "top":
            xmin, xmax, ymin, ymax = self.course.extent
            cam.lookat[:] = ((xmin + xmax) / 2, (ymin + ymax) / 2, 0.0)
            half = math.tan(math.radians(self.fovy_deg) / 2)
            cam.distance = 1.04 * max((ymax - ymin) / 2 / half, (xmax - xmin) / 2 / (half * self.aspect))
            cam.azimuth, cam.elevation = 90.0, -90.0
            return
        yaw = yaw_of(state)
        if self._yaw is None or not 0 < t_us - self._t_us < US_PER_S:  # the first frame, or a frame out of order
            self._yaw = yaw
        else:  # the heading unwrapped onto the camera's, then followed with a first-order lag
            dt = (t_us - self._t_us) / US_PER_S
            target = self._yaw + (yaw - self._yaw + math.pi) % (2 * math.pi) - math.pi
            self._yaw += (target - self._yaw) * (1 - math.exp(-dt / CHASE_LAG_S))
        self._t_us = t_us
        x, y = state[0], state[1]
        cam.lookat[:] = (x + 0.12 * math.cos(yaw), y + 0.12 * math.sin(yaw), 0.03)
        cam.distance = CHASE_DISTANCE_M
        cam.azimuth, cam.elevation = math.degrees(self._yaw), CHASE_ELEVATION_DEG


def project(gl_camera: mujoco.MjvGLCamera, point, width: int, height: int) -> tuple[float, float]:
    """The pixel (column, row from the top) where a world point appears through MuJoCo's camera."""
    pos, fwd, up = (np.array(v, dtype=float) for v in (gl_camera.pos, gl_camera.forward, gl_camera.up))
    right = np.cross(fwd, up)
    v = np.asarray(point, dtype=float) - pos
    z = v @ fwd
    xs, ys = (v @ right) * gl_camera.frustum_near / z, (v @ up) * gl_camera.frustum_near / z
    top, bottom = gl_camera.frustum_top, gl_camera.frustum_bottom
    half = gl_camera.frustum_width or (top - bottom) / 2 * width / height  # 0: from the viewport, as mjr_render
    left = gl_camera.frustum_center - half
    col = width * (xs - left) / (2 * half)
    row = height * (top - ys) / (top - bottom)
    return float(col), float(row)


class Filmer:
    """Renders a replay's frames; one OpenGL context for all of them."""

    def __init__(self, replay: Replay, camera: str = "chase", width: int = WIDTH, height: int = HEIGHT,
                 course: Course | None = None, title: str = "") -> None:
        problem = gl_problem()
        if problem:
            raise VideoError(problem)
        self.replay = replay
        self.course = course or load_course(replay.course)
        self.scene: Scene = build_scene(self.course, replay.robot, width, height)
        self.width, self.height = width, height
        self.renderer = mujoco.Renderer(self.scene.model, height, width)
        self.camera = Camera(camera, self.course, width / height, float(self.scene.model.vis.global_.fovy))
        self.cam = mujoco.MjvCamera()
        self.title = title or f"{self.course.name} · {replay.robot.name}"
        self._font = _font(max(12, height // 24))
        self._big = _font(max(18, height // 12))
        self._small = _font(max(10, height // 30))

    def render(self, t_us: float, overlay: bool = True) -> np.ndarray:
        r = self.replay
        state = r.state_at(t_us)
        self.scene.show(state, r.passed_at(t_us), r.objects_at(t_us))
        self.camera.place(self.cam, state, t_us)
        self.renderer.update_scene(self.scene.data, self.cam)
        pixels = self.renderer.render()
        return self._overlay(pixels, t_us) if overlay else pixels

    def gl_camera(self) -> mujoco.MjvGLCamera:
        """The camera of the last frame rendered, as MuJoCo placed it: a mono frame is seen from between the
        two stereo eyes MuJoCo places (`mjv_averageCamera`)."""
        scene = self.renderer.scene
        return mujoco.mjv_averageCamera(scene.camera[0], scene.camera[1])

    def frames(self, fps: int, speed: float) -> Iterator[np.ndarray]:
        for t in frame_times_us(self.replay.duration_us, fps, speed):
            yield self.render(t)

    def close(self) -> None:
        self.renderer.close()

    def _overlay(self, pixels: np.ndarray, t_us: float) -> np.ndarray:
        from PIL import Image, ImageDraw

        r = self.replay
        img = Image.fromarray(pixels)
        draw = ImageDraw.Draw(img, "RGBA")
        bar = self.height // 13
        draw.rectangle((0, 0, self.width, bar), fill=(15, 18, 24, 170))
        n = r.checkpoints
        passed = r.passed_at(t_us)
        ended = t_us >= r.event_us and r.event != "NONE"
        lap = (passed - 1) // n + 1 if passed else 1  # a lap's last checkpoint still counts to that lap
        this_lap = passed - n * (lap - 1)
        text = f"t {t_us / US_PER_S:6.2f} s    lap {lap}    checkpoints {this_lap}/{n}"
        lap_s = r.score["lap_time_s"] if r.score else None
        if lap_s is not None and t_us >= lap_s * US_PER_S:
            text = f"t {t_us / US_PER_S:6.2f} s    LAP {lap_s:.2f} s    checkpoints {this_lap}/{n}"
        pad = bar // 4
        draw.text((pad, pad), text, font=self._font, fill=(255, 255, 255, 255))
        small = self._small
        tw = draw.textlength(self.title, font=small)
        draw.rectangle((0, self.height - small.size - 2 * pad, tw + 2 * pad, self.height), fill=(15, 18, 24, 140))
        draw.text((pad, self.height - small.size - pad), self.title, font=small, fill=(215, 220, 230, 255))
        recent = [i for i, p in enumerate(r.passed_us) if p <= t_us < p + CHECKPOINT_NOTE_S * US_PER_S]
        if recent and not ended:
            i = recent[-1]
            note = f"checkpoint {i % n + 1} at {r.passed_us[i] / US_PER_S:.2f} s"
            draw.text((pad, bar + pad), note, font=self._font, fill=(120, 240, 140, 255),
                      stroke_width=2, stroke_fill=(0, 0, 0, 200))
        if ended:
            banner = _event_text(r)
            w = draw.textlength(banner, font=self._big)
            y = bar + pad
            score = Score.from_dict(r.score).describe() if r.score else ""
            bottom = y + self._big.size + 2 * pad + (self._font.size + pad if score else 0)
            draw.rectangle((0, y - pad, self.width, bottom), fill=(15, 18, 24, 150))
            colour = _EVENT_COLOUR.get(r.event, (255, 255, 255))
            draw.text(((self.width - w) / 2, y), banner, font=self._big, fill=colour)
            if score:
                font = self._font if draw.textlength(score, font=self._font) < self.width - 2 * pad else self._small
                w = draw.textlength(score, font=font)
                draw.text(((self.width - w) / 2, y + self._big.size + pad), score, font=font, fill=(255, 230, 120, 255))
        return np.asarray(img)


_EVENT_COLOUR = {"GOAL": (110, 235, 130), "COMPLETED": (110, 235, 130), "FINISH": (110, 235, 130),
                 "HIT_WALL": (255, 120, 100), "TIME_OVER": (255, 200, 90), "CRASH": (255, 120, 100),
                 "COURSE_OUT": (255, 120, 100)}


def _event_text(r: Replay) -> str:
    t = r.event_us / US_PER_S
    if r.event == "GOAL":
        return f"GOAL  lap {t:.2f} s"
    if r.event == "COMPLETED" and r.completed_us is not None:
        return f"COMPLETED at {r.completed_us / US_PER_S:.2f} s"
    return f"{r.event.replace('_', ' ')} at {t:.2f} s"


def _font(size: int):
    from PIL import ImageFont

    for name in ("DejaVuSans-Bold.ttf", "DejaVuSans.ttf", "/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf"):
        try:
            return ImageFont.truetype(name, size)
        except OSError:
            continue
    return ImageFont.load_default(size)


def writer_problem(path: Path) -> str | None:
    """Why this machine cannot write `path`'s format, or None."""
    if Path(path).suffix.lower() == ".mp4":
        try:
            import imageio_ffmpeg  # noqa: F401
        except ImportError:
            return "an MP4 needs imageio-ffmpeg (pip install imageio-ffmpeg); a .gif needs only Pillow"
    return None


def write_video(path: Path, frames: Iterator[np.ndarray], fps: int, size: tuple[int, int]) -> int:
    """Write the frames as an MP4 (H.264 through imageio-ffmpeg's ffmpeg) or a GIF (Pillow, one palette per
    frame); the number of frames written. Written beside and renamed into place."""
    path = Path(path)
    tmp = path.with_name(path.stem + ".part" + path.suffix)
    count = 0
    if path.suffix.lower() == ".mp4":
        import imageio_ffmpeg

        gen = imageio_ffmpeg.write_frames(str(tmp), size, fps=fps, codec="libx264", pix_fmt_out="yuv420p",
                                          quality=7, macro_block_size=2, ffmpeg_log_level="error")
        gen.send(None)
        try:
            for frame in frames:
                gen.send(np.ascontiguousarray(frame))
                count += 1
        finally:
            gen.close()
    else:
        from PIL import Image

        images = [Image.fromarray(f).quantize(colors=128, method=Image.Quantize.MEDIANCUT) for f in frames]
        count = len(images)
        # A GIF's delays are whole hundredths of a second: each frame's is rounded so that their sum stays
        # on time (15 fps is 70, 70, 60 ms ...), where one delay for all would drift (60 ms: 10% fast).
        ticks = [round(i * 100 / fps) for i in range(count + 1)]
        images[0].save(tmp, save_all=True, append_images=images[1:], loop=0, optimize=True,
                       duration=[10 * (b - a) for a, b in zip(ticks, ticks[1:])])
    tmp.replace(path)
    return count


def film(replay: Replay, options: VideoOptions, width: int = WIDTH, height: int = HEIGHT, title: str = "") -> int:
    """Film the replay into `options.path`; the number of frames (VideoError: no OpenGL, no writer)."""
    problem = writer_problem(options.path)
    if problem:
        raise VideoError(problem)
    filmer = Filmer(replay, options.camera, width, height, title=title)
    try:
        return write_video(options.path, filmer.frames(options.fps, options.speed), options.fps, (width, height))
    finally:
        filmer.close()
