"""The stored Nastran/SDT tables of the cube: read as stored, and every kind of damage refused with the file, the line
and the field named (a truncated row broke numpy's broadcasting, a duplicated row gave KeyError: nan, a typo blamed the
parameters, a deleted xi row skipped the damping check)."""

import shutil
from pathlib import Path

import numpy as np
import pytest
from trusscodesign.infra import paths
from trusscodesign.model import nastran

STORED = paths.PACKAGE_DATA / "nastran_cube"


def test_the_stored_tables_read_as_the_paper_gives_them():
    t = nastran.load_tables()
    assert t.parameters["xi"] == 0.001 and t.parameters["E"] == 70.0 and len(t.parameters) == 10
    assert t.omega["patran_nastran"][0] == 16.77 and t.omega["paper_sdt"].shape == (10,)
    assert t.participation["patran_nastran"].shape == (10, 6) and np.all(np.diff(t.omega["paper_sdt"]) > 0)


def _damaged(tmp_path: Path, name: str, edit) -> Path:
    folder = tmp_path / "tables"
    shutil.copytree(STORED, folder)
    lines = (folder / name).read_text().splitlines()
    (folder / name).write_text("\n".join(edit(lines)) + "\n")
    return folder


@pytest.mark.parametrize("name, edit, match", [
    ("cube_modes.csv", lambda ls: ls[:3] + [ls[3][:20]] + ls[4:], r"cube_modes\.csv, line 4: \d fields where 9 are expected.*truncated"),
    ("cube_modes.csv", lambda ls: ls[:3] + [ls[2]] + ls[3:], r"cube_modes\.csv, line 4: mode 2 of patran_nastran is given twice \(first on line 3\)"),
    ("cube_modes.csv", lambda ls: [ls[0], ls[1].replace("16.77", "61.77")] + ls[2:],
     r"cube_modes\.csv, line 3, field omega_rad_s: the frequencies of patran_nastran must increase.*17\.51 rad/s follows 61\.77"),
    ("cube_modes.csv", lambda ls: [ls[0], ls[1].replace("16.77", "x")] + ls[2:], r"line 2, field omega_rad_s: 'x' is not a number"),
    ("cube_modes.csv", lambda ls: ls[:-1], r"each model must give the same number of modes"),
    ("cube_parameters.csv", lambda ls: [ln for ln in ls if not ln.startswith("xi,")], r"cube_parameters\.csv: parameter\(s\) \['xi'\] missing"),
    ("cube_parameters.csv", lambda ls: [ln.replace("E,70,GPa", "E,70,Pa") for ln in ls], r"line 7, field unit: E must be in 'GPa', got 'Pa'"),
    ("cube_parameters.csv", lambda ls: [ln.replace("rho,2700", "rho,nan") for ln in ls], r"line 6, field value: 'nan' is not a finite number"),
    ("cube_parameters.csv", lambda ls: ["name,value,unit,description"] + ls[1:], r"line 1: the columns must be"),
])
def test_a_damaged_table_names_the_file_the_line_and_the_field(tmp_path, name, edit, match):
    with pytest.raises(ValueError, match=match):
        nastran.load_tables(_damaged(tmp_path, name, edit))
