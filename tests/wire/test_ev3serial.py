"""The mock's serial input file reader against what the physics process writes (Scenario.serial_lines)."""

from hypothesis import given
from hypothesis import strategies as st

from athrill_sim.ev3serial import Input, parse_serial_input
from hakoniwa.physics.scenario import SERIAL_PORTS, Scenario, SerialInput

inputs = st.lists(st.builds(SerialInput, st.integers(0, 10**12), st.sampled_from(SERIAL_PORTS), st.text(min_size=1)))


@given(inputs)
def test_every_port_reads_back_what_the_scenario_wrote_in_order(serial):
    text = Scenario(serial=tuple(serial)).serial_lines()
    for port in SERIAL_PORTS:
        assert parse_serial_input(text, port) == [Input(s.at_us, s.text.encode()) for s in serial if s.port == port]
