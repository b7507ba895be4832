"""One closing line for the test command's pytest runs: ``total: N passed, N failed, N skipped`` from their JUnit XML
reports (``python scripts/test_summary.py REPORT.xml ...``). Failed counts failures and errors; skipped counts skips
and expected failures. Exits 1 when no report holds a test."""

from __future__ import annotations

import sys
import xml.etree.ElementTree as ET


def counts(paths: list[str]) -> dict[str, int]:
    """Passed, failed and skipped tests over the reports at ``paths`` (a missing or unreadable report is an error)."""
    total = {"tests": 0, "failed": 0, "skipped": 0}
    for path in paths:
        for suite in ET.parse(path).getroot().iter("testsuite"):
            total["tests"] += int(suite.get("tests", 0))
            total["failed"] += int(suite.get("failures", 0)) + int(suite.get("errors", 0))
            total["skipped"] += int(suite.get("skipped", 0))
    total["passed"] = total["tests"] - total["failed"] - total["skipped"]
    return total


def main(paths: list[str]) -> int:
    total = counts(paths)
    print(f"total: {total['passed']} passed, {total['failed']} failed, {total['skipped']} skipped")
    return 0 if total["tests"] else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
