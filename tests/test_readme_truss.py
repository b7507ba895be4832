"""The README's "Your own truss" block runs as printed, and what it prints is right: the beam count, the mass summed
against its closed form, and the first frequencies against OpenSeesPy frame elements of the same truss (within the T-truss's
bar, 5e-3)."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import numpy as np
from trusscodesign.model import opensees_fe

ROOT = Path(__file__).parents[1]


def _block() -> str:
    readme = (ROOT / "README.md").read_text()
    start, end = "<!-- truss:start -->\n```python\n", "```\n<!-- truss:end -->"
    assert readme.count(start) == 1 and readme.count(end) == 1, "the README's truss block markers are missing"
    return readme[readme.index(start) + len(start):readme.index(end)]


def test_the_readmes_own_truss_runs_and_prints_the_right_numbers() -> None:
    ns: dict = {}
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(_block(), "README.md truss block", "exec"), ns)  # noqa: S102 - the README's own code
    printed = out.getvalue()
    boom, sections = ns["boom"], ns["sections"]
    assert len(boom.members) == 12 * 13 and printed.startswith(f"156 beams, {boom.mass(sections):.1f} kg")
    per_member = boom.sections(sections)
    # 48 m of longerons at 3 cm; 48 m of battens and 60 diagonals of sqrt(2) m at 2.139 cm; 2700 kg/m^3
    mass = 2700.0 * (0.03**2 * 48 + 0.02139**2 * (48 + 60 * np.sqrt(2)))
    assert abs(mass - boom.mass(sections)) < 1e-12 * mass
    shown = [float(x) for x in re.findall(r"(\d+\.\d{3})", printed.split(":", 1)[1])]
    fe = opensees_fe.frame_frequencies(boom.nodes, boom.pairs(), per_member, ["N1", "N2", "N3", "N4"], 10, "consistent", 4)
    assert len(shown) == 4 and np.max(np.abs(np.array(shown) * 2 * np.pi / fe - 1)) < 5e-3
