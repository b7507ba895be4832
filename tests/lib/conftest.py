"""Fixtures shared by the closed-loop, synthesis and fast-path tests: the reduced uncertain spacecraft model at the
paper's h = 2.139 cm and its rigid inertia at P1 (built once per test module, as before)."""

import pytest

from trusscodesign import spacecraft


@pytest.fixture(scope="module")
def model():
    return spacecraft.reduced_uncertain_model(0.02139)


@pytest.fixture(scope="module")
def inertia(model):
    return spacecraft.inertia_at_p1(model)
