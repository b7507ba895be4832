"""LFT models of the structure: the h-parametrised beam and truss, the uncertain spacecraft, the reduction."""

import numpy as np
import pytest

from trusscodesign import ports, reduction, spacecraft, titop, truss
from trusscodesign.lft import Parameter

H = Parameter("h", 0.03, 0.015, 0.03, tunable=True)


def _rel_err(g1, g0):
    return np.max(np.max(np.abs(g1 - g0), axis=(0, 1)) / np.max(np.abs(g0), axis=(0, 1)))


@pytest.mark.parametrize("h", [0.015, 0.0187, 0.02139, 0.03])
def test_h_beam_is_exact(h):
    model = titop.clamped_free_lft(1.0, titop.Section.square(0.02), H)
    assert model.occurrences() == {"h": 16}  # 2 per bending mode (6) + 4 torsion channels
    r = h / H.center
    scale = np.r_[np.full(6, 1 / r), np.full(6, r)]  # scaled signals -> physical
    w = np.logspace(0, 4.5, 200)
    g = model.substitute({"h": h}).freqresp(w) * scale[:, None, None] * scale[None, :, None]
    assert _rel_err(g, titop.clamped_free(1.0, titop.Section.square(h)).freqresp(w)) < 1e-9


def test_h_truss_occurrences_and_exact_poles():
    model = truss.t_truss(titop.Section.square(0.02), h_param=H)
    assert model.occurrences() == {"h": 65 * 16 + 6 * 12}
    for h in (0.015, 0.03):
        p1 = np.abs(model.substitute({"h": h}).poles())
        p2 = np.abs(truss.t_truss(titop.Section.square(h)).poles())
        f1, f2 = np.sort(p1[p1 > 1e-2]), np.sort(p2[p2 > 1e-2])
        assert f1.size == f2.size == 760 and np.max(np.abs(f1 / f2 - 1)) < 1e-9


def test_uncertain_tunable_spacecraft_equals_direct_build():
    ol = spacecraft.open_loop(uncertain=True, tunable=True)
    occ = ol.lft.occurrences()
    assert occ == {"M_SC": 3, "Iyy_SC": 1, "omega1_SP": 4, "tau": 32, "h": 1112}
    vals = {"h": 0.015, "M_SC": 960.0, "Iyy_SC": 800.0, "omega1_SP": 2.008, "tau": -1.0}  # a corner
    a, b, c, d = ol.lft.evaluate(vals)
    ref = spacecraft.open_loop(vals["h"], theta=4 * np.arctan(vals["tau"]), hub_mass=vals["M_SC"], hub_iyy=vals["Iyy_SC"],
                               panel_omega1=vals["omega1_SP"]).G
    s1, s2 = reduction.split_slow(a, b, c, d), reduction.split_slow(ref.A, ref.B, ref.C, ref.D)
    w = np.logspace(-3, 4, 120)
    assert _rel_err(ports.modal_frequency_response(*s1.fast, w), ports.modal_frequency_response(*s2.fast, w)) < 1e-8


def test_reduction_keeps_dc_and_removes_the_right_poles():
    g = spacecraft.open_loop(0.03).G
    low = reduction.modal_reduction(g.A, g.B, g.C, g.D)
    red = reduction.modal_reduction(g.A, g.B, g.C, g.D, omega_max=500.0)
    assert low.n_slow == 540 and low.reduced[0].shape[0] == 784
    poles = np.abs(np.linalg.eigvals(red.reduced[0]))
    assert poles.max() <= 500.0 and red.reduced[0].shape[0] + red.n_high == 784
    dc = [m[3] - m[2] @ np.linalg.solve(m[0], m[1]) for m in (low.reduced, red.reduced)]
    assert np.max(np.abs(dc[1] - dc[0])) < 1e-6 * np.max(np.abs(dc[0]))
    with pytest.raises(ValueError, match="omega_max"):
        reduction.modal_reduction(g.A, g.B, g.C, g.D, omega_max=0.001)
