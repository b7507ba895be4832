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


# What a reader is pointed to: the notebooks (text and code), the README files and the docs pages.
READ = ("notebooks/", "docs/", "README.md", "benchmarks/README.md")
# A commit id: 7 to 40 hex digits with a letter and a digit, standing alone (history is git's, not the text's).
COMMIT = re.compile(r"(?<![\w/.-])(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}(?![\w-])")
# A repository path in backticks or a Markdown link: a folder/file (with a slash), not a URL.
PATH_REF = re.compile(r"`((?:\.\./)*[\w.-]+/[\w./-]*)`|\]\(((?:\.\./)*[\w.-]+/[\w./-]*|[\w.-]+\.md)\)")
# folders a run writes (git-ignored): named as where the outputs go, not as files that exist
OUTPUTS = ("build/", "runs/")


def _read_texts() -> dict[str, str]:
    """The texts a reader reads: each notebook's cells (markdown and code) and the Markdown files of :data:`READ`."""
    import json

    out = {}
    for path in _tracked():
        rel = path.relative_to(ROOT).as_posix()
        if not rel.startswith(READ) or path.suffix not in (".md", ".ipynb"):
            continue
        text = _text(path)
        if text is None:
            continue
        if path.suffix == ".ipynb":
            text = "\n".join("".join(c["source"]) for c in json.loads(text)["cells"])
        out[rel] = text
    return out


def _missing_paths(rel: str, text: str) -> list[str]:
    """The repository paths named in ``text`` (of the file ``rel``) that exist nowhere a reader would look: the root,
    the file's folder, ``lib/`` or the package."""
    missing = []
    for m in PATH_REF.finditer(text):
        name = (m.group(1) or m.group(2)).rstrip(".")
        if name.startswith(OUTPUTS):
            continue
        places = [ROOT, (ROOT / rel).parent, ROOT / "lib", ROOT / "lib" / "trusscodesign"]
        if not any((base / name).exists() for base in places):
            missing.append(f"{rel}: {name}")
    return missing


def test_no_commit_ids_in_what_a_reader_reads() -> None:
    hits = [f"{rel}: {m.group(0)}" for rel, text in _read_texts().items() for m in COMMIT.finditer(text)]
    assert not hits, "commit ids (say what the run showed, not which commit made it):\n" + "\n".join(hits)


def test_named_repository_paths_exist() -> None:
    missing = [hit for rel, text in _read_texts().items() for hit in _missing_paths(rel, text)]
    assert not missing, "paths named that do not exist:\n" + "\n".join(missing)


def test_the_reference_patterns() -> None:
    """The checks above can fail: a commit id and a missing path are found; hashes of parameters and paths that exist
    are not flagged."""
    assert [m.group(0) for m in COMMIT.finditer("the run of commit 5566afb quoted")] == ["5566afb"]
    assert [m.group(0) for m in COMMIT.finditer("ids 1234567 and abcdefa, dec0de12")] == ["dec0de12"]
    assert _missing_paths("README.md", "see `lib/trusscodesign/nope.py` and [x](docs/titop.md)") == ["README.md: lib/trusscodesign/nope.py"]
    assert _missing_paths("notebooks/x.ipynb", "`data/results/` and `build/smoke/x.ipynb` and [r](../docs/results.md)") == []


GLOSSARY_TERMS = ("ACS", "Ball trust region", "f^n", "G, G_r, G_r_low", "J_c", "Least-change restoration", "Lever", "LOS",
                  "NINOP", "p~, W~u", "PMA", "Preset", "Recipe", "RPE", "SADM", "TITOP", "Z_c")


def test_the_glossary_defines_every_term_the_pages_use() -> None:
    """Each term a newcomer meets in the README, the notebooks and the results page has its entry (a bold head)."""
    text = (ROOT / "docs" / "glossary.md").read_text()
    heads = re.findall(r"^\*\*(.+?)\*\*", text, flags=re.M)
    missing = [t for t in GLOSSARY_TERMS if not any(h == t or h.startswith(t + " ") or h.startswith(t + ",") for h in heads)]
    assert not missing, f"terms without a glossary entry: {missing}"


def test_the_paper_map_has_every_figure_and_table() -> None:
    """docs/paper.md has a row for each of the paper's 16 figures and 7 tables, each naming a notebook section and
    a verdict."""
    rows = [line.split(" | ") for line in (ROOT / "docs" / "paper.md").read_text().splitlines()
            if line.startswith(("| Fig. ", "| Table "))]
    names = [r[0].lstrip("| ") for r in rows]
    assert names == [f"Fig. {k}" for k in range(1, 17)] + [f"Table {k}" for k in range(1, 8)]
    assert all(len(r) == 5 and re.search(r"\d\d", r[2]) and r[4].strip(" |") for r in rows)
