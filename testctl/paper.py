"""The paper's experiment (section 4.1, Table 4), stated once: the line tracer's parameters and the
result the paper reports."""

from __future__ import annotations

from hakoniwa.wire.protocol import Rx

MOTOR_POWER = 15.0  # the fixed base motor power of the experiment
BEST_GAINS = (1.539, 4.267, 4.511)  # the paper's best [Kp, Ki, Kd] (a 32.39 s lap on its course)
GAIN_RANGE = (0.0, 5.0)  # each gain is searched in [0, 5]


def line_trace_params(kp: float, ki: float, kd: float, power: float = MOTOR_POWER) -> dict[int, float]:
    """The parameter area the line tracer reads, as {data offset: value} for the controller to write."""
    return {Rx.KP: kp, Rx.KI: ki, Rx.KD: kd, Rx.MOTOR_POWER: power}
