"""The OpenSeesPy frame model against the in-house frame finite elements."""

import numpy as np
from trusscodesign.model import cube, frame_fe, opensees_fe, titop


def test_two_fe_codes_agree():
    s = titop.Section.square(0.03, torsion="exact")
    nodes, members = cube.cube_nodes(), cube.cube_members()
    w_ops = opensees_fe.frame_frequencies(nodes, members, s, ["N1"], 8, "consistent", 10)
    w_own = frame_fe.build_frame(nodes, members, s, 8, "consistent").modes(["N1"], n_modes=10).omega
    # OpenSees' consistent torsional inertia uses rho J instead of rho Ip: allow 0.2 %
    np.testing.assert_allclose(w_ops, w_own, rtol=2e-3)
