"""The T-truss: its h-parametrised LFT model."""

import numpy as np
from trusscodesign.model import titop, truss
from trusscodesign.model.lft import Parameter

H = Parameter("h", 0.03, 0.015, 0.03, tunable=True)


def test_h_truss_occurrences_and_exact_poles():
    model = truss.t_truss(titop.Section.square(0.02), h_param=H)
    assert model.occurrences() == {"h": 65 * 16 + 6 * 12}
    for h in (0.015, 0.03):
        p1 = np.abs(model.substitute({"h": h}).poles())
        p2 = np.abs(truss.t_truss(titop.Section.square(h)).poles())
        f1, f2 = np.sort(p1[p1 > 1e-2]), np.sort(p2[p2 > 1e-2])
        assert f1.size == f2.size == 760 and np.max(np.abs(f1 / f2 - 1)) < 1e-9
