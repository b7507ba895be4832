"""Input checks: a string or a non-finite value for a number is named, with its unit, wherever it enters."""

import pytest
from trusscodesign.control.synthesis import Scenario
from trusscodesign.model import truss
from trusscodesign.model.lft import Parameter


def test_strings_for_numbers_are_named():
    with pytest.raises(TypeError, match="nominal must be a real number"):
        Parameter("m", "800", 600.0, 1000.0)
    with pytest.raises(TypeError, match="high must be a real number"):
        Parameter("m", 800.0, 600.0, "1000")
    with pytest.raises(TypeError, match="nominal must be a real number"):
        Parameter.percent("m", "800", 20.0)
    with pytest.raises(TypeError, match="percent must be a real number"):
        Parameter.percent("m", 800.0, "20")
    with pytest.raises(TypeError, match="Scenario.d_mass must be a real number"):
        Scenario(d_mass="0.5")
    with pytest.raises(TypeError, match="Scenario.theta must be a real number"):
        Scenario(theta="1.0")
    with pytest.raises(TypeError, match="cube side a must be a real number"):
        truss.truss_nodes("1")
    assert Parameter("m", 800, 600, 1000).center == 800.0 and Scenario(1, 0, 0, 0).d_mass == 1
    assert len(truss.truss_nodes(2)) == 24
