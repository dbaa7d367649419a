"""`hako try --view`: MuJoCo's interactive viewer on the test as it runs, paced at real time or a speed.

The viewer shows the render scene (`scene.py`), not the physics model: each look copies the robot's state
into it, so the physics is only read. Looks come from a scheduler stream of the environment, between two
batches of steps; pacing sleeps there until the wall clock catches up with simulated time / speed. In the
lockstep the program waits for physics, so a paced test gives the very result an unpaced one does; in the
real emulator's `hakoniwa` mode results depend on speed anyway, as with Unity.
"""

from __future__ import annotations

import threading
import time
import warnings

from hakoniwa.physics.environment import Environment
from hakoniwa.wire.errors import HakoError
from hakoniwa.wire.timebase import US_PER_S

LOOK_PERIOD_US = 20_000  # 50 looks per simulated second: smooth at real time
CLOSE_WAIT_S = 5.0  # for the viewer's thread to close its window


class ViewerError(HakoError, RuntimeError):
    """The viewer's window cannot open (no display, no OpenGL); one line."""


class LiveView:
    def __init__(self, env: Environment, speed: float) -> None:
        import mujoco.viewer

        from hakoniwa.physics.replay import RobotLook
        from hakoniwa.pictures.scene import build_scene

        r = env.robot
        self.env = env
        self.speed = speed
        self.scene = build_scene(env.course, RobotLook(r.name, r.hub, r.body, tuple(k for _, k in r.sensors)))
        import glfw

        with warnings.catch_warnings():  # GLFW warns, then fails: say it once, in one line
            warnings.simplefilter("ignore")
            if not glfw.init():
                why = glfw.get_error()[1]
                raise ViewerError(f"--view: MuJoCo's viewer cannot open a window "
                                  f"({_text(why) if why else 'GLFW cannot start'})")
        before = set(threading.enumerate())
        try:
            self.viewer = mujoco.viewer.launch_passive(self.scene.model, self.scene.data, show_left_ui=False,
                                                       show_right_ui=False)
        except Exception as e:  # GLFW raises what it raises: no display, no GL, a dead X server
            raise ViewerError(f"--view: MuJoCo's viewer cannot open a window ({e})") from None
        # The viewer's own thread: it must have torn its window down before the process exits, or the exit
        # may crash inside GL (SIGSEGV, seen on Xvfb) after the test's result was written.
        self._threads = [t for t in threading.enumerate() if t not in before]
        self._wall0 = time.monotonic()
        env.scheduler.add("view", LOOK_PERIOD_US, self.look)

    def look(self, now_us: int) -> None:
        if now_us == LOOK_PERIOD_US:  # the first look of a test: its clock starts now
            self._wall0 = time.monotonic() - now_us / US_PER_S / self.speed
        if not self.viewer.is_running():  # the window was closed: the test runs on unwatched and unpaced
            return
        delay = self._wall0 + now_us / US_PER_S / self.speed - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        with self.viewer.lock():
            self.scene.show(self.env.world.state(), len(self.env.task.passed_us), self.env.world.object_states())
        self.viewer.sync()

    def close(self) -> None:
        self.viewer.close()
        for thread in self._threads:
            thread.join(timeout=CLOSE_WAIT_S)


def _text(description: str | bytes) -> str:
    """GLFW's error description: the Python binding returns bytes, though its stubs say str."""
    return description.decode(errors="replace") if isinstance(description, bytes) else description
