"""Films of a test (issue 27): a frame shows the robot and the floor where the world has them, a video has
the frames its duration, fps and speed say, from the first pose to the last, and filming changes nothing a
test reports. The renderer needs OpenGL (EGL or OSMesa): where none can be had, these tests say so and skip."""

from __future__ import annotations

import json
import math
import os
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from hakoniwa.physics.course import COURSES_DIR, load_course
from hakoniwa.physics.replay import REPLAY_FILE, Replay, RobotLook, read_replay, write_replay
from hakoniwa.physics.robots import DEFAULT_ROBOT, HACKSPI
from hakoniwa.pictures.video_options import VideoOptions
from tests.helpers.commands import hako, one_line_error

OVAL = load_course("oval")


@pytest.fixture(scope="module")
def video():
    from hakoniwa.pictures import video

    problem = video.gl_problem()
    if problem:
        pytest.skip(problem)
    return video


def look(robot=DEFAULT_ROBOT) -> RobotLook:
    return RobotLook(robot.name, robot.hub, robot.body, tuple(k for _, k in robot.sensors))


def state(x: float, y: float, yaw: float, robot=DEFAULT_ROBOT, wheels: float = 0.0) -> tuple[float, ...]:
    return (x, y, robot.body.wheel_radius, math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2), wheels, wheels)


def replay_of(times_us: list[int], states: list[tuple[float, ...]], robot=DEFAULT_ROBOT, event: str = "TIME_OVER",
              passed_us: tuple[int, ...] = ()) -> Replay:
    return Replay(str(COURSES_DIR / "oval"), look(robot), "lap", len(OVAL.checkpoints), event, times_us[-1],
                  passed_us, None, tuple(times_us), tuple(states))


def robot_centroid(frame: np.ndarray, background: np.ndarray) -> tuple[float, float]:
    """Where the robot is in a frame: the centre of the pixels that differ from the same view without it."""
    rows, cols = np.nonzero(np.abs(frame.astype(int) - background.astype(int)).sum(axis=2) > 60)
    assert len(rows) > 50, "no robot in the frame"
    return float(cols.mean()), float(rows.mean())


AWAY = state(50.0, 50.0, 0.0)  # far off the course: the same view without the robot


def test_a_frame_shows_the_robot_and_the_line_where_the_world_has_them(video) -> None:
    x, y, yaw = -0.55, -0.68, math.radians(30)  # between the line's bottom straight and the south wall
    filmer = video.Filmer(replay_of([0, 1], [state(x, y, yaw)] * 2), camera="top")
    frame = filmer.render(0, overlay=False)
    cam = filmer.gl_camera()
    w, h = filmer.width, filmer.height
    filmer.replay = replay_of([0, 1], [AWAY] * 2)
    empty = filmer.render(0, overlay=False)
    body = DEFAULT_ROBOT.body
    hx, hy, hz = body.chassis_half
    u, v = -0.01 - 0.8 * hx, 0.6 * hy  # on the brick's top, in the robot's frame: clear of its screen and buttons
    top = (x + u * math.cos(yaw) - v * math.sin(yaw), y + u * math.sin(yaw) + v * math.cos(yaw),
           body.wheel_radius + 2 * hz)
    col, row = (round(v) for v in video.project(cam, top, w, h))
    robot_top = frame[row, col].astype(int)
    assert robot_top.max() < 110 and robot_top.max() - robot_top.min() < 25, robot_top  # the EV3's dark grey top
    assert empty[row, col].min() > 170, empty[row, col]  # where the white floor is without it
    # The colour sensor, ahead of the axle along the heading (and nothing as far behind it): the robot faces
    # the way the world says.
    def at(distance: float) -> np.ndarray:
        point = (x + distance * math.cos(yaw), y + distance * math.sin(yaw), 0.005)
        col, row = (round(v) for v in video.project(cam, point, w, h))
        return frame[row, col].astype(int)

    assert at(body.color_sensor_forward).max() < 80 and at(-2 * body.color_sensor_forward).min() > 170
    # The floor: dark where the floor image has the line, light where it has none, off walls and checkpoints.
    def free(px: float, py: float) -> bool:  # clear of the walls and their shadows, and of the checkpoints
        return not any(abs(px - b.x) <= b.hx + m and abs(py - b.y) <= b.hy + m
                       for boxes, m in ((OVAL.walls, 0.06), (OVAL.checkpoints, 0.0)) for b in boxes)

    dark, light = [], []
    darkest = float(OVAL.floor.min())  # the soft line's centre
    for px in np.linspace(-1.4, 1.4, 141):
        for py in np.linspace(-0.8, 0.8, 81):
            if not free(px, py):
                continue
            reflect = OVAL.reflect_at(px, py)
            col, row = (round(v) for v in video.project(cam, (px, py, 0.0), w, h))
            brightness = int(empty[row, col].max())
            if reflect <= darkest + 2:
                dark.append(brightness)
            elif reflect >= OVAL.reflect_white - 1:
                light.append(brightness)
    assert len(dark) > 20 and len(light) > 1000
    assert max(dark) < 80 < 170 < min(light), (max(dark), min(light))
    filmer.close()


