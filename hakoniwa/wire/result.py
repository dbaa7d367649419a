"""What one test on the bench produced: the one result type from the physics side, which writes it into
`unity_mmap.bin` (`hakoniwa.physics.slots.Slots.report`), through the controller, which reads it back
(`testctl.runner`), to the journal and every report, under one set of field names."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from hakoniwa.wire.etrobocon_rules import Score
from hakoniwa.wire.protocol import BenchCause, CrashKind, Event, Objective, SyncMode

# What ends a test under ET Robocon's score: each of them is a scored run (5.18: a run that ends without the
# finish keeps the points it made: a robot off the course can no longer run, and the referee ends its turn so);
# only a crash says nothing.
SCORED_EVENTS = (Event.FINISH, Event.TIME_OVER, Event.HIT_WALL, Event.COMPLETED, Event.COURSE_OUT)


@dataclass(frozen=True)
class TestResult:
    """One test: the event the physics process reported and, for GOAL, the goal time.

    `goal_time_us` is 0 for every event but GOAL; `completed_time_us` is when the program's completion notice
    (ET Robocon's `ETRoboc_notifyCompletedToSimulator()`) came, 0 if it never did. The bench's `objective`
    says what the test is scored by: under `Objective.COMPLETED` it succeeds on COMPLETED and its
    `lap_time_s`, the time every score, quantile and lap bound reads, is the completion's time. `wall_s` is how
    long the test took in wall-clock time, which is informative only: in the lockstep the event and goal time never
    depend on it. For a CRASH, `crash_kind` says whose fault it may have been and `crash_detail` the Athrill's exit
    status (negative: the signal that killed it); `program_output` holds the last lines a program that crashed
    printed (its own error, such as a Python traceback's end), which would otherwise stay in a run folder's
    athrill.log.
    A bench fault's `bench_cause` says what spoiled the test; its `crash_detail` is then the exit status of
    the process that ended (the physics process's, for `PHYSICS_KILLED` and a `FILE_DAMAGED` that killed it).
    Under `Objective.ETROBOCON` every test that ends without a crash succeeds with its `score` (ET Robocon's
    result points and their parts); `lap_time_s` is then the LAP gate's time, and `cost` minus the score.
    A test that ends COURSE_OUT says when the robot left the course (`out_time_us`) and where its axle centre
    was then (`out_xy_mm`); both are 0 for every other event.
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
    objective: Objective = Objective.LAP
    bench_cause: BenchCause = BenchCause.NONE
    score: Score | None = None
    out_time_us: int = 0
    out_xy_mm: tuple[int, int] = (0, 0)

    @property
    def success_event(self) -> Event:
        """The event that makes the test a success under its objective (under ET Robocon's score, the best
        of those that do: the finish)."""
        return {Objective.COMPLETED: Event.COMPLETED, Objective.ETROBOCON: Event.FINISH}.get(self.objective,
                                                                                           Event.GOAL)

    @property
    def success(self) -> bool:
        if self.objective == Objective.ETROBOCON:
            return self.event in SCORED_EVENTS and self.score is not None
        return self.event == self.success_event

    @property
    def cost(self) -> float | None:
        """What a campaign minimises for this test when it succeeded: its lap time, or minus its score."""
        if not self.success:
            return None
        return -self.score.total if self.score is not None else self.lap_time_s

    @property
    def bench_fault(self) -> bool:
        """A crash the bench caused: it says nothing about the parameters and is never scored."""
        return self.event == Event.CRASH and self.crash_kind == CrashKind.BENCH

    @property
    def lap_time_s(self) -> float | None:
        """The scored time of a successful test: the lap, or (objective completed) when the program ended."""
        if not self.success:
            return None
        if self.score is not None:
            return self.score.lap_time_s
        return (self.completed_time_us if self.objective == Objective.COMPLETED else self.goal_time_us) / 1e6

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
        """The fields a person or a script reads (`hako trial --json`, the journal)."""
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
        if self.objective != Objective.LAP:
            d["objective"] = self.objective.name.lower()
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
                   Objective[d.get("objective", "lap").upper()], BenchCause[d.get("bench_cause", "none").upper()],
                   None if d.get("score") is None else Score.from_dict(d["score"]),
                   0 if out is None else round(float(out["time_s"]) * 1e6),
                   (0, 0) if out is None else (round(float(out["x_m"]) * 1000), round(float(out["y_m"]) * 1000)))
