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


def test_sweep_same_bounds_in_order_on_dask_workers(models):
    """The angles run on two Dask workers come back in the order asked, with the bounds computed in this process:
    the lower bounds to the last bit, the upper bounds (SDP solves, not bitwise repeatable) to 1e-5 relative."""
    from lib import codesign

    thetas = np.deg2rad([100.0, 20.0])
    kw = dict(n_log=60, seed=3)
    here = robustness.sweep(models.g_r_low, thetas, -np.ones((4, 8)), models.inertia, ST, **kw)
    assert [out["rpe"].theta_deg for out in here] == pytest.approx([100.0, 20.0])
    client = codesign.local_client(2)
    try:
        there = robustness.sweep(models.g_r_low, thetas, -np.ones((4, 8)), models.inertia, ST, client=client, **kw)
    finally:
        client.close()
        client.cluster.close()
    for a, b in zip(here, there):
        for group in ("rpe", "effort"):
            assert a[group].theta_deg == b[group].theta_deg
            assert a[group].lower == b[group].lower and a[group].omega_lower == b[group].omega_lower
            assert b[group].upper == pytest.approx(a[group].upper, rel=1e-5)


@pytest.mark.parametrize("thetas", [[], [np.nan], [[0.1, 0.2]]])
def test_sweep_rejects_bad_angles(models, thetas):
    with pytest.raises(ValueError, match="thetas"):
        robustness.sweep(models.g_r_low, thetas, -np.ones((4, 8)), models.inertia, ST)
