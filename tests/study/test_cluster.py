"""The Dask clients: local workers single-threaded, without the nanny's malloc trim threshold."""

import pytest
from trusscodesign.study import cluster


def test_local_workers_keep_glibc_dynamic_mmap_threshold():
    """Dask's nanny would start the workers with MALLOC_TRIM_THRESHOLD_ set, which pins glibc's mmap threshold and made
    a fast-path synthesis twice as slow in a worker as in a plain process (measured: 33.3 s against 16.8 s)."""
    import os

    pytest.importorskip("dask.distributed")
    client = cluster.local_client(1)
    try:
        env = client.run(lambda: os.environ.get("MALLOC_TRIM_THRESHOLD_"))
        blas = client.run(lambda: os.environ.get("OPENBLAS_NUM_THREADS"))
    finally:
        client.close()
        client.cluster.close()
    assert list(env.values()) == [None]
    assert list(blas.values()) == ["1"]


def test_the_local_cluster_keeps_its_info_messages_out_of_the_output(caplog):
    """Importing distributed sets its loggers to INFO: the cluster's start and stop would print some 40 lines into a
    notebook's output (notebook 06's sensitivity study did); its warnings still show."""
    import logging

    pytest.importorskip("dask.distributed")
    with caplog.at_level(logging.INFO):
        client = cluster.local_client(1)
        cluster.close_client(client)
    assert not [r for r in caplog.records if r.name.startswith("distributed") and r.levelno < logging.WARNING]
    assert logging.getLogger("distributed").getEffectiveLevel() == logging.WARNING
