"""What one test on the bench produced: the one result type from the physics side, which builds it once and
sends it once (`encode`, into the run directory's `RESULT_FILE` before it raises the event), through the
controller, which decodes it once (`testctl.runner`), to the journal and every report, under one set of field
names. The encoding follows the fields, so a new field travels without an edit of its own."""

from __future__ import annotations

import enum
import json
import types
import typing
from dataclasses import dataclass, field, fields
from typing import Any

from hakoniwa.wire.etrobocon_rules import Score
from hakoniwa.wire.objective import DEFAULT, Objective, objective_named
from hakoniwa.wire.protocol import BenchCause, CrashKind, Event, SyncMode


@dataclass(frozen=True)
class TestResult:
    """One test: the event the physics process reported and, for GOAL, the goal time.

    `goal_time_us` is 0 for every event but GOAL; `completed_time_us` is when the program's completion notice
    (ET Robocon's `ETRoboc_notifyCompletedToSimulator()`) came, 0 if it never did. The bench's `objective`
    judges the test (`success`, `cost`, `lap_time_s`: the time every score, quantile and lap bound reads): under
    `completed` it succeeds on COMPLETED and its time is the completion's. `wall_s` is how
    long the test took in wall-clock time, which is informative only: in the lockstep the event and goal time never
    depend on it. For a CRASH, `crash_kind` says whose fault it may have been and `crash_detail` the Athrill's exit
    status (negative: the signal that killed it); `program_output` holds the last lines a program that crashed
    printed (its own error, such as a Python traceback's end), which would otherwise stay in a run folder's
    athrill.log.
    A bench fault's `bench_cause` says what spoiled the test; its `crash_detail` is then the exit status of
    the process that ended (the physics process's, for `PHYSICS_KILLED` and a `FILE_DAMAGED` that killed it).
    Under `etrobocon` every test that ends without a crash succeeds with its `score` (ET Robocon's
    result points and their parts); `lap_time_s` is then the LAP gate's time, and `cost` minus the score.
    A test that ends COURSE_OUT says when the robot left the course (`out_time_us`) and where its axle centre
    was then (`out_xy_mm`); both are 0 for every other event.
    `trajectory` is the path the robot drove, as the run directory's trajectory.csv holds it: a campaign draws a
    set from the test that measured it instead of running the test again. The journal leaves it out (it is the
    size of all the rest many times over), so a resumed campaign's earlier sets have none; no result compares
    by it.
    """

    __test__ = False  # not a pytest class

    event: Event
    goal_time_us: int
    wall_s: float
    checkpoints: int = 0
    distance_mm: int = 0
    max_time_diff_us: int = 0
    sync: SyncMode = SyncMode.LOCKSTEP
    crash_kind: CrashKind = CrashKind.NONE
    crash_detail: int = 0
    program_output: str = ""
    completed_time_us: int = 0
    objective: Objective = field(default_factory=lambda: objective_named(DEFAULT))
    bench_cause: BenchCause = BenchCause.NONE
    score: Score | None = None
    out_time_us: int = 0
    out_xy_mm: tuple[int, int] = (0, 0)
    trajectory: str = field(default="", compare=False, repr=False)

    @classmethod
    def spoiled(cls, cause: BenchCause, detail: int, wall_s: float) -> TestResult:
        """A test the bench spoiled where the physics process could report nothing (it died, or time stood
        still): `detail` is its exit status."""
        return cls(Event.CRASH, 0, wall_s, crash_kind=CrashKind.BENCH, crash_detail=detail, bench_cause=cause)

    def encode(self) -> str:
        """Every field by its type, as the physics process sends the result (`decode` reads it)."""
        return json.dumps({f.name: _plain(getattr(self, f.name)) for f in fields(self)})

    @classmethod
    def decode(cls, text: str) -> TestResult:
        """The result `encode` wrote (ValueError, KeyError or TypeError if it is not one)."""
        d = json.loads(text)
        hints = typing.get_type_hints(cls)
        return cls(**{f.name: _typed(hints[f.name], d[f.name]) for f in fields(cls)})

    @property
    def success_event(self) -> Event:
        """The event that makes the test a success under its objective (where several do, the best: under ET
        Robocon's score, the finish)."""
        return self.objective.success_event

    @property
    def success(self) -> bool:
        return self.objective.success(self)

    @property
    def cost(self) -> float | None:
        """What a campaign minimises for this test when it succeeded: its lap time, or minus its score."""
        return self.objective.cost(self)

    @property
    def bench_fault(self) -> bool:
        """A crash the bench caused: it says nothing about the parameters and is never scored."""
        return self.event == Event.CRASH and self.crash_kind == CrashKind.BENCH

    @property
    def lap_time_s(self) -> float | None:
        """The scored time of a successful test: the lap, or (objective completed) when the program ended."""
        return self.objective.lap_time_s(self)

    @property
    def distance_m(self) -> float:
        return self.distance_mm / 1000

    def crash_reason(self) -> str | None:
        """The crash in words, naming the signal that killed the program if one did."""
        if self.event != Event.CRASH:
            return None
        from hakoniwa.wire.processes import describe_exit

        what = self.crash_kind.name.lower()
        if self.bench_fault and self.bench_cause != BenchCause.NONE:
            what += f" ({self.bench_cause.words})"
        if self.crash_kind in (CrashKind.PROGRAM, CrashKind.BENCH) and self.crash_detail:
            physics = self.bench_cause in (BenchCause.PHYSICS_KILLED, BenchCause.FILE_DAMAGED)
            return f"{what}: {'the physics process' if physics else 'athrill'} {describe_exit(self.crash_detail)}"
        return what

    def to_dict(self) -> dict:
        """The fields a person or a script reads (`hako try --json`, the journal)."""
        d: dict[str, Any] = {
            "event": self.event.name, "lap_time_s": self.lap_time_s, "goal_time_us": self.goal_time_us,
            "sync": self.sync.name.lower(), "checkpoints": self.checkpoints, "distance_m": self.distance_m,
            "max_time_diff_us": self.max_time_diff_us}
        if self.event == Event.CRASH:
            d.update(crash=self.crash_kind.name.lower(), crash_detail=self.crash_detail,
                     crash_reason=self.crash_reason())
            if self.bench_cause != BenchCause.NONE:
                d["bench_cause"] = self.bench_cause.name.lower()
        if self.program_output:
            d["program_output"] = self.program_output
        if self.completed_time_us:
            d["completed_time_us"] = self.completed_time_us
        if self.objective != objective_named(DEFAULT):
            d["objective"] = self.objective.key
        if self.score is not None:
            d["score"] = self.score.to_dict()
        if self.event == Event.COURSE_OUT:
            d["course_out"] = {"time_s": self.out_time_us / 1e6, "x_m": self.out_xy_mm[0] / 1000,
                               "y_m": self.out_xy_mm[1] / 1000}
        return d

    @classmethod
    def from_dict(cls, d: dict, wall_s: float) -> TestResult:
        """The inverse of `to_dict` (which leaves the wall time out); a field an older journal lacks takes
        the value every test had then."""
        crash, out = d.get("crash"), d.get("course_out")
        return cls(Event[d["event"]], int(d["goal_time_us"]), wall_s, int(d.get("checkpoints", 0)),
                   round(float(d.get("distance_m", 0.0)) * 1000), int(d.get("max_time_diff_us", 0)),
                   SyncMode[d.get("sync", "lockstep").upper()],
                   CrashKind[crash.upper()] if crash else CrashKind.NONE, int(d.get("crash_detail", 0)),
                   str(d.get("program_output", "")), int(d.get("completed_time_us", 0)),
                   objective_named(d.get("objective", DEFAULT)), BenchCause[d.get("bench_cause", "none").upper()],
                   None if d.get("score") is None else Score.from_dict(d["score"]),
                   0 if out is None else round(float(out["time_s"]) * 1e6),
                   (0, 0) if out is None else (round(float(out["x_m"]) * 1000), round(float(out["y_m"]) * 1000)))


def _plain(value: Any) -> Any:
    """A field's value as JSON holds it: an enum by name, an objective by its key, a score by its fields."""
    if isinstance(value, enum.Enum):
        return value.name
    if isinstance(value, Objective):
        return value.key
    if isinstance(value, Score):
        return value.to_dict()
    return list(value) if isinstance(value, tuple) else value


def _typed(hint: Any, value: Any) -> Any:
    """The inverse of `_plain` for a field of type `hint`."""
    if typing.get_origin(hint) in (typing.Union, types.UnionType):
        if value is None:
            return None
        hint = next(a for a in typing.get_args(hint) if a is not type(None))
    if hint is Objective:
        return objective_named(value)
    if hint is Score:
        return Score.from_dict(value)
    if isinstance(hint, type) and issubclass(hint, enum.Enum):
        return hint[value]
    if typing.get_origin(hint) is tuple:
        return tuple(value)
    if not isinstance(value, hint if hint is not float else (int, float)):
        raise TypeError(f"{value!r} is not a {hint.__name__}")
    return value
