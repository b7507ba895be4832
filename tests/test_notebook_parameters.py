"""Every notebook checks its parameters before any work: a bad value stops it in the cell right after the parameters, with
a message naming the parameter, its unit and the allowed range (papermill batch runs pass them as -p or YAML)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

CASES = [  # (notebook, bad parameters, what the message must say)
    ("01_titop_beam", {"n_omega": 1}, r"n_omega must be an integer in [2, inf)"),
    ("01_titop_beam", {"omega_max": 0.5}, r"omega_max must be a number in (1, inf) rad/s, got 0.5"),
    ("02_mechanisms_2d", {"alpha_l": 90.0}, r"alpha_l must be a number in (0, 3.14159) rad, got 90.0"),
    ("03_cube_vs_nastran", {"fe_nastran_elements": 0}, r"fe_nastran_elements must be an integer in [1, inf)"),
    ("03_cube_vs_nastran", {"other_h": -0.02}, r"other_h must be a number in (0, inf) m"),
    ("04_t_truss_spacecraft", {"theta": 90.0}, r"theta must be a number in [-3.14159, 3.14159] rad, got 90.0"),
    ("04b_large_trusses", {"plate_size": [3]}, r"plate_size must be [cubes along x, cubes along y], got [3]"),
    ("04b_large_trusses", {"dense_sizes": [1, 30]}, r"dense_sizes above 20 cubes take hours"),
    ("04b_large_trusses", {"longeron_h": 3.0}, r"longeron_h must be a number in (0, 0.1] m, got 3.0"),
    ("05_lft_reduction", {"h_figure": 2.139}, r"h_figure must be a section side in metres in (0, 0.1]"),
    ("05_lft_reduction", {"omega_band": 1000.0}, r"omega_band must be a number in (0, 500] rad/s"),
    ("06_robust_synthesis", {"levers": ["u_max", "u_maximum"]}, r"levers[1] must be one of ['u_max'"),
    ("06_robust_synthesis", {"lever_values": {"u_max": [15.0, -5.0]}}, r"lever u_max at -5.0 (effort bound $u_{max}$ [N]): LoopSettings.u_max must be"),
    ("06_robust_synthesis", {"show_spillover": "no"}, r"show_spillover must be True or False, got str 'no'"),
    ("06_robust_synthesis", {"h_values": [0.02139, 3.0]}, r"h_values[1] must be a section side in metres"),
    ("06b_calibration_tolerance", {"calibration_cases": [{"u_max": 0.1, "t_delta": -1.0}]},
     r"lever t_delta at -1.0 (RPE window $t_\Delta$ [s]): LoopSettings.t_delta must be"),
    ("06b_calibration_tolerance", {"tolerance_presets": ["paper"]}, r"tolerance_presets[0] must be one of ['stated', 'paper_calibrated']"),
    ("06b_calibration_tolerance", {"truss_design_shifts": [0.0, 0.02]}, r"truss_design_shifts must not hold 0"),
    ("07_pso_codesign", {"pso_rule": "MATLAB"}, r"pso_rule must be one of ['documented', 'matlab'], got 'MATLAB'"),
    ("07_pso_codesign", {"run_baseline": "False"}, r"run_baseline must be True or False, got str 'False'"),
    ("07_pso_codesign", {"baseline_particles": 0}, r"baseline_particles must be an integer in [2, inf), got 0"),
    ("07_pso_codesign", {"preset": "calibrated"}, r"unknown preset 'calibrated'"),
    ("07_pso_codesign", {"truss_tolerance": 2}, r"truss_tolerance must be a relative section-side error in [0, 0.2)"),
    ("07_pso_codesign", {"h_resolution": 0.01}, r"h_resolution must be a number in [1e-07, 0.001] m, got 0.01"),
    ("07_pso_codesign", {"check_angles": 1}, r"check_angles must be an integer in [2, inf), got 1"),
    ("07_pso_codesign", {"preset": "stated"}, r"preset = 'stated' with run_baseline = True would store two runs"),
    ("07_pso_codesign", {"trust_region": "circle"}, r"trust_region"),
    ("07_pso_codesign", {"pso_tolerance": -0.1}, r"pso_tolerance must be a number in [0, 1]"),
    ("06b_calibration_tolerance", {"reference_dir": "nowhere"}, r"reference_dir = 'nowhere': no stored results"),
    ("06c_pma_authority", {"readings": [{"u_convention": "acceleration"}]}, r"u_convention must be one of ['force', 'proof-mass acceleration']"),
    ("06c_pma_authority", {"n_omega": 2}, r"n_omega must be an integer in [10, inf), got 2"),
    ("07b_multiparameter_pareto", {"population": 0}, r"population must be an integer in [1, inf), got 0"),
    ("07b_multiparameter_pareto", {"groups": {"a": ["battens"], "b": ["battens", "diagonals"]}}, r"repeated: ['battens']"),
    ("07b_multiparameter_pareto", {"resolution": 0.01}, r"resolution must be a number in [1e-07, 0.001] m, got 0.01"),
    ("07b_multiparameter_pareto", {"check_jc_range": [0.9, 0.5]}, r"check_jc_range[1] must be a number in [0.9, 2]"),
    ("07b_multiparameter_pareto", {"prior_dir": "nowhere"}, r"no file"),
    ("08_worst_case_mu", {"certify_groups": ["RPE"]}, r"certify_groups entries must be one of ['rpe', 'effort'], got 'RPE'"),
    ("08_worst_case_mu", {"samples_per_period": 4}, r"samples_per_period must be an integer in [8, inf), got 4"),
    ("08_worst_case_mu", {"h_shifts": [2.0]}, r"h_shifts[0] must be a number in [-0.5, 0.5] (relative), got 2.0"),
    ("08_worst_case_mu", {"table_presets": ["calibrated"]}, r"unknown preset 'calibrated'"),
]


@pytest.mark.parametrize("notebook, bad, message", CASES, ids=[f"{n.split('_')[0]}-{next(iter(b))}" for n, b, _ in CASES])
def test_a_bad_parameter_stops_the_notebook_before_any_work(tmp_path: Path, notebook: str, bad: dict, message: str) -> None:
    import papermill as pm

    out = tmp_path / f"{notebook}.ipynb"
    parameters = {"results_dir": str(tmp_path / "results"), "figures_dir": str(tmp_path / "figures"), **bad}
    with pytest.raises(pm.PapermillExecutionError) as err:
        pm.execute_notebook(ROOT / "notebooks" / f"{notebook}.ipynb", out, parameters=parameters, cwd=ROOT / "notebooks",
                            progress_bar=False, log_output=False)
    assert message in str(err.value), str(err.value)[-2000:]
    # the failed cell is the one right after the parameters (papermill's injected cell follows them): no model was built
    cells = [c for c in json.loads(out.read_text())["cells"] if c["cell_type"] == "code"]
    tags = [c["metadata"].get("tags", []) for c in cells]
    first = tags.index(["injected-parameters"]) + 1
    assert any(o.get("output_type") == "error" for o in cells[first]["outputs"]), f"cell {first} did not fail"
    assert all(c["execution_count"] is None for c in cells[first + 1:]), "a cell after the checks ran"
