"""Dask clients for the parallel studies: a local cluster of single-threaded workers, or a running scheduler, and
a wait on their results that gives up when every worker has died.
"""

from __future__ import annotations

import logging
import os
import time
from collections.abc import Iterator

__all__ = ['NANNY_ENVIRON', 'local_client', 'close_client', 'WORKERLESS_S', 'as_finished']


# Dask's nanny starts its workers with MALLOC_TRIM_THRESHOLD_=65536 (to hand freed memory back to the OS). Setting it
# at all pins glibc's mmap threshold at 128 KiB, so every temporary array above that size is mmap'ed and page-faulted
# anew: measured on this machine, a warm synthesis by the fast path took 33.3 s in a Dask worker, 16.8 s in a plain
# process, 29.8 s in a plain process with that variable, and 17.4 s in a worker without it. None unsets it.
NANNY_ENVIRON = {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}


def local_client(n_workers: int | None = None, scheduler: str | None = None):
    """A Dask client: to ``scheduler`` (address of a running scheduler) or a local cluster of ``n_workers`` processes.

    Workers get one thread each and one BLAS thread (``OPENBLAS_NUM_THREADS=1`` is set before they start), so that
    process-level parallelism does not oversubscribe the cores. The local workers do not get the
    ``MALLOC_TRIM_THRESHOLD_=65536`` that Dask's nanny sets by default (:data:`NANNY_ENVIRON`); on a cluster of your
    own, set ``distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_`` to null in its Dask configuration too.
    """

    import dask
    from dask.distributed import Client, LocalCluster

    # importing distributed sets its loggers to INFO (Dask's configuration): a notebook's output would fill with the
    # cluster's start and stop messages; its warnings and errors still show
    logging.getLogger("distributed").setLevel(logging.WARNING)
    if scheduler:
        return Client(scheduler)
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[var] = "1"
    n = n_workers or os.cpu_count() or 1
    with dask.config.set(NANNY_ENVIRON):
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None)
    return Client(cluster)


def close_client(client) -> None:
    """Close a client of :func:`local_client`, and the local cluster it started (a scheduler of your own stays up)."""
    client.close()
    if client.cluster is not None:
        client.cluster.close()


WORKERLESS_S = 120.0  # s without any worker after which a wait on the cluster gives up (its workers died for good)


_POLL_S = 10.0  # s between two looks at the cluster while waiting


def as_finished(client, futures) -> Iterator:
    """The futures, as they finish; a RuntimeError once the cluster has had no worker for :data:`WORKERLESS_S`.

    ``dask.distributed.as_completed`` waits for ever when every worker has died and none was restarted (seen with a
    nanny that could not restart its worker on an overloaded machine): the co-design would hang instead of stopping
    with what it has saved.
    """
    from dask.distributed import wait

    pending, alone_since = set(futures), None
    while pending:
        try:
            done, pending = wait(pending, timeout=_POLL_S, return_when="FIRST_COMPLETED")
        except TimeoutError:
            if client.scheduler_info().get("workers"):
                alone_since = None
            elif alone_since is None:
                alone_since = time.monotonic()
            elif time.monotonic() - alone_since > WORKERLESS_S:
                raise RuntimeError(f"the Dask cluster has had no worker for {WORKERLESS_S:.0f} s (they died and were not "
                                   f"restarted) with {len(pending)} evaluations waiting: restart the cluster (the notebook's "
                                   "kernel) and rerun; every finished evaluation is saved and is not run again") from None
            continue
        yield from done
