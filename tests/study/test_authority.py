"""The PMAs' authority share: exactly 1 on a constructed one-mode loop where the cancelling force is u_max, the same
from the frequency response and from the modal forcings, and independent of the damping at a resonance."""

from __future__ import annotations

import numpy as np
import pytest
from trusscodesign.control.closedloop import GeneralizedPlant, LoopSettings, pma_filter
from trusscodesign.study import authority


def _one_mode(zeta: float, omega0: float = 97.5, share: float = 1.0) -> GeneralizedPlant:
    """One mode ``x'' + 2 zeta w x' + w^2 x = beta_p . (p_max p~) + beta_u . u`` with the LOS ``(x, x / 2)`` and
    ``u = F_PMA(s) v``; u_max chosen so that the least force cancelling the worst p of 2-norm p_max is share x u_max."""
    beta_p, beta_u = np.array([3.0, 4.0]), np.array([1.0, 2.0, 2.0, 0.0])  # norms 5 and 3
    p_max = 0.382
    st = LoopSettings(u_max=5 * p_max / (3 * share))
    af, bf, cf, df = pma_filter(st)
    n = 2 + 2 * 4
    a = np.zeros((n, n))
    b = np.zeros((n, 2 + 4))
    a[0, 1], a[1, 0], a[1, 1] = 1.0, -omega0**2, -2 * zeta * omega0
    b[1, :2] = beta_p * p_max
    for i in range(4):  # the filter of v_i, its output u_i forcing the mode
        s = slice(2 + 2 * i, 4 + 2 * i)
        a[s, s], b[s, 2 + i] = af, bf[:, 0]
        a[1, s] += beta_u[i] * cf[0]
    c = np.zeros((2 + 4 + 8, n))
    c[0, 0], c[1, 0] = 1.0, 0.5
    return GeneralizedPlant(a, b, c, np.zeros((c.shape[0], b.shape[1])), n_delta=0, rigid_rank=0, settings=st)


@pytest.mark.parametrize("zeta", [1e-3, 1e-4])
def test_the_share_is_one_where_the_cancelling_force_is_u_max(zeta: float) -> None:
    plant = _one_mode(zeta)
    w = np.array([10.0, 97.5 * (1 - zeta), 97.5, 300.0])
    assert np.allclose(authority.authority_share(plant, w), 1.0, rtol=1e-9)
    (mode,) = authority.modal_authority(plant)
    assert mode.share == pytest.approx(1.0, rel=1e-9) and mode.omega == pytest.approx(97.5) and mode.damping == pytest.approx(zeta)
    assert authority.authority_share(_one_mode(zeta, share=7.0), [97.5])[0] == pytest.approx(7.0, rel=1e-9)


def test_bad_input_is_refused() -> None:
    plant = _one_mode(1e-3)
    with pytest.raises(ValueError, match="omega must be positive finite frequencies"):
        authority.authority_share(plant, [0.0, 1.0])
    with pytest.raises(ValueError, match="band must be"):
        authority.modal_authority(plant, band=(10.0, 1.0))


def test_on_the_spacecraft_the_share_at_a_resonance_does_not_depend_on_the_truss_damping() -> None:
    """The calibrated preset at 2.139 cm with its truss damping (1.5e-4) and ten times it: at the mode near 97.5 rad/s
    that matters most to the LOS, the share (frequency response) and the modal share move by less than 2 %, the
    mode's LOS peak by about the damping ratio. The modal share is at most the share: cancelling the LOS along the
    mode's direction alone needs less force than cancelling both LOS axes."""
    from trusscodesign.control import synthesis
    from trusscodesign.model import spacecraft
    from trusscodesign.study import design

    shares, modal, peaks = [], [], []
    for damping in (1.5e-4, 1.5e-3):
        p = spacecraft.with_choices(spacecraft.preset_parameters("paper_calibrated"), truss_damping=damping)
        m = design.models_at(0.02139, p)
        plant = synthesis.plant_at(m.g_r, synthesis.Scenario(theta=np.deg2rad(100.6)), m.inertia, LoopSettings.from_parameters(p))
        mode = max(authority.modal_authority(plant, band=(90.0, 105.0)), key=lambda x: x.los_peak)
        shares.append(authority.authority_share(plant, [mode.omega])[0])
        modal.append(mode.share)
        peaks.append(mode.los_peak)
        assert mode.share <= shares[-1] * 1.01
    assert shares[1] == pytest.approx(shares[0], rel=0.02) and modal[1] == pytest.approx(modal[0], rel=0.02)
    assert 3 < peaks[0] / peaks[1] < 30
