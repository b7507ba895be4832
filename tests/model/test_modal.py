"""Modal data: participation factors and models built from them."""

import numpy as np
import pytest
from trusscodesign.model import modal


def test_transposed_participation_factors_are_refused():
    omega = np.array([2.5, 5.0, 9.0])
    factors = np.array([[0, 0, 5.0, 0, 1.0, 0], [0, 0, 2.0, 0, 0.5, 0], [1.0, 0, 0, 0, 0, 0.2]])
    rigid = np.diag([80, 80, 80, 50, 50, 50.0])
    modal.cantilever_from_modes(rigid, omega, factors)
    with pytest.raises(ValueError, match=r"shape \(n, 6\)"):  # was reshaped (scrambled) into a 3x6 array silently
        modal.cantilever_from_modes(rigid, omega, factors.T)
    modal.cantilever_from_modes(rigid, omega[:1], factors[0])  # one mode: a row of 6 is fine
