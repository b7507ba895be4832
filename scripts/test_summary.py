"""One closing line for the test command's pytest runs, from their JUnit XML reports and exit statuses:
``total: N passed, N failed, N skipped``.

Usage: ``python scripts/test_summary.py NAME=REPORT.xml=STATUS ...`` (as scripts/test.sh calls it). Failed counts
failures and errors; skipped counts skips and expected failures. A run whose report is missing or unreadable, or
whose exit status is not 0 while its report shows no failure (a crash, an interrupt, a usage error), is named on a
line of its own and counted as one failure, so that the last line is never green for a run that did not pass.
"""

from __future__ import annotations

import sys
import xml.etree.ElementTree as ET


def counts(path: str) -> dict[str, int]:
    """Tests, failed and skipped of one report (raises OSError or ET.ParseError if it cannot be read)."""
    total = {"tests": 0, "failed": 0, "skipped": 0}
    for suite in ET.parse(path).getroot().iter("testsuite"):
        total["tests"] += int(suite.get("tests", 0))
        total["failed"] += int(suite.get("failures", 0)) + int(suite.get("errors", 0))
        total["skipped"] += int(suite.get("skipped", 0))
    return total


def summary(runs: list[str]) -> tuple[list[str], dict[str, int]]:
    """The lines about broken runs, and the totals, for ``NAME=REPORT=STATUS`` items."""
    lines, total = [], {"tests": 0, "failed": 0, "skipped": 0}
    for run in runs:
        name, path, status = run.rsplit("=", 2)
        try:
            one = counts(path)
        except (OSError, ET.ParseError) as err:
            lines.append(f"{name}: no readable report {path} ({type(err).__name__}), exit status {status}: counted as 1 failure")
            one = {"tests": 1, "failed": 1, "skipped": 0}
        else:
            if status != "0" and one["failed"] == 0:
                lines.append(f"{name}: exit status {status} although its report shows no failure: counted as 1 failure")
                one = {"tests": one["tests"] + 1, "failed": 1, "skipped": one["skipped"]}
        total = {k: total[k] + one[k] for k in total}
    return lines, total


def main(runs: list[str]) -> int:
    lines, total = summary(runs)
    for line in lines:
        print(line)
    passed = total["tests"] - total["failed"] - total["skipped"]
    print(f"total: {passed} passed, {total['failed']} failed, {total['skipped']} skipped")
    return 0 if total["tests"] and not total["failed"] else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