def test_a_spike_robot_looks_like_a_spike_hub(video) -> None:
    filmer = video.Filmer(replay_of([0, 1], [state(-0.55, -0.7, 0.0, HACKSPI)] * 2, HACKSPI), camera="top")
    frame = filmer.render(0, overlay=False)
    body = HACKSPI.body
    hx, hy, hz = body.chassis_half
    side = (-0.55 - 0.01 - 0.85 * hx, -0.7 + 0.8 * hy, body.wheel_radius + 2 * hz)  # the frame beside the hub
    col, row = (round(v) for v in video.project(filmer.gl_camera(), side, filmer.width, filmer.height))
    r, g, b = (int(v) for v in frame[row - 1:row + 2, col - 1:col + 2].reshape(-1, 3).mean(axis=0))
    assert r > 120 and g > 90 and b < 70, (r, g, b)  # the hub's yellow
    filmer.close()


def straight_run(seconds: float = 2.0) -> Replay:
    """The robot driving 0.6 m along the bottom, clear of the line, sampled every 50 ms as the bench does."""
    times = list(range(0, round(seconds * 1e6) + 1, 50_000))
    states = [state(-0.95 + 0.5 * t / 1e6 / seconds, -0.7, 0.0, wheels=t / 1e5) for t in times]
    return replay_of(times, states)


@pytest.mark.parametrize("suffix, fps, speed", [(".gif", 15, 3.0), (".mp4", 12, 1.0)])
def test_a_video_has_duration_x_fps_over_speed_frames_from_the_first_pose_to_the_last(
        video, tmp_path: Path, suffix: str, fps: int, speed: float) -> None:
    replay = straight_run()
    out = tmp_path / f"run{suffix}"
    assert video.film(replay, VideoOptions(out, "top", fps, speed)) == round(2.0 * fps / speed)
    frames = read_frames(out)
    assert len(frames) == round(2.0 * fps / speed)
    filmer = video.Filmer(replay, camera="top")
    filmer.replay = replay_of([0, 1], [AWAY] * 2)
    empty = filmer.render(0)
    filmer.replay = replay
    for frame, t in ((frames[0], 0), (frames[-1], replay.duration_us)):
        expected = robot_centroid(filmer.render(t), empty)
        found = robot_centroid(frame, empty)
        assert math.dist(found, expected) < 1.5, (t, found, expected)
    # and the robot moved: 0.6 m is some 120 pixels in this view
    assert robot_centroid(frames[-1], empty)[0] - robot_centroid(frames[0], empty)[0] > 100
    filmer.close()


def read_frames(path: Path) -> list[np.ndarray]:
    if path.suffix == ".gif":
        with Image.open(path) as im:
            out = []
            for i in range(im.n_frames):
                im.seek(i)
                out.append(np.asarray(im.convert("RGB")))
            return out
    import imageio_ffmpeg

    gen = imageio_ffmpeg.read_frames(str(path))
    meta = next(gen)
    w, h = meta["size"]
    return [np.frombuffer(f, dtype=np.uint8).reshape(h, w, 3) for f in gen]


