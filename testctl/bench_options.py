"""The physics process's command line: what a bench needs to know besides its run directory, the world
(`hakoniwa.physics`) and the robot program (`athrill_sim`) alike.

This is the one declaration of the bench options and their defaults. `hakoniwa-physics` parses them,
`hako try` and `hako run` offer the same options to the user, and the controller turns a `BenchOptions`
back into the command line that starts a bench (`physics_command`), so the three can never disagree. It
lives with the controller, above both peers its options configure.
"""

from __future__ import annotations

import dataclasses
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import click

from athrill_sim.programs.athrill2 import REPEATABLE_DIR, AthrillTransport, RealSync
from athrill_sim.programs.kinds.kind import Emulator
from athrill_sim.programs.program import ProgramError
from hakoniwa.conventions import SECONDS, option_group
from hakoniwa.wire.objective import BUILT_IN, DEFAULT, Objective, ObjectiveError, objective_named
from hakoniwa.wire.vdev_udp import UDP_DEVICE_CONFIG

if TYPE_CHECKING:
    from athrill_sim.programs.program import Program
    from hakoniwa.physics.course import Course
    from hakoniwa.physics.robots import Robot
    from hakoniwa.physics.scenario import Scenario

DEFAULT_COURSE = "oval"
DEFAULT_APP = "line_trace"
PHYSICS_MODULE = "testctl.physics_process"  # `python -m` this: the physics process of a bench


@dataclass(frozen=True)
class BenchOptions:
    """The course and the program a bench serves, and how long it waits for them."""

    course: str = DEFAULT_COURSE
    app: str = DEFAULT_APP
    athrill2: str | None = None
    emulator: Emulator | None = None  # None: by the kind of --app (a C program natively, a v850 image in athrill2)
    sync: RealSync | None = None  # None: repeatable for the real emulator (hakoniwa over UDP)
    transport: AthrillTransport | None = None  # None: mmap, or udp with a device config
    device_config: str | None = None  # a user's athrill2 device config for UDP (ET Robocon's device_config.txt)
    athrill_timeout_s: float = 10.0
    time_limit_s: float | None = None  # None: the course's own limit
    robot: str | None = None  # None: the default robot, with the course's wheel ports
    scenario: str | None = None  # a scenario TOML applied to every test
    bindings: str | None = None  # JSON: how parameters other than `offset` reach the program (from the space)
    objective: str | None = DEFAULT  # what ends and scores a test: an `Objective`, by its key

    def __post_init__(self) -> None:
        """The command line and a journal give these by name: they become their enums here, once."""
        for field, kind in (("emulator", Emulator), ("sync", RealSync), ("transport", AthrillTransport)):
            value = getattr(self, field)
            if value is not None and not isinstance(value, kind):
                if value not in set(kind):
                    raise ProgramError(f"--{field} {value}: not one of {', '.join(kind)}")
                object.__setattr__(self, field, kind(value))
        try:
            self.scored_by  # noqa: B018 (an objective that cannot be found is one line here, before any test)
        except ObjectiveError as e:
            raise ProgramError(f"--objective: {e}") from None

    @property
    def scored_by(self) -> Objective:
        """The bench's objective; a journal from before objectives were recorded names none: the lap."""
        return objective_named(self.objective or DEFAULT)

    def physics_command(self, run_dir: Path, controller: list[str], extra: tuple[str, ...] = ()) -> list[str]:
        """`extra`: options of the physics process alone, which are not the bench's (`--view`)."""
        cmd = [sys.executable, "-m", PHYSICS_MODULE, "--run-dir", str(run_dir), *extra]
        for option in _OPTIONS:
            value = getattr(self, option.field)
            if value is not None:
                cmd += [option.flag, value if isinstance(value, str) else repr(value)]
        return [*cmd, "--", *controller]

    def program(self) -> Program:
        """The robot program this bench serves (ProgramError, one line, if it cannot run)."""
        from athrill_sim.programs.resolve import resolve_program

        return resolve_program(self.app, athrill2=self.athrill2, emulator=self.emulator, sync=self.sync,
                               transport=self.transport, device_config=self.device_config, bindings=self.bindings)

    def time_limit_us(self, course_limit_us: int) -> int:
        """The simulated time a test may take (`hakoniwa.physics.bench.time_limit_us`)."""
        from hakoniwa.physics.bench import time_limit_us

        return time_limit_us(course_limit_us, self.time_limit_s)


class ObjectiveKey(click.ParamType):
    """A built-in objective's name or a plug-in's module:attribute, found before any bench starts."""

    name = "objective"

    def get_metavar(self, param: click.Parameter, ctx: click.Context) -> str:
        return f"[{'|'.join(BUILT_IN)}|MODULE:ATTRIBUTE]"

    def convert(self, value: str, param: click.Parameter | None, ctx: click.Context | None) -> str:
        try:
            objective_named(value)
        except ObjectiveError as e:
            self.fail(str(e), param, ctx)
        return value

    def shell_complete(self, ctx: click.Context, param: click.Parameter, incomplete: str) -> list:
        from click.shell_completion import CompletionItem

        return [CompletionItem(k) for k in BUILT_IN if k.startswith(incomplete)]


