"""Test configuration: non-interactive plotting and the figures closed after each test."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture(autouse=True)
def _no_assert_log(monkeypatch):
    """Notebooks that a test runs itself (papermill, other parameters) do not log their asserts as run under the smoke
    parameters: only the nbval runs of scripts/test.sh do (scripts/smoke_asserts.py)."""
    monkeypatch.delenv("SMOKE_ASSERT_LOG", raising=False)
