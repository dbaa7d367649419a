"""ET Robocon's numbers, in one place, each with the section of the regulation it comes from.

Source: ET ソフトウェアデザインロボットコンテスト 2026 ベーシッククラス・アプライドクラス 競技規約 1.0.0 版
(2026-04-30), public in AnimatoAJS-RCT/EtRobocon2026, docs/regulation/ETRC2026_rules_basic_applied_1.0.0.md.
Where the regulation is unclear the number is marked so, and docs/DESIGN-NOTES.md ("ET Robocon's score")
says how the bench reads it.
"""

from __future__ import annotations

from dataclasses import dataclass

# 5.6.1 数式 5-2: run points = max(MP - t, 0), MP = 35, t the run time in seconds.
RUN_POINTS_MAX = 35.0
# 5.6.1: the run time counts in 0.1 s units (unclear whether cut or rounded: the bench cuts, as a stopwatch
# showing tenths does).
RUN_TIME_UNIT_S = 0.1
# 5.4.7 and 5.6.1: the maximum measuring time; a run time that never comes (no LAP gate) counts as this.
MAX_TIME_S = 120.0
# 5.14: finish = part of the robot inside the garage, completely stopped (5.11: every motor stopped or
# holding) for this long.
FINISH_STOP_S = 3.0


@dataclass(frozen=True)
class TaskPoints:
    """One class's task points (課題ポイント), the items the bench can judge."""

    checkpoint: float  # each checkpoint reached, once, before the LAP gate (5.12)
    lap_gate: float  # the LAP gate reached (5.13)
    finish: float  # the finish in the garage (5.14)
    sumo: float  # the sumo bottle pushed out of the ring (5.15)


# 6.4 表 6-2 (basic class) and 7.4 表 7-3 (applied class). The table's text is scrambled by its conversion from
# PDF; read in row order it gives checkpoints 4 (basic) / 2 (applied) points each, LAP gate 3, finish 3,
# bottle push-out 5 (then delivery 1, colour match 5, rally laps 5 / 10 / 15, which the bench does not judge).
# Both tables "may be revised at the CS (championship) event".
TASK_POINTS = {"basic": TaskPoints(checkpoint=4, lap_gate=3, finish=3, sumo=5),
               "applied": TaskPoints(checkpoint=2, lap_gate=3, finish=3, sumo=5)}
CLASSES = tuple(TASK_POINTS)


def run_points(lap_time_us: int | None) -> float:
    """5.6.1: max(35 - t, 0), t in whole tenths of a second, the maximum time when there is no LAP."""
    if lap_time_us is None:
        t = MAX_TIME_S
    else:
        tenths = lap_time_us // round(RUN_TIME_UNIT_S * 1_000_000)
        t = min(tenths / 10, MAX_TIME_S)
    return round(max(RUN_POINTS_MAX - t, 0.0), 1)


def result_points(run: float, task: float) -> float:
    """5.6 数式 5-1: max(run + task, 0)."""
    return max(run + task, 0.0)


@dataclass(frozen=True)
class Score:
    """One run's result points and what they are made of: the result JSON's and the journal's `score`."""

    total: float
    run_points: float
    task_points: float
    lap_time_s: float | None  # when the LAP gate was reached (the run time), None if it never was
    checkpoints: int  # checkpoints reached before the LAP gate
    lap_gate: bool
    finish: bool  # stopped in the garage for FINISH_STOP_S
    sumo: bool | None  # the sumo bottle pushed out of the ring; None on a course without one
    competition_class: str

    @classmethod
    def of(cls, competition_class: str, lap_time_us: int | None, checkpoints: int, finish: bool,
           sumo: bool | None) -> Score:
        """The score of a run that reached `checkpoints` checkpoints, the LAP gate at `lap_time_us` (None: not
        at all), finished in the garage or not and pushed the bottle out or not."""
        points = TASK_POINTS[competition_class]
        lap = lap_time_us is not None
        task = (points.checkpoint * checkpoints + points.lap_gate * lap + points.finish * finish
                + points.sumo * bool(sumo))
        run = run_points(lap_time_us)
        return cls(round(result_points(run, task), 1), run, task, None if lap_time_us is None else lap_time_us / 1e6,
                   checkpoints, lap, finish, sumo, competition_class)

    def to_dict(self) -> dict:
        return {"total": self.total, "run_points": self.run_points, "task_points": self.task_points,
                "lap_time_s": self.lap_time_s, "checkpoints": self.checkpoints, "lap_gate": self.lap_gate,
                "finish": self.finish, "sumo": self.sumo, "class": self.competition_class}

    @classmethod
    def from_dict(cls, d: dict) -> Score:
        return cls(float(d["total"]), float(d["run_points"]), float(d["task_points"]),
                   None if d["lap_time_s"] is None else float(d["lap_time_s"]), int(d["checkpoints"]),
                   bool(d["lap_gate"]), bool(d["finish"]), None if d["sumo"] is None else bool(d["sumo"]),
                   str(d["class"]))

    def describe(self) -> str:
        """One line: the total and its parts."""
        lap = "no LAP" if self.lap_time_s is None else f"LAP {self.lap_time_s:.2f} s"
        parts = [f"run {self.run_points:g} ({lap})", f"{self.checkpoints} checkpoints"]
        parts += [name for name, done in (("LAP gate", self.lap_gate), ("finish", self.finish),
                                          ("sumo", self.sumo)) if done]
        return f"score {self.total:g}: " + ", ".join(parts) + f" ({self.competition_class} class)"
