"""The benches a campaign runs on, settled once before it starts: how many (`campaign_benches`, from the cores
this process may use), which bench a resumed campaign runs on (`campaign_bench`), and what its journal records
of that bench (`RECORDED_BENCH`, `bench_info`) and of its files (`recorded_files`, which refuses a resume whose
files changed). `hako run` only calls these; `hako test` shares the cores and the paths made absolute."""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, overload

import click

from testctl.bench_options import BenchOptions

if TYPE_CHECKING:
    from hakoniwa.wire.protocol import SyncMode


def bench_sync(bench: BenchOptions) -> SyncMode:
    """How the bench's program keeps time with physics, from what --app names (not built yet: a tuned program
    builds only with its parameters' values).

    Raises:
        ProgramError: --app names nothing that can run.
    """
    from athrill_sim.programs.resolve import program_recipe

    return program_recipe(bench.app, athrill2=bench.athrill2, emulator=bench.emulator, sync=bench.sync,
                          transport=bench.transport, device_config=bench.device_config).sync


def repeatable_bench(bench: BenchOptions) -> bool:
    """Whether the bench runs the real emulator in the repeatable mode, where a set's tests without noise
    all give the same result."""
    from hakoniwa.wire.protocol import SyncMode

    return bench_sync(bench) == SyncMode.REPEATABLE


def campaign_benches(bench: BenchOptions, wave: int) -> int:
    """`hako run`'s default bench count: one per usable core, and on two cores or more at least `wave`, the
    tests of a set that run at once (3 for 3 of 5), where results do not depend on timing. With one set
    proposed at a time, a set's three tests on two benches ran two, then one beside an idle core: a third
    bench runs them at once, 95 s against 100 s for the README's campaign on two cores (docs/BENCHMARKS.md).
    On one core a second bench lost 27 %. TOPPERS' unsynchronised protocol keeps one bench per core, as
    its results depend on the CPU each emulator gets; and one bench where a device config fixes athrill2's
    UDP ports, which benches cannot share.

    Raises:
        ProgramError: --app names nothing that can run.
    """
    from athrill_sim.programs.athrill2 import udp_link
    from hakoniwa.wire.protocol import SyncMode

    link = udp_link(bench.transport, bench.device_config)
    if link is not None and link.fixed:
        return 1
    cores = usable_cores()
    return max(cores, wave) if cores >= 2 and bench_sync(bench) != SyncMode.HAKONIWA else cores


def usable_cores() -> int:
    """The cores this process may run on: `taskset` and a container's cpuset say fewer than os.cpu_count().
    `hako test` keeps half of them: a second bench did not pay for its start on the example suite (issue 23);
    `hako run` takes them all (`campaign_benches`)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


# What the journal records of the bench: what decides results (not where athrill2 lives).
RECORDED_BENCH = ("course", "app", "emulator", "sync", "transport", "device_config", "time_limit_s", "robot",
                  "scenario", "objective")


def bench_info(bench: BenchOptions) -> dict:
    return {field: getattr(bench, field) for field in RECORDED_BENCH}


def recorded_files(stored: dict, bench: BenchOptions) -> dict:
    """The hashes of the bench's files, for the journal; a resume whose files are not the journal's is refused,
    naming them (a journal from before the hashes were recorded cannot be checked)."""
    from testctl.campaign.fingerprint import FILES_KEY, changes, fingerprint

    files = fingerprint(bench, RECORDED_BENCH)
    if FILES_KEY in stored and (changed := changes(stored[FILES_KEY], files, bench)):
        raise click.ClickException(f"--resume: the campaign's files changed since it started ({'; '.join(changed)}); "
                                   "its results so far were measured with the old ones: restore them, or start a "
                                   "new campaign with another --out")
    return files


def campaign_bench(stored: dict, given: BenchOptions, on_command_line: set[str]) -> BenchOptions:
    """The bench for a campaign: as given, with paths made absolute for workers elsewhere; a resumed campaign
    runs on the bench its journal records, and giving another on the command line (`on_command_line`: the
    fields given there) is an error."""
    given = dataclasses.replace(given, course=absolute(given.course), app=absolute(given.app),
                                robot=absolute(given.robot), scenario=absolute(given.scenario),
                                device_config=absolute(given.device_config))
    if not stored:
        return given
    differ = [f"--{field.removesuffix('_s').replace('_', '-')} {getattr(given, field)!r} (given) vs "
              f"{stored.get(field)!r} (journal)"
              for field in RECORDED_BENCH if field in on_command_line and getattr(given, field) != stored.get(field)]
    if differ:
        raise click.UsageError("--resume runs on the campaign's own bench: " + "; ".join(differ))
    recorded: dict[str, Any] = {field: stored.get(field) for field in RECORDED_BENCH}
    return dataclasses.replace(given, **recorded)


@overload
def absolute(spec: str) -> str: ...
@overload
def absolute(spec: None) -> None: ...
def absolute(spec: str | None) -> str | None:
    """A path made absolute for workers elsewhere; a built-in course or app name stays a name (a file of that
    name in the working directory does not shadow it)."""
    from athrill_sim.apps import BUILTIN, C_BUILTIN
    from hakoniwa.physics.course import builtin_course

    if spec is None or spec in BUILTIN or spec in C_BUILTIN or builtin_course(spec) is not None:
        return spec
    return str(Path(spec).resolve()) if Path(spec).exists() else spec

