"""What a test did, kept so that it can be watched afterwards: the robot's pose and wheel angles at every
trajectory sample (and the course's objects' poses), the checkpoint passes, the event, ET Robocon's score
under that objective, and the course and robot it ran on.

The physics process writes it at each test's end from state it already has (the samples are taken at the
trajectory's 50 ms ticks, which the world steps to anyway), so recording it changes neither a result nor its
timing; rendering happens afterwards, from this file, in another process (`video.py`). One JSON file in the
run directory, replaced whole, like the trajectory.
"""

from __future__ import annotations

import dataclasses
import json
import math
from bisect import bisect_right
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from hakoniwa.physics.robot import Body
from hakoniwa.wire.errors import HakoError

REPLAY_FILE = "replay.json"  # the last test of a run directory, for `hako replay` and --video
REPLAY_VERSION = 1
# One sample: time [us], the free joint's qpos (x, y, z [m], quaternion w, x, y, z), wheel angles [rad].
State = tuple[float, ...]
STATE_SIZE = 9


class ReplayError(HakoError, ValueError):
    """A run directory without a usable replay; the message says which and why, in one line."""


@dataclass(frozen=True)
class RobotLook:
    """What a renderer needs of the robot: its body's sizes, its hub and which sensors it carries."""

    name: str
    hub: str
    body: Body
    sensors: tuple[str, ...]  # kinds, in port order


@dataclass(frozen=True)
class Replay:
    course: str  # the course folder
    robot: RobotLook
    objective: str
    checkpoints: int  # of the course, in a lap
    event: str  # the event's name (NONE for a test that never ended: a bench that died)
    event_us: int
    passed_us: tuple[int, ...]  # when each checkpoint was entered, in order (laps continue under `completed`)
    completed_us: int | None
    times_us: tuple[int, ...]
    states: tuple[State, ...]
    object_states: tuple[tuple[float, ...], ...] = ()  # at each sample, each object's free joint (7 values)
    score: dict | None = None  # ET Robocon's score at the end (`etrobocon_rules.Score.to_dict`)

    @property
    def duration_us(self) -> int:
        return self.times_us[-1]

    def state_at(self, t_us: float) -> State:
        """The state at `t_us`, between two samples: positions and wheel angles linear, the orientation
        normalised linear (the samples are 50 ms apart, where the two agree to well below a pixel)."""
        times = self.times_us
        i = bisect_right(times, t_us) - 1
        if i < 0:
            return self.states[0]
        if i >= len(times) - 1:
            return self.states[-1]
        a, b = self.states[i], self.states[i + 1]
        f = (t_us - times[i]) / (times[i + 1] - times[i])
        qa, qb = a[3:7], b[3:7]
        sign = -1.0 if sum(p * q for p, q in zip(qa, qb)) < 0 else 1.0
        q = [p * (1 - f) + sign * r * f for p, r in zip(qa, qb)]
        norm = math.sqrt(sum(v * v for v in q))
        pos = [p * (1 - f) + r * f for p, r in zip(a[:3], b[:3])]
        wheels = [p * (1 - f) + r * f for p, r in zip(a[7:], b[7:])]
        return (*pos, *(v / norm for v in q), *wheels)

    def objects_at(self, t_us: float) -> tuple[float, ...]:
        """The objects' free joints at the sample at or before `t_us` (50 ms apart: an object pushed along
        moves a few millimetres between two)."""
        if not self.object_states:
            return ()
        return self.object_states[max(bisect_right(self.times_us, t_us) - 1, 0)]

    def passed_at(self, t_us: float) -> int:
        """Checkpoints entered by `t_us`."""
        return bisect_right(self.passed_us, t_us)


def write_replay(path: Path, replay: Replay) -> None:
    """Written beside and renamed into place: a reader sees a whole file or none."""
    # asdict would copy every sample
    doc = dataclasses.asdict(dataclasses.replace(replay, times_us=(), states=(), object_states=()))
    doc.update(version=REPLAY_VERSION, times_us=replay.times_us, states=replay.states,  # floats exact, as repr
               object_states=replay.object_states)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(doc, separators=(",", ":")))
    tmp.replace(path)


def read_replay(run_dir: Path) -> Replay:
    """The replay of the last test run in `run_dir` (ReplayError, one line, if there is none or it is
    damaged)."""
    path = Path(run_dir) / REPLAY_FILE
    if not path.is_file():
        why = "is not a folder" if not Path(run_dir).is_dir() else f"has no {REPLAY_FILE} (no test ran there yet)"
        raise ReplayError(f"{run_dir} {why}")
    try:
        doc = json.loads(path.read_text())
        if doc.get("version") != REPLAY_VERSION:
            raise ReplayError(f"{path}: version {doc.get('version')!r}, this hako reads {REPLAY_VERSION}")
        robot = doc["robot"]
        look = RobotLook(str(robot["name"]), str(robot["hub"]), Body(**_fields(robot["body"])),
                         tuple(robot["sensors"]))
        states = tuple(tuple(float(v) for v in s) for s in doc["states"])
        times = tuple(int(t) for t in doc["times_us"])
        objects = tuple(tuple(float(v) for v in s) for s in doc.get("object_states", ()))
        if (not times or len(times) != len(states) or any(len(s) != STATE_SIZE for s in states)
                or (objects and len(objects) != len(times))):
            raise ReplayError(f"{path}: its samples are damaged")
        score = doc.get("score")
        return Replay(str(doc["course"]), look, str(doc["objective"]), int(doc["checkpoints"]), str(doc["event"]),
                      int(doc["event_us"]), tuple(int(t) for t in doc["passed_us"]),
                      None if doc["completed_us"] is None else int(doc["completed_us"]), times, states, objects,
                      None if score is None else dict(score))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError, KeyError, TypeError, ValueError) as e:
        if isinstance(e, ReplayError):
            raise
        raise ReplayError(f"{path}: not a replay this hako can read ({type(e).__name__}: {e})") from None


def _fields(table: dict[str, Any]) -> dict[str, Any]:
    """A dataclass's fields as JSON gave them back: its tuples came back as lists."""
    return {k: (tuple(v) if isinstance(v, list) else v) for k, v in table.items()}
