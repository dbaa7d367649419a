"""The mock's serial input file reader against what the physics process writes (Scenario.serial_lines)."""

from hypothesis import given
from hypothesis import strategies as st

from athrill_sim.mock.ev3serial import Input, parse_serial_input
from hakoniwa.physics.scenario import SERIAL_PORTS, Scenario, SerialInput

# by keyword: SerialInput's first field is `where`, so positional strategies filled the wrong fields and the
# test compared almost nothing (a port of random text is on none of the ports read back)
inputs = st.lists(st.builds(SerialInput, where=st.just("scenario.toml serial"), at_us=st.integers(0, 10**12),
                            port=st.sampled_from(SERIAL_PORTS), text=st.text(min_size=1)))


@given(inputs)
def test_every_port_reads_back_what_the_scenario_wrote_in_order(serial):
    text = Scenario(serial=tuple(serial)).serial_lines()
    for port in SERIAL_PORTS:
        assert parse_serial_input(text, port) == [Input(s.at_us, s.text.encode()) for s in serial if s.port == port]
