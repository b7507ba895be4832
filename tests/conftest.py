"""Test configuration: non-interactive plotting and the figures closed after each test; the reduced uncertain spacecraft
model at the paper's h = 2.139 cm and its rigid inertia at P1, shared by the control and study tests (built once per
test module)."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402
from trusscodesign.model import spacecraft  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture(autouse=True)
def _no_assert_log(monkeypatch):
    """Notebooks that a test runs itself (papermill, other parameters) do not log their asserts as run under the smoke
    parameters: only the nbval runs of scripts/test.sh do (scripts/smoke_asserts.py)."""
    monkeypatch.delenv("SMOKE_ASSERT_LOG", raising=False)


@pytest.fixture(scope="module")
def model():
    return spacecraft.reduced_uncertain_model(0.02139)


@pytest.fixture(scope="module")
def inertia(model):
    return spacecraft.inertia_at_p1(model)
