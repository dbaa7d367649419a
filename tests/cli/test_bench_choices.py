"""The bench's choices given by name (a command line, a journal's bench) become their enums once, where the
`BenchOptions` is made, and go back out under the same names: to the physics process's command line and to the
journal."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest

from athrill_sim.programs.athrill2 import AthrillTransport, RealSync
from athrill_sim.programs.kinds.kind import Emulator
from athrill_sim.programs.program import ProgramError
from testctl.bench_options import BenchOptions
from testctl.campaign.benches import bench_info


def test_names_become_their_enums_and_go_back_out_as_the_same_names(tmp_path: Path) -> None:
    bench = BenchOptions(app="line_trace_c", emulator="athrill2", sync="hakoniwa", transport="udp")
    assert bench.emulator is Emulator.ATHRILL2
    assert bench.sync is RealSync.HAKONIWA and bench.sync.mode.name == "HAKONIWA"
    assert bench.transport is AthrillTransport.UDP
    recorded = json.loads(json.dumps(bench_info(bench)))
    assert (recorded["emulator"], recorded["sync"], recorded["transport"]) == ("athrill2", "hakoniwa", "udp")
    assert BenchOptions(**{**dataclasses.asdict(bench), **recorded}) == bench  # a resume reads the journal back
    command = bench.physics_command(tmp_path, [])
    assert [command[command.index(flag) + 1] for flag in ("--emulator", "--sync", "--transport")] == [
        "athrill2", "hakoniwa", "udp"]


@pytest.mark.parametrize(("field", "name"), [("emulator", "qemu"), ("sync", "lockstep"), ("transport", "tcp")])
def test_a_name_no_choice_has_is_refused_in_one_line(field: str, name: str) -> None:
    with pytest.raises(ProgramError) as e:
        BenchOptions(**{field: name})
    assert str(e.value).startswith(f"--{field} {name}: not one of ") and "\n" not in str(e.value)
