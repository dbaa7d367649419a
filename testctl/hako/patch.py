"""`hako patch apply RUN_DIR`: a campaign's tuned values set in the program's own files, from wherever the user
stands, and checked (testctl.campaign.patch)."""

from __future__ import annotations

from pathlib import Path

import click

from hakoniwa.conventions import HELP, OneLineErrorsGroup


@click.group(cls=OneLineErrorsGroup, context_settings=HELP)
def patch() -> None:
    """A campaign's best.patch: the tuned values in the program's own files (apply)."""


@patch.command(context_settings=HELP)
@click.argument("run_dir", type=click.Path(file_okay=False, exists=True, path_type=Path))
@click.option("--check", is_flag=True, help="Only say whether it applies, and what it would set.")
def apply(run_dir: Path, check: bool) -> None:
    """Set the values of RUN_DIR's best.patch in the program's files (all of them or none), wherever you run
    it, inside a git repository or not, and check that each file then holds them. A file edited since the
    campaign is refused in one line naming it; one that already holds the values is said so."""
    from testctl.campaign.patch import apply_patch

    for line in apply_patch(run_dir, check):
        click.echo(line)
