"""Another run holding a file's lock (trusscodesign.infra.results.run_lock), in a forked process: for the tests of the
co-design's and the sweep's locks."""

from __future__ import annotations

import multiprocessing as mp
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


def hold_lock(path: str, ready, release) -> None:
    """Another run: holds the lock of ``path`` until told to release it."""
    from trusscodesign.infra import results

    with results.run_lock(path):
        ready.set()
        release.wait(30)


@contextmanager
def held_elsewhere(path: str | Path) -> Iterator[mp.process.BaseProcess]:
    """The lock of ``path`` held by another process (yielded) for the duration of the block."""
    ctx = mp.get_context("fork")
    ready, release = ctx.Event(), ctx.Event()
    holder = ctx.Process(target=hold_lock, args=(str(path), ready, release))
    holder.start()
    assert ready.wait(30)
    try:
        yield holder
    finally:
        release.set()
        holder.join(30)
