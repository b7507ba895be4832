"""The interconnection of multi-port models at shared nodes: the connection rule, its checks, a closed form."""

import numpy as np
import pytest
from trusscodesign.model import interconnect, titop


SEC = titop.Section.square(0.03)


def test_connect_rejects_two_free_ports_and_misplaced_nodes():
    b1 = titop.beam(("A", [0, 0, 0]), ("B", [1, 0, 0]), SEC)
    b2 = titop.beam(("C", [1, 1, 0]), ("B", [1, 0, 0]), SEC)
    with pytest.raises(ValueError, match="free in several models"):
        interconnect.connect([b1, b2])
    b3 = titop.beam(("C", [1, 1, 0]), ("B", [1, 0.5, 0]), SEC).invert_ports("B")
    with pytest.raises(ValueError, match="node 'B'"):
        interconnect.connect([b1, b3])


def test_connect_parent_child_equals_analytic_serial_beam_statics():
    # Two collinear beams in series (clamped at A, free at C) have the static
    # compliance of one beam of twice the length.
    b1 = titop.beam(("A", [0, 0, 0]), ("B", [1, 0, 0]), SEC)
    b2 = titop.beam(("B", [1, 0, 0]), ("C", [2, 0, 0]), SEC)
    chain = interconnect.connect([b1, b2], order=["A", "B", "C"])
    assert [p.kind for p in chain.ports] == ["clamped", "free", "free"]
    single = titop.clamped_free(2.0, SEC)
    np.testing.assert_allclose(chain.static_compliance("C"), single.static_compliance("C"), rtol=1e-9, atol=1e-18)
