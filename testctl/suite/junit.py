"""The test run as JUnit XML: the one report format GitHub Actions, GitLab and Jenkins all read.

One `<testcase>` per case (a case is what a person states and fixes, its noise draws are its evidence);
a failing case carries one `<failure>` whose message names the first unmet expectation and its measured
value, and lists every unmet one in its text. Written with the standard library's ElementTree.
"""

from __future__ import annotations

import datetime as dt
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path

from testctl.suite.run import CaseRun


def junit_tree(suite_name: str, runs: Sequence[CaseRun]) -> ET.ElementTree:
    failures = sum(not r.passed for r in runs)
    wall = f"{sum(r.wall_s for r in runs):.3f}"
    counts = {"tests": str(len(runs)), "failures": str(failures), "errors": "0", "skipped": "0", "time": wall}
    root = ET.Element("testsuites", {"name": "hako test", **counts})
    suite = ET.SubElement(root, "testsuite", {"name": suite_name, **counts,
                                              "timestamp": dt.datetime.now().replace(microsecond=0).isoformat()})
    for run in runs:
        case = ET.SubElement(suite, "testcase", classname=suite_name, name=run.case.name, time=f"{run.wall_s:.3f}")
        unmet = [c for c in run.checks if not c.passed]
        if unmet:
            failure = ET.SubElement(case, "failure", message=unmet[0].message(), type="expectation")
            failure.text = "\n".join(c.message() for c in unmet)
        out = ET.SubElement(case, "system-out")
        out.text = "\n".join([*(f"{'ok  ' if c.passed else 'FAIL'} {c.message()}" for c in run.checks),
                              run.stats.describe()])
    ET.indent(root)
    return ET.ElementTree(root)


def write_junit(path: Path, suite_name: str, runs: Sequence[CaseRun]) -> None:
    junit_tree(suite_name, runs).write(path, encoding="utf-8", xml_declaration=True)
