"""The corpus of real EV3RT programs the bench must run unmodified: EV3RT's own samples
(../shared/third_party/ev3rt/ev3rt-athrill-v850e2m/sdk/workspace). A new program needs only its folder there
and a line here: what it must do in one test (`Expect`)."""

from __future__ import annotations

from dataclasses import dataclass

from athrill_sim.programs.third_party import EV3RT_SDK
from tests.helpers.paths import SHARED, needs_shared

EV3RT = SHARED / "third_party" / "ev3rt" / "ev3rt-athrill-v850e2m"
WORKSPACE = EV3RT / "sdk" / "workspace"
EV3API = EV3RT / "sdk" / "common" / "ev3api"
NEEDS_SHARED = needs_shared("EV3RT's SDK", EV3RT, EV3RT_SDK)


@dataclass(frozen=True)
class Expect:
    """What one test of the program must show besides not crashing."""

    min_distance_m: float = 0.0
    log: tuple[str, ...] = ()  # lines athrill.log must contain
    lcd: bool = False  # it draws on the LCD
    serial_out: str | None = None  # the serial port it writes to (serial-<port>.log is not empty)
    scenario: str | None = None  # a scenario TOML for the test
    time_limit_s: float = 3.0


CORPUS = {
    "athrillsample": Expect(min_distance_m=0.1),
    "automotive_bench": Expect(log=("athrill time:",)),
    "base_practice_1": Expect(min_distance_m=0.5, time_limit_s=20.0),
    "bt_remote": Expect(scenario='[[serial]]\nat_s = 0.5\ntext = "1"\n'),
    "bt_sample": Expect(serial_out="bt", scenario='[[serial]]\nat_s = 0.5\ntext = "hello\\n"\n'),
    "bttest": Expect(serial_out="bt", scenario='[[serial]]\nat_s = 0.2\ntext = "abc"\n'),
    "fstest": Expect(log=("fopen: suceeded", "read_write: suceeded", "memfile_load: suceeded")),
    "sensor_test": Expect(lcd=True),
    "taskbench": Expect(log=("athrill time:",)),
    "toppers_conference": Expect(min_distance_m=0.1),
}
SKIPPED = {"base_practice_1_mruby": "needs the mruby tools, which are not here"}
