"""Test configuration: non-interactive plotting, figures closed after each test, and the grouping of the tests for
pytest-xdist (scripts/test.sh runs them on 2 workers with ``--dist loadgroup --no-loadscope-reorder``)."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

# Notebook 08 analyses the design that notebook 07 stores in the same results folder (build/smoke/results in the test run):
# both run on one worker, 07 first. They are the longest part of the run (about 15 of 25 min on one process), so
# they go first and the other tests share the second worker.
CHAIN_GROUP = "notebooks 07-08"
_CHAIN = ("07_", "08_")


def xdist_group(path: Path) -> str:
    """The pytest-xdist group of the items of one file: its folder and name (a module's tests stay together, so its module-scoped
    fixtures are built once; a notebook's cells run in order in one kernel), or :data:`CHAIN_GROUP` for notebooks 07
    and 08."""
    if path.suffix == ".ipynb" and path.name.startswith(_CHAIN):
        return CHAIN_GROUP
    return f"{path.parent.name}/{path.name}"  # (shown after the test names: short)


def pytest_configure(config):
    # registered by pytest-xdist too; here as well, so that a run without it (plain pytest) does not warn of an unknown mark
    config.addinivalue_line("markers", "xdist_group(name): the pytest-xdist group of a test (set by tests/conftest.py)")


@pytest.hookimpl(tryfirst=True)  # before pytest-xdist's own hook, which reads the marks
def pytest_collection_modifyitems(config, items):
    for item in items:
        item.add_marker(pytest.mark.xdist_group(xdist_group(Path(item.path))))
    items.sort(key=_chain_first)


def _chain_first(item) -> tuple[bool, str]:
    """Sort key: the chain's items first, 07's before 08's (a stable sort keeps every file's items in their order)."""
    path = Path(item.path)
    chain = xdist_group(path) == CHAIN_GROUP
    return not chain, path.name if chain else ""


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")
