"""Running a test file for a person and a CI system: the progress bar, the table, the report files, and the
exit status that a pipeline acts on (0 all cases passed, 1 a case failed, 2 the input or the run broke)."""

from __future__ import annotations

import json
import sys
from collections.abc import Sequence
from pathlib import Path

import click

from hakoniwa.wire.exits import EXIT_CASES_FAILED, EXIT_RUN_BROKEN
from hakoniwa.wire.protocol import LayoutError
from hakoniwa.wire.result import TestResult
from testctl.cluster_address import ClusterAddress
from testctl.executor import BenchFault, TestSpec
from testctl.interrupts import on_stop_say, stopped_by
from testctl.runner import PhysicsGone
from testctl.suite.cases import Case
from testctl.suite.junit import write_junit
from testctl.suite.report import format_table, keep_case_files, results_dict
from testctl.suite.run import bench_executor, rerun_worst, run_cases
from testctl.time_left import Countdown


class RunBroken(click.ClickException):
    """Exit 2: the input is bad or the run itself broke, so nothing was shown of the program; exit 1 is kept
    for a case that fails."""

    exit_code = EXIT_RUN_BROKEN


def run_suite(test_file: Path, cases: Sequence[Case], out_dir: Path, *, benches: int, scheduler: ClusterAddress | None,
              junit_file: Path | None, json_file: Path | None) -> None:
    """Run and judge every case, print the table, write the files, and exit 1 if a case failed."""
    from testctl.cluster import ClusterError  # Dask: not for `hako --help`

    on_stop_say("nothing is judged")
    total = sum(len(c.seeds) for c in cases)
    countdown = Countdown(total)
    try:
        with click.progressbar(length=total, label=f"hako test {test_file}", item_show_func=lambda s: s,
                               show_eta=False, file=sys.stderr) as bar:
            def finished(spec: TestSpec, result: TestResult) -> None:
                left = countdown.finished()
                bar.update(1, ", ".join(filter(None, [f"{cases[spec.set_index].name}: {result.event.name}", left])))

            runs = run_cases(cases, lambda bench: bench_executor(bench, out_dir / "run", benches, scheduler),
                             finished)
        files = {r.case.name: keep_case_files(out_dir, r, rerun_worst) for r in runs}
        click.echo(format_table(runs))
        written = [out_dir]
        if json_file is not None:
            json_file.write_text(json.dumps(results_dict(test_file, runs, files), indent=2) + "\n")
            written.append(json_file)
        if junit_file is not None:
            write_junit(junit_file, test_file.stem, runs)
            written.append(junit_file)
    except (BenchFault, PhysicsGone, ClusterError, LayoutError) as e:
        raise RunBroken(f"the test run broke, nothing is judged: {e}") from None
    except OSError as e:
        raise RunBroken(f"cannot write {e.filename or 'the results'}: {e.strerror or e}") from None
    except KeyboardInterrupt as e:  # Ctrl-C, or SIGTERM (a CI runner cancelling the job)
        stopped_by(e, "nothing is judged")
    click.echo("wrote " + ", ".join(str(f) for f in written))
    if not all(r.passed for r in runs):
        sys.exit(EXIT_CASES_FAILED)
