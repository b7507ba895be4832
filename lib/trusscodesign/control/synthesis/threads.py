"""The synthesis's thread pool: scenario plants evaluated in parallel, one BLAS thread each.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager

from threadpoolctl import threadpool_limits

from ...infra.checks import check_option as _check_option

__all__ = []


def _n_workers(n: int | None) -> int:
    """Worker threads: ``n``, or up to 2 (the cores of the reference machine)."""
    if n is not None:
        _check_option("workers", n, 1, integer=True)
    return max(1, min(os.cpu_count() or 1, 2) if n is None else int(n))


@contextmanager
def _workers(n: int | None):
    """A thread pool (LAPACK releases the GIL) with one BLAS thread per worker: no oversubscription."""
    n = _n_workers(n)
    if n == 1:  # in this thread: no pool overhead, and profilers see the work
        with threadpool_limits(1):
            yield map
        return
    with threadpool_limits(1), ThreadPoolExecutor(n) as pool:
        yield pool.map