def test_frame_times_run_from_the_start_to_the_end_at_the_speed_asked() -> None:
    from hakoniwa.pictures.video import frame_times_us

    times = frame_times_us(35_680_000, 30, 4.0)
    assert len(times) == round(35.68 * 30 / 4) and times[0] == 0 and times[-1] == 35_680_000
    assert frame_times_us(0, 30, 1.0) == [0.0]


def test_a_replay_survives_its_file_and_interpolates_between_samples(tmp_path: Path) -> None:
    replay = straight_run()
    write_replay(tmp_path / REPLAY_FILE, replay)
    again = read_replay(tmp_path)
    assert again.times_us == replay.times_us and again.robot == replay.robot
    middle = again.state_at(25_000)
    assert middle[0] == pytest.approx((replay.states[0][0] + replay.states[1][0]) / 2, abs=1e-6)
    assert again.state_at(-5) == again.states[0] and again.state_at(1e9) == again.states[-1]


def test_replay_of_a_folder_without_one_is_one_line(tmp_path: Path) -> None:
    one_line_error(hako("replay", str(tmp_path), "--video", str(tmp_path / "x.gif")), "replay.json")
    (tmp_path / REPLAY_FILE).write_text("{not json")
    one_line_error(hako("replay", str(tmp_path), "--video", str(tmp_path / "x.gif")), "not a replay")


@pytest.mark.parametrize("args, words", [
    (["--video", "lap.avi"], [".mp4 or .gif"]),
    (["--video", "lap.gif", "--speed", "0x"], ["speed"]),
    (["--video", "lap.gif", "--speed", "fast"], ["speed"]),
    (["--video", "lap.gif", "--fps", "100"], ["GIF"]),
    (["--video", "no/such/folder/lap.gif"], ["does not exist"]),
])
def test_bad_video_options_are_one_line_before_any_test(tmp_path: Path, args: list[str], words: list[str]) -> None:
    r = hako("try", "--run-dir", str(tmp_path / "run"), *args, cwd=tmp_path)
    one_line_error(r, *words)
    assert not (tmp_path / "run" / REPLAY_FILE).exists()


def test_view_without_a_display_is_one_line_and_exit_1_within_a_second(tmp_path: Path) -> None:
    """Within a second on a machine that starts `hako` in a fraction of one; on a loaded one, no later than
    `hako --help` answers plus a fifth of a second: the refusal comes before anything but parsing."""
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    start = time.monotonic()
    hako("--help")
    startup = time.monotonic() - start
    start = time.monotonic()
    r = hako("try", "--view", "--run-dir", str(tmp_path), env=env, timeout=10)
    assert time.monotonic() - start < max(1.0, startup + 0.2)
    assert r.returncode == 1
    one_line_error(r, "--view", "display")


@pytest.mark.slow
def test_filming_a_trial_changes_nothing_it_reports_and_makes_a_five_second_clip(video, tmp_path: Path) -> None:
    """The paper's tracer with its best gains, as the README shows it: the whole lap at 6.5x is a 5 s clip."""
    plain = hako("try", "--json", "--run-dir", str(tmp_path / "a"))
    filmed = hako("try", "--json", "--run-dir", str(tmp_path / "b"), "--video", str(tmp_path / "lap.gif"),
                  "--speed", "6.5x", "--fps", "10")
    assert plain.returncode == 0 and filmed.returncode == 0, filmed.stderr
    assert plain.stdout == filmed.stdout  # byte for byte
    result = json.loads(filmed.stdout)
    replay = read_replay(tmp_path / "b")
    assert replay.event == result["event"] == "GOAL" and replay.event_us == result["goal_time_us"]
    assert len(replay.passed_us) == result["checkpoints"] and replay.times_us[-1] == result["goal_time_us"]
    with Image.open(tmp_path / "lap.gif") as im:
        assert im.n_frames == round(result["lap_time_s"] * 10 / 6.5)
        shown_s = 0.0
        for i in range(im.n_frames):
            im.seek(i)
            shown_s += im.info["duration"] / 1000
        assert shown_s == pytest.approx(im.n_frames / 10, abs=0.011) and 4.8 <= shown_s <= 5.4
    # The replay's samples are the trajectory's (at the same ticks), plus the moment the test ended.
    rows = (tmp_path / "b" / "trajectory.csv").read_text().splitlines()[1:]
    first, last = rows[0].split(","), rows[-1].split(",")
    assert replay.times_us[0] == int(first[0]) and replay.states[0][0] == pytest.approx(float(first[1]), abs=1e-5)
    i = replay.times_us.index(int(last[0]))
    assert replay.states[i][1] == pytest.approx(float(last[2]), abs=1e-5)
    again = hako("replay", str(tmp_path / "b"), "--video", str(tmp_path / "again.gif"), "--speed", "6.5x",
                 "--fps", "10")
    assert again.returncode == 0, again.stderr
    assert (tmp_path / "again.gif").read_bytes() == (tmp_path / "lap.gif").read_bytes()