@dataclass(frozen=True)
class _Option:
    field: str
    flag: str
    help: str
    type: click.ParamType | None = None
    hidden: bool = False

    def declare(self) -> Callable:
        default = next(f.default for f in dataclasses.fields(BenchOptions) if f.name == self.field)
        return click.option(self.flag, self.field, type=self.type, default=default,
                            show_default=default is not None, help=self.help, hidden=self.hidden)


_OPTIONS = [
    _Option("course", "--course", "Built-in course name or course folder."),
    _Option("app", "--app", "Robot program: a built-in name (line_trace, line_trace_c), a Python "
            "module:function, an EV3RT C or C++ program (app.c, app.cpp or its workspace folder), or a v850 ELF "
            "image (run in the real athrill2)."),
    _Option("emulator", "--emulator", "What an EV3RT C or C++ program runs on: native (compiled for this machine), "
            "athrill2 (built into a v850 image with the EV3RT SDK and run in the real TOPPERS emulator) or "
            "raspike-art (a RasPike-ART workspace folder built by RasPike-ART's make into the robot's own asp, run "
            "under qemu-user against the SPIKE hub the bench plays; --robot hackspi) [default: native; a v850 image "
            "always runs in athrill2].", click.Choice([e.value for e in Emulator])),
    _Option("athrill2", "--athrill2", "The TOPPERS athrill2 emulator for the real emulator [default: on PATH, "
            f"else {REPEATABLE_DIR}/athrill2]."),
    _Option("sync", "--sync", "How the real emulator keeps time with physics: repeatable (athrill2 built with "
            "scripts/build_athrill2.sh --repeatable waits at each sync point: the same result on every run) or "
            "hakoniwa (TOPPERS' unmodified protocol: results depend on the machine's load) [default: "
            "repeatable; hakoniwa over UDP].", click.Choice([s.value for s in RealSync])),
    _Option("transport", "--transport", "How the real emulator's packets travel: mmap (the two mapped files) or "
            "udp (athrill2's vdev_udp device, as in ET Robocon's simulator; --sync hakoniwa only) [default: mmap; "
            "udp with --device-config].", click.Choice([t.value for t in AthrillTransport])),
    _Option("device_config", "--device-config", f"athrill2's device config for UDP, e.g. ET Robocon's "
            f"{UDP_DEVICE_CONFIG}: athrill2 runs with it unchanged and the physics side uses its addresses and "
            "ports (127.x.x.x only) [default: the bench writes one with ports of its own]."),
    _Option("athrill_timeout_s", "--athrill-timeout",
            "Wall seconds a silent Athrill is waited for before the test counts as a crash.", SECONDS),
    _Option("robot", "--robot", "The robot's wiring: a built-in name (default, hackev, hackspi, basic) or a robot "
            "TOML file [default: the default robot, wheels as the course says]."),
    _Option("scenario", "--scenario", "A scenario TOML: touch and button presses, serial input, the robot "
            "placed by hand and a hand in front of the ultrasonic sensor at simulated times, the same in every "
            "test."),
    _Option("time_limit_s", "--time-limit", "Simulated seconds before a test ends as TIME_OVER; a campaign "
            "scores a failed test as this many seconds [default: the course's time_limit_s].", SECONDS),
    _Option("bindings", "--bindings", "How the parameters of kinds other than offset (define, symbol, file, "
            "source) reach the program, as JSON; the controller makes it from the --space file.", hidden=True),
    _Option("objective", "--objective", "What ends and scores a test: lap (GOAL at the course's last "
            "checkpoint, scored by the lap time), completed (the program's ETRoboc_notifyCompletedToSimulator(), "
            "as an ET Robocon competition program ends its run, scored by when it came; the goal line does not "
            "end the test, and a test it never comes to fails), etrobocon (ET Robocon's result points, raised) "
            "or an objective of your own as module:attribute (docs/OBJECTIVES.md).", ObjectiveKey()),
]

bench_options = option_group([o.declare() for o in _OPTIONS])
"""The bench options for a click command; the command receives them as BenchOptions' field names, and
`BenchOptions(**those)` is the bench."""

BENCH_FIELDS = tuple(o.field for o in _OPTIONS)


def pop_bench(kwargs: dict) -> BenchOptions:
    """Take the bench options out of a command's keyword arguments."""
    return BenchOptions(**{name: kwargs.pop(name) for name in BENCH_FIELDS})


def load_bench(options: BenchOptions) -> tuple[Course, Robot, Scenario]:
    """The world the bench serves (`hakoniwa.physics.bench.load_world`): its errors are one line each, also
    for a robot the program cannot drive (asp talks to a SPIKE hub)."""
    from hakoniwa.physics.bench import load_world
    from hakoniwa.physics.robots import RobotError

    course, robot, scenario = load_world(options.course, options.robot, options.scenario, options.time_limit_s)
    if options.emulator == Emulator.RASPIKE_ART and not robot.spike:
        raise RobotError(f"--emulator {Emulator.RASPIKE_ART}: asp drives a SPIKE hub; give a SPIKE robot (--robot "
                         "hackspi, basic, or a robot file with a SPIKE hub)")
    return course, robot, scenario
