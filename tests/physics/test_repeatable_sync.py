"""The repeatable loop against a scripted patched athrill2, without the emulator: physics takes every step up to the
one Athrill stopped in at once, applies a new command once, before the first of them, and publishes the snapshot of
that step; so the tests that need ../shared's emulator are not the only ones to hold it."""

import os

import pytest

from hakoniwa.physics import sync

TICK_US = 25_000  # the fake scheduler's streams fire every 25 ms: a stretch of steps must stop at each


class ScriptedAthrill:
    """The slots of a patched athrill2 that stops at the clocks given, its TX commands as given at each stop."""

    stopped_address = 0

    def __init__(self, stops: list[tuple[int, tuple[int, ...]]]) -> None:
        self._stops = iter(stops)
        self.at_us, self.commands = 0, (0,)

    def resume(self) -> None:
        self.at_us, self.commands = next(self._stops)

    def stopped_at_us(self) -> int:
        return self.at_us

    def stopped_word(self) -> int:
        return self.at_us & 0xFFFFFFFF

    def athrill_time_us(self) -> int:
        return self.at_us

    def command_words(self) -> tuple[int, ...]:
        return self.commands


class RecordingServer:
    """A SyncServer without MuJoCo that writes down what the loop asks of it, in order."""

    def __init__(self, athrill: ScriptedAthrill, end_us: int) -> None:
        self.slots, self.end_us = athrill, end_us
        self.now_us, self.run_dir, self.athrill_timeout_s = 0, os.getcwd(), 10.0
        self.log: list[tuple[str, int]] = []
        self.diffs: list[int] = []

    def next_tick(self) -> int:
        return (self.now_us // TICK_US + 1) * TICK_US

    def advance_to(self, target_us: int) -> bool:
        """As `Environment.advance_to`: through every tick on the way, ending at the first that has an event."""
        while self.now_us < target_us:
            self.now_us = min(self.next_tick(), target_us)
            self.log.append(("step to", self.now_us))
            if self.now_us >= self.end_us:
                return True
        return False

    def apply_actuators(self) -> None:
        self.log.append(("apply", self.now_us))

    def publish_sensors(self) -> None:
        self.log.append(("publish", self.now_us))

    def note_time_diff(self, diff_us: int) -> None:
        self.diffs.append(diff_us)

    def check_ceiling(self) -> None: ...


def test_physics_steps_at_once_to_the_step_athrill_stopped_in(monkeypatch: pytest.MonkeyPatch):
    athrill = ScriptedAthrill([(10_400, (0,)), (20_250, (30,)), (40_000, (30,)), (45_500, (-5,)), (60_000, (-5,))])
    server = RecordingServer(athrill, end_us=50_000)

    def wait_word(address, word, ready, on_idle) -> None:
        while not ready():
            athrill.resume()

    monkeypatch.setattr(sync, "wait_word", wait_word)
    proc = type("Proc", (), {"pid": os.getpid(), "poll": staticmethod(lambda: None)})()
    sync.run_repeatable(server, proc)  # type: ignore[arg-type]
    assert server.log == [
        ("apply", 0), ("step to", 10_000), ("publish", 10_000),  # the first command, before the first step
        ("apply", 10_000), ("step to", 20_000), ("publish", 20_000),  # a new one, from the step it was written in
        ("step to", 25_000), ("step to", 40_000), ("publish", 40_000),  # no new command; a tick on the way
        ("apply", 40_000), ("step to", 45_000), ("publish", 45_000),
        ("step to", 50_000)]  # the stop at 60 ms is past the end: the test ends at the tick before it
    assert server.diffs == [400, 250, 0, 500]  # how old each snapshot is when Athrill reads it
