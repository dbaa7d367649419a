"""The mapped files as the physics side reads and writes them: sensor snapshots and the test report into
RX (`unity_mmap.bin`), motor commands and reset requests out of TX (`athrill_mmap.bin`).

Only this module knows which slot holds what for the physics side (the sync loops read Athrill's clock and
answers through its named accessors); the layout itself is `hakoniwa.wire.protocol`'s. Writes that a reader
waits on come last (the unity time after a snapshot, the event after a report), so whoever sees them sees
everything that belongs to them.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from hakoniwa.physics.course import CourseInfo
from hakoniwa.physics.sensors import Sensors
from hakoniwa.wire.protocol import (
    ETROBOC_EXT,
    HEADER_SIZE,
    MOTOR_PORTS,
    Event,
    Header,
    MappedFile,
    Rx,
    Tx,
    goal_time_words,
    open_athrill,
    open_unity,
)
from hakoniwa.wire.waiting import futex_wake

ACTUATORS_END = Tx.SPIKE_DIRECTION + 4 * MOTOR_PORTS  # TX body bytes a test starts with cleared
COMMAND_WORDS = (Tx.MOTOR_POWER, (ACTUATORS_END - Tx.MOTOR_POWER) // 4)  # TX words of powers .. directions
_RESET_WORD, _GYRO_WORD, _DIRECTION_WORD = ((offset - Tx.MOTOR_POWER) // 4 for offset in
                                            (Tx.MOTOR_RESET_ANGLE, Tx.GYRO_RESET, Tx.SPIKE_DIRECTION))
OUR_EXT = (Rx.TEST_SEQ, Rx.PHYSICS_PID + 4)  # RX bytes of our extension the physics side writes
# EV3RT reads the battery from RX (uart_dri_get_data_battery); Unity leaves those slots 0, which no program
# expects of a running brick, so the physics side writes a charged EV3 pack idling there.
BATTERY_MV = 8000  # six AA cells, charged
BATTERY_MA = 150  # the brick idling, motors still


@dataclass(frozen=True)
class Commands:
    """What Athrill asked of the robot since the last look: motor powers by port, and the resets."""

    powers: tuple[int, ...]
    directions: tuple[int, ...]  # each port's pup_motor_setup direction (0, clockwise, unless a SPIKE runtime set it)
    reset_angle_ports: list[int]
    reset_gyro: bool
    completed: bool  # ETRoboc_notifyCompletedToSimulator(): the program says its run is over


class Slots:
    def __init__(self, run_dir: Path) -> None:
        self.unity: MappedFile = open_unity(run_dir, create=True)
        self.athrill: MappedFile = open_athrill(run_dir, create=True)
        self.unity.write_u32(Rx.PHYSICS_PID, os.getpid())
        self._unity_time_address = self.unity.address(Header.UNITY_TIME)
        self.answer_address = self.athrill.address(HEADER_SIZE + Tx.ANSWER_SEQ)  # a lockstep Athrill rings here
        self.stopped_address = self.athrill.address(HEADER_SIZE + Tx.STOPPED_AT)  # a patched Athrill rings here

    def repair(self) -> list[str]:
        """Repair the files if anyone damaged them; what was wrong with each (a path names the file)."""
        return [problem for f in (self.unity, self.athrill) if (problem := f.repair()) is not None]

    def noise_request(self) -> tuple[int, float]:
        """The (seed, scale) the controller wrote for this test."""
        return self.unity.read_u32(Rx.NOISE_SEED), self.unity.read_f32(Rx.NOISE_SCALE)

    def begin(self, info: CourseInfo) -> int:
        """Clear what a new test starts without, and write the course's information; returns Athrill's answer
        counter before the test."""
        a = self.athrill
        a.clear(0, ACTUATORS_END)
        a.clear(*ETROBOC_EXT)
        a.athrill_time_us = 0  # a real Athrill's clock starts at 0; a stale one would let physics run ahead
        a.write("q", Tx.STOPPED_AT, 0)  # where a patched Athrill stopped: likewise
        self.unity.clear(*OUR_EXT)
        self.unity.write_u32(Rx.PHYSICS_PID, os.getpid())
        self.unity.write_i32(Rx.BATTERY_CURRENT, BATTERY_MA)
        self.unity.write_i32(Rx.BATTERY_VOLTAGE, BATTERY_MV)
        self.unity.write_u32(Rx.COURSE_CARD_NUMBER, info.card_number)
        self.unity.write_u32(Rx.COURSE_BLOCK_NUMBER, info.block_number)
        for i, position in enumerate(info.block_positions):
            self.unity.write("B", Rx.COURSE_BLOCK_POS + i, position)
        return a.read_u32(Tx.ANSWER_SEQ)

    def announce(self, seq: int) -> None:
        self.unity.write_u32(Rx.TEST_SEQ, seq)  # last: a waiting Athrill starts when it sees its number

    def publish(self, s: Sensors | None, unity_time_us: int, snapshot_end_us: int) -> None:
        """The sensor snapshot (none for a program that does not read it from the file), then the instant it
        holds until and the unity time (last: a reader that sees the new times sees the values they belong
        to), and a wake-up for an Athrill sleeping on the latter."""
        u = self.unity
        if s is not None:
            self._write_readings(s)
        u.snapshot_end_us = snapshot_end_us
        u.unity_time_us = unity_time_us
        futex_wake(self._unity_time_address)

    def _write_readings(self, s: Sensors) -> None:
        u = self.unity
        # BUTTONS, COLOR0_AMBIENT .. COLOR0_RGB and GYRO_ANGLE, GYRO_RATE are one run of words: one write.
        u.write_i32s(Rx.BUTTONS, [s.buttons, s.ambient, int(s.color), s.reflect, *s.rgb, s.gyro_angle_deg,
                                  s.gyro_rate_dps])
        u.write_i32(Rx.ULTRASONIC_MM, s.ultrasonic_mm)
        u.write("q", Rx.BUTTONS_UNTIL, s.buttons_until_us)
        u.write_i32(Rx.TOUCH0, s.touch[0])
        u.write_i32(Rx.TOUCH1, s.touch[1])
        for port, angle in s.motor_angles_deg.items():
            u.write_i32(Rx.MOTOR_ANGLE + 4 * port, angle)
        if s.imu is not None:  # only a SPIKE robot's: an EV3 robot's files stay as they were
            for offset, value in zip((Rx.SPIKE_IMU_ACCEL_X, Rx.SPIKE_IMU_ACCEL_Y, Rx.SPIKE_IMU_ACCEL_Z,
                                      Rx.SPIKE_IMU_ANGVEL_X, Rx.SPIKE_IMU_ANGVEL_Y, Rx.SPIKE_IMU_ANGVEL_Z),
                                     (*s.imu.acceleration_mm_s2, *s.imu.angular_velocity_dps)):
                u.write_f32(offset, value)
        if s.spike is not None:  # what the hub answers: the SDK's HSV slots, then ours after them, in one run
            u.write_i32s(Rx.SPIKE_HSV_H, [*s.spike.hsv, *s.spike.ambient_hsv, *s.spike.color, *s.spike.powers])

    def take_commands(self) -> Commands:
        """Motor powers, and the reset requests, which are cleared once taken (EV3RT never clears them)."""
        a = self.athrill
        words = a.read_i32s(*COMMAND_WORDS)  # one read of the lot: this runs at every answer
        resets = [port for port in range(MOTOR_PORTS) if words[_RESET_WORD + port]]
        for port in resets:
            a.write_i32(Tx.MOTOR_RESET_ANGLE + 4 * port, 0)
        gyro = bool(words[_GYRO_WORD])
        if gyro:
            a.write_i32(Tx.GYRO_RESET, 0)
        return Commands(words[:MOTOR_PORTS], words[_DIRECTION_WORD:_DIRECTION_WORD + MOTOR_PORTS], resets, gyro,
                        a.read_i32(Tx.COMPLETED) == 1)

    def relay_commands(self, powers: tuple[int, ...], directions: tuple[int, ...]) -> None:
        """What a program asked of a hub the physics side plays (RasPike-ART's asp never writes TX), written
        where Athrill's commands are taken from, so that the loop takes both alike."""
        a = self.athrill
        a.write_i32s(Tx.MOTOR_POWER, list(powers[:MOTOR_PORTS]))
        a.write_i32s(Tx.SPIKE_DIRECTION, list(directions[:MOTOR_PORTS]))

    def publish_event(self, event: Event, goal_time_us: int) -> None:
        hi, lo = goal_time_words(goal_time_us)
        self.unity.write_u32(Rx.GOAL_TIME_HI, hi)
        self.unity.write_u32(Rx.GOAL_TIME_LO, lo)
        self.unity.write_i32(Rx.EVENT, int(event))  # last: the controller reads everything else after it

    # -- what Athrill wrote: its clock and answers for the sync loops, the controller's flags -----------
    def athrill_time_us(self) -> int:
        return self.athrill.athrill_time_us

    def stopped_at_us(self) -> int:
        """The clock at which the patched Athrill last stopped to wait for physics (repeatable)."""
        return int(self.athrill.read("q", Tx.STOPPED_AT))

    def stopped_word(self) -> int:
        """The word at `stopped_address` (its low half): what a waiter on the patched Athrill compares."""
        return self.stopped_at_us() & 0xFFFFFFFF

    def answer_seq(self) -> int:
        """Athrill's answer counter (lockstep): bumped last whenever it has published its outputs."""
        return self.athrill.read_u32(Tx.ANSWER_SEQ)

    def athrill_pid(self) -> int:
        """The pid the mock wrote once it runs (the real Athrill writes none)."""
        return self.athrill.read_u32(Tx.ATHRILL_PID)

    def next_wake_us(self) -> int:
        """When the program's task wakes next (lockstep): the instant physics steps to."""
        return int(self.athrill.read("q", Tx.NEXT_WAKE))

    def command_words(self) -> tuple[int, ...]:
        """The TX words of powers, brakes and resets as they stand: a change is a new command."""
        return self.athrill.read_i32s(*COMMAND_WORDS)

    def start_flag(self) -> int:
        return self.athrill.read_i32(Tx.START)

    def end_requested(self) -> bool:
        return self.athrill.read_i32(Tx.END) == 1
