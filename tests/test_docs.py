"""Everything the repository points to is in the repository.

(a) No tracked text file cites the design notes or the paper's source that lived outside the repository (a user who
clones the project does not have them). (b) Every ``docs/<name>.md`` page cited by the package, the notebooks, the
tests, the scripts or the README exists.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# Spelled in pieces so that this file does not match itself.
OUTSIDE = ("shared" + "/docs", "shared" + "/paper", ".." + "/shared")
CITING = ("lib/", "notebooks/", "tests/", "scripts/", "README.md")
# A docs page cited from the root (docs/ then the page) or from a folder below it (../docs/ then the page); not a URL or another
# project's docs/ folder (anything glued to the front, such as a path segment, is excluded).
DOC_REF = re.compile(r"(?<![\w/.-])(?:\.\./)*docs/([\w-]+\.md)")


def _tracked() -> list[Path]:
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout")
    return [ROOT / p for p in out.decode().split("\0") if p]


def _text(path: Path) -> str | None:
    """The file's text, or None for a binary (a NUL byte in its first 8000 bytes, as git decides) or missing file."""
    try:
        data = path.read_bytes()
    except OSError:  # deleted in the working tree but still tracked
        return None
    if b"\0" in data[:8000]:
        return None
    return data.decode("utf-8", errors="replace")


def test_no_reference_outside_the_repository() -> None:
    hits = []
    for path in _tracked():
        text = _text(path)
        if text is None:
            continue
        for lineno, line in enumerate(text.splitlines(), 1):
            if any(s in line for s in OUTSIDE):
                hits.append(f"{path.relative_to(ROOT)}:{lineno}: {line.strip()[:120]}")
    assert not hits, "references to files outside the repository:\n" + "\n".join(hits)


def test_cited_docs_pages_exist() -> None:
    missing = []
    for path in _tracked():
        rel = path.relative_to(ROOT).as_posix()
        if not (rel.startswith(CITING[:-1]) or rel == CITING[-1]):
            continue
        text = _text(path)
        if text is None:
            continue
        for lineno, line in enumerate(text.splitlines(), 1):
            for name in DOC_REF.findall(line):
                if not (ROOT / "docs" / name).is_file():
                    missing.append(f"{rel}:{lineno}: docs/{name}")
    assert not missing, "cited docs pages that do not exist:\n" + "\n".join(missing)


def test_the_docs_pattern() -> None:
    """The citation pattern takes the package's and the notebooks' forms, and leaves URLs and other folders alone."""
    assert DOC_REF.findall("Mathematics: ``docs/titop.md`` section b") == ["titop.md"]
    assert DOC_REF.findall("[`docs/titop.md`](../docs/titop.md)") == ["titop.md", "titop.md"]
    assert DOC_REF.findall("see https://example.org/docs/x.md and other/docs/y.md") == []
