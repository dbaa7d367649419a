"""Fig. 8 draws each searched parameter in its own colour, on its own axis (their ranges differ: gains in
0..5, a motor power in 10..30), each with a legend."""

from __future__ import annotations

from matplotlib.colors import to_rgba

from hakoniwa.wire.protocol import Event, Rx
from testctl.campaign.loop import Campaign, CampaignConfig
from testctl.campaign.report import fig8
from testctl.search.space import Parameter, ParameterSpace
from tests.helpers.campaign_doubles import ScriptedBench, result

SPACE = ParameterSpace((Parameter("Kp", Rx.KP, 0, 5), Parameter("Ki", Rx.KI, 0, 5), Parameter("Kd", Rx.KD, 0, 5),
                        Parameter("motor_power", Rx.MOTOR_POWER, 10, 30)))


def test_each_parameter_has_its_own_colour_axis_and_legend(tmp_path):
    config = CampaignConfig(space=SPACE, init_points=3, trials=2, repeats=1, optimizer="random")
    summary = Campaign(config, tmp_path, ScriptedBench([result(Event.GOAL, 30.0 + i) for i in range(5)])).run()
    fig = fig8(summary)
    *params, lap = fig.axes
    assert [ax.get_ylabel() for ax in params] == list(SPACE.names) and lap.get_ylabel() == "lap time [s]"
    colours = [to_rgba(ax.get_lines()[0].get_color()) for ax in params]
    assert len(set(colours)) == len(colours)
    assert colours[:3] == [to_rgba(c) for c in ("red", "blue", "green")]  # the paper's Kp, Ki, Kd
    for ax, name in zip(params, SPACE.names):
        assert name in [t.get_text() for t in ax.get_legend().get_texts()]
        low, high = ax.get_ylim()
        values = [s.x[SPACE.names.index(name)] for s in summary.sets]
        assert low <= min(values) and max(values) <= high and high - low < 4 * (max(values) - min(values) + 1)