@pytest.mark.slow
def test_view_paces_the_lockstep_and_changes_nothing_it_reports(tmp_path: Path) -> None:
    """On a virtual display (Xvfb): the viewer opens, the test takes at least its lap / speed of wall time,
    and its result is byte for byte the unwatched one."""
    import shutil
    import subprocess

    if shutil.which("Xvfb") is None:
        pytest.skip("no Xvfb to give the viewer a display (apt-get install xvfb)")
    display = f":{os.getpid() % 400 + 100}"
    xvfb = subprocess.Popen(["Xvfb", display, "-screen", "0", "1280x1024x24"], stderr=subprocess.DEVNULL)
    try:
        time.sleep(1)
        env = {**{k: v for k, v in os.environ.items() if k != "MUJOCO_GL"}, "DISPLAY": display}
        plain = hako("try", "--json", "--run-dir", str(tmp_path / "a"))
        start = time.monotonic()
        viewed = hako("try", "--json", "--view", "--speed", "8x", "--run-dir", str(tmp_path / "b"), env=env)
        wall = time.monotonic() - start
    finally:
        xvfb.terminate()
        xvfb.wait()
    assert viewed.returncode == 0, viewed.stderr
    assert viewed.stdout == plain.stdout
    assert wall >= json.loads(plain.stdout)["lap_time_s"] / 8


def test_the_film_module_picks_egl_before_mujoco_chooses_its_backend() -> None:
    """A user's shell has no MUJOCO_GL: the film module must set EGL before MuJoCo is imported, or MuJoCo takes
    GLFW and the campaign's film of the best lap fails headless (the test suite itself sets MUJOCO_GL)."""
    import subprocess
    import sys

    code = "import os\nimport hakoniwa.pictures.video\nprint(os.environ.get('MUJOCO_GL'))"
    env = {k: v for k, v in os.environ.items() if k != "MUJOCO_GL"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert out.stdout.strip() == "egl"


def test_a_backend_that_opens_a_context_but_cannot_render_is_told_before_the_film() -> None:
    """GLFW without a display only warns when its context is made; MuJoCo's rendering context then fails. The
    probe must say so, so that a film is refused in one line instead of a traceback after the campaign."""
    import subprocess
    import sys

    code = ("import warnings\nwarnings.simplefilter('ignore')\n"
            "from hakoniwa.pictures.video import gl_problem\nprint(gl_problem())")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")} | {"MUJOCO_GL": "glfw"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert out.stdout.startswith("MuJoCo cannot render here (MUJOCO_GL=glfw"), out.stdout


def test_a_machine_without_egl_gets_a_note_not_a_traceback_at_import() -> None:
    """With MUJOCO_GL=egl and no libEGL, PyOpenGL breaks `import mujoco` itself, and the campaign that had
    written all its results ended in a traceback when it came to film its best lap (seen on a GPU machine
    whose image has no libEGL). Without EGL the backend is left to MuJoCo, and the probe says why not."""
    import subprocess
    import sys

    code = ("import ctypes.util, os, warnings\nwarnings.simplefilter('ignore')\n"
            "ctypes.util.find_library = lambda name: None\n"
            "import hakoniwa.pictures.video as video\nprint(os.environ.get('MUJOCO_GL'), video.gl_problem() is None)")
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "DISPLAY", "WAYLAND_DISPLAY")}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert out.stdout.split() == ["None", "False"], out.stdout
