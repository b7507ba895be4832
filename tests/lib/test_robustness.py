"""mu bounds of the spacecraft closed loop at one panel angle: ordered, tight, and the lower bound achieved by the model."""

import numpy as np
import pytest

from lib import design, robustness, synthesis
from lib.closedloop import LoopSettings
from lib.synthesis import Scenario

ST = LoopSettings.from_parameters()


@pytest.fixture(scope="module")
def models():
    return design.models_at(0.02139)


@pytest.mark.parametrize("theta_deg", [40.0])
def test_bounds_ordered_tight_and_achieved(models, theta_deg):
    gain = -np.ones((4, 8))
    out = robustness.bounds_at_angle(models.g_r_low, np.deg2rad(theta_deg), gain, models.inertia, ST)
    for group, b in out.items():
        assert np.isfinite(b.upper) and b.upper >= b.lower * (1 - 1e-9)
        assert b.gap < 0.05, (group, b.upper, b.lower)
        # the lower bound is a gain of the model at those parameters (peak-aware norm at least as large)
        sc = Scenario(b.deltas["M_SC"], b.deltas["Iyy_SC"], b.deltas["omega1_SP"], np.deg2rad(theta_deg))
        value = synthesis.loop_peaks(synthesis.plant_at(models.g_r_low, sc, models.inertia, ST), gain).norm(group)
        assert value >= b.lower * (1 - 1e-6)


def test_physical_deltas(models):
    phys = robustness.physical_deltas(models.g_r_low, {"M_SC": -1.0, "Iyy_SC": 1.0, "omega1_SP": 0.0})
    assert np.isclose(phys["M_SC"], 640.0) and np.isclose(phys["Iyy_SC"], 1200.0) and np.isclose(phys["omega1_SP"], 2.51)
