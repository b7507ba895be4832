"""A design for MATLAB and Simulink: written to a .mat file and read back equal."""

import numpy as np
import pytest
from trusscodesign.control.closedloop import LoopSettings
from trusscodesign.control.synthesis import Scenario, plant_at
from trusscodesign.model import spacecraft
from trusscodesign.study import design, export


def test_the_stored_calibrated_design_at_2139_cm_round_trips(tmp_path):
    """Notebook 06b's design at h = 2.139 cm on `paper_calibrated`: the gain, G_r (its Delta channels open) and the
    nominal closed loop come back from the file with every matrix entry and signal name equal, and the closed loop is
    stable with the gain and as the file says."""
    h, gain = design.table_design("paper_calibrated", "paper_h")
    params = spacecraft.study_parameters("paper_calibrated")
    models = design.models_at(h, params)
    settings = LoopSettings.from_parameters(params)
    path = export.save_design_mat(tmp_path / "design.mat", gain, models, settings)
    back = export.load_design_mat(path)
    assert np.array_equal(back["K_PMA"], gain) and back["h_m"] == h
    loop = plant_at(models.g_r, Scenario(), models.inertia, settings).closed_loop(gain)
    for name, ref in (("G_r", models.G_r), ("closed_loop", loop)):
        got = back[name]
        for m in "ABCD":
            assert np.array_equal(getattr(got, m), getattr(ref, m)), (name, m)
        assert got.input_labels == ref.input_labels and got.output_labels == ref.output_labels
    n = len(spacecraft.INPUTS)
    assert back["G_r"].input_labels[-n:] == list(spacecraft.INPUTS) and back["G_r"].input_labels[0].startswith("w_")
    assert np.max(np.linalg.eigvals(back["closed_loop"].A).real) < 0


def test_bad_input_is_named(tmp_path):
    with pytest.raises(ValueError, match="gain must be a finite 4x8"):
        export.save_design_mat(tmp_path / "x.mat", np.ones((8, 4)), None, None)
    with pytest.raises(ValueError, match="does not exist"):
        export.save_design_mat(tmp_path / "no" / "x.mat", np.ones((4, 8)), None, None)


def test_a_design_with_sides_by_member_group_round_trips(tmp_path):
    models = design.models_at({"longerons": 0.025, "all": 0.02})
    path = export.save_design_mat(tmp_path / "grouped.mat", np.full((4, 8), -0.5), models, LoopSettings.from_parameters())
    back = export.load_design_mat(path)
    assert back["h_m"] == {"longerons": 0.025, "all": 0.02}
