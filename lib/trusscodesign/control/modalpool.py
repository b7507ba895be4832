"""Worker processes that keep the open-loop modal forms of scenario plants and evaluate them at a gain.

The synthesis's optimiser evaluates every scenario plant at each trial gain by the fast path
(:class:`trusscodesign.control.modalloop.ModalLoop`: about 4-5 ms per plant at order 208). Those are many small numpy calls that hold
the GIL, so two threads speed them up only 1.2-1.5 times; a worker process and the calling process, each evaluating
half of the plants, 1.65 times two threads (``benchmarks/warm_search.py``: 1.97 against 3.25 ms per plant, 22 plants
at 2.139 cm, parabolic peaks). A process pool of the standard
library (``concurrent.futures.ProcessPoolExecutor``) cannot send a task to the worker that already holds a plant's
form, and sending the form with every task would pickle the plant's state matrix (350 kB) each time: hence these
workers, each with a pipe and a registry ``key -> ModalLoop`` built from a plant the first time it is sent.

The state of a form that carries from one call to the next (the poles of the last call, from which the pole
iteration starts) travels with each task and comes back with its result: the main process's copy of the form holds
it, so a result does not depend on which worker computed it.

Workers are started by ``fork`` (a few milliseconds; ``spawn`` and ``forkserver`` run the caller's main script again
in each worker, the whole study if it has no ``if __name__ == "__main__"`` guard) once per process and kept, before
the synthesis starts its threads; they use one BLAS thread each, import nothing after the fork, ignore keyboard
interrupts (the main process handles them) and stop when the main process dies. Where fork is missing (Windows) or
unsafe (macOS) or not allowed (a daemonic process, e.g. a Dask worker, cannot start children), :func:`shared_pool`
raises ``RuntimeError`` and the caller falls back to threads.
"""

from __future__ import annotations

import atexit
import ctypes
import itertools
import multiprocessing as mp
import signal
import sys
import threading
import traceback
from collections.abc import Callable, Sequence
from typing import Any

from threadpoolctl import threadpool_limits

from .closedloop import GeneralizedPlant
from .modalloop import ModalLoop

__all__ = ["ModalPool", "shared_pool"]


def _serve(conn, inherited: Sequence[Any] = (), pdeathsig: bool = False) -> None:
    """A worker's loop: ``("call", func, jobs, args)`` with jobs ``(key, plant or None, state)`` answers
    ``("ok", [func(form, state, *args), ...])`` or ``("error", traceback)`` (the registry then emptied, as the caller's
    record of it); ``("forget",)`` empties the registry; ``None``, or the main process's end, stops it.

    ``inherited``: the main process's ends of the workers' pipes, which the fork copied here; closed first, so that
    this worker sees the end of its pipe (and stops) when the main process dies, however it dies. ``pdeathsig``: also
    have the kernel stop it then (Linux; only for a pool created from the main thread, see :class:`ModalPool`)."""
    for end in inherited:
        end.close()
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # an interrupt is the main process's to handle (it stops the workers)
    if pdeathsig and _PRCTL is not None:
        _PRCTL(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    forms: dict[int, ModalLoop] = {}
    with threadpool_limits(1):
        while True:
            try:
                msg = conn.recv()
                if msg is None:
                    return
                if msg[0] == "forget":
                    forms.clear()
                    conn.send(("ok", None))
                    continue
                _, func, jobs, args = msg
                out = []
                for key, plant, state in jobs:
                    if plant is not None:
                        forms[key] = ModalLoop.of(plant)
                    out.append(func(forms[key], state, *args))
                conn.send(("ok", out))
            except EOFError:  # the main process has gone
                return
            except BaseException:  # noqa: BLE001 - every failure goes back to the caller, with its traceback
                forms.clear()  # the caller forgets what it sent this worker too (some plants may not be registered)
                conn.send(("error", traceback.format_exc()))


def _find_prctl() -> Callable[..., int] | None:
    """Linux's ``prctl`` from the C library already loaded (resolved here, before any fork: a child that loaded a
    library after the fork could deadlock on a lock another thread of the parent held)."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        return ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None


_PRCTL = _find_prctl()


class _WorkerError(RuntimeError):
    """An evaluation failed in a worker, which replied with its traceback: the pipes are still in step."""


class _Stopped(RuntimeError):
    """A worker's pipe is closed: the worker has died."""


class ModalPool:
    """``processes`` worker processes holding modal forms; :meth:`map` evaluates plants on them.

    A call that is interrupted between its requests and their replies (a keyboard interrupt, a worker that died)
    would leave replies in the pipes for the next call: the pool then stops its workers and refuses further calls
    (:func:`shared_pool` starts a new one). A failure in a worker, or a request that cannot be pickled, leaves it
    usable (every reply is read before the error is raised). The workers run the code as it was when they
    were forked: after reloading a module (``%autoreload``) or patching one of its functions, start a new pool.

    Parameters
    ----------
    processes : int
        Number of worker processes (at least 1).
    """

    def __init__(self, processes: int = 2) -> None:
        if not (isinstance(processes, int) and processes >= 1):
            raise ValueError(f"processes must be an integer >= 1, got {processes!r}")
        if sys.platform == "darwin" or "fork" not in mp.get_all_start_methods():
            raise RuntimeError("the modal-form workers need the 'fork' start method, which this platform lacks "
                               "(or, on macOS, does not make safe)")
        if mp.current_process().daemon:
            raise RuntimeError("a daemonic process (e.g. a Dask worker) cannot start the modal-form workers")
        ctx = mp.get_context("fork")
        self._conns: list[Any] = []
        self._procs: list[Any] = []
        self._broken = False
        self._known: list[set[int]] = [set() for _ in range(processes)]
        self._keys: dict[int, tuple[int, GeneralizedPlant]] = {}  # id(plant) -> key, and the plant (so its id stays its own)
        self._count = itertools.count()
        self._lock = threading.Lock()
        # the kernel's parent-death signal fires when the creating *thread* ends: asked for only from the main thread
        pdeathsig = threading.current_thread() is threading.main_thread()
        try:
            for _ in range(processes):
                parent, child = ctx.Pipe()
                try:
                    proc = ctx.Process(target=_serve, args=(child, [*self._conns, parent], pdeathsig), daemon=True)
                    proc.start()
                except BaseException:
                    parent.close()
                    raise
                finally:
                    child.close()
                self._conns.append(parent)
                self._procs.append(proc)
        except BaseException:
            self._abandon()
            raise

    @property
    def processes(self) -> int:
        return len(self._conns)

    def _key(self, plant: GeneralizedPlant) -> int:
        if id(plant) not in self._keys:
            self._keys[id(plant)] = (next(self._count), plant)
        return self._keys[id(plant)][0]

    @property
    def _stopped(self) -> bool:
        """Whether the pool has been stopped (closed, or abandoned after an interrupted call)."""
        return self._broken or not self._conns

    def _usable(self) -> None:
        if self._stopped:
            raise RuntimeError("this ModalPool has been stopped (closed, or a call was interrupted); "
                               "trusscodesign.control.modalpool.shared_pool() starts a new one")

    def map(self, func: Callable[..., Any], items: Sequence[tuple[GeneralizedPlant, Any]], *args: Any,
            local: Callable[[int], Any] | None = None) -> list[Any]:
        """``[func(form_of(plant), state, *args) for plant, state in items]`` on the workers.

        ``func`` must be a module-level function (it is sent by reference); ``form_of(plant)`` is the worker's
        :class:`~trusscodesign.control.modalloop.ModalLoop` of the plant, built the first time the plant reaches that worker. With
        ``local`` (``j -> result of item j``, computed in this process), this process takes a share too: items
        ``0, k, 2k, ...`` (``k = processes + 1``) here while the workers compute the others, so that a machine with
        ``processes + 1`` cores runs as many busy processes as it has cores. Raises ``RuntimeError`` with the
        worker's traceback if an evaluation fails in a worker (the pool stays usable), ``local``'s own exception if
        it fails here, and ``RuntimeError`` if a worker has died (the pool is then stopped).
        """
        if not items:
            return []
        n, first = self.processes + (local is not None), int(local is not None)
        out: list[Any] = [None] * len(items)
        with self._lock:
            self._usable()
            sent: list[int] = []
            gathered = False  # every reply due has been read: the pipes are in step
            failure: BaseException | None = None
            try:
                try:
                    for w in range(min(self.processes, len(items) - first)):
                        jobs, new = [], set()
                        for plant, state in items[w + first::n]:
                            key = self._key(plant)
                            jobs.append((key, None if key in self._known[w] or key in new else plant, state))
                            new.add(key)
                        self._send(w, ("call", func, jobs, args))
                        self._known[w] |= new
                        sent.append(w)
                except _Stopped:
                    raise
                except Exception as exc:  # a request that cannot be pickled (nothing of it written)
                    failure = exc
                if failure is None and local is not None:
                    try:
                        out[::n] = [local(j) for j in range(0, len(items), n)]
                    except Exception as exc:  # raised below, once the workers' replies are read
                        failure = exc
                try:
                    parts = self._gather(sent)
                except _WorkerError as exc:
                    gathered = True
                    if failure is None:
                        raise
                    raise failure from exc
                gathered = True
            except BaseException:
                if not gathered:  # an interrupt or a dead worker: replies may be left in the pipes
                    self._abandon()
                raise
            if failure is not None:
                raise failure
        for w, part in zip(sent, parts):
            out[w + first::n] = part
        return out

    def forget(self) -> None:
        """Drop every plant and form (the workers' and this side's registry); call when a synthesis ends. Nothing to
        do on a stopped pool."""
        with self._lock:
            if self._stopped:
                return
            gathered = False
            try:
                for w in range(self.processes):
                    self._send(w, ("forget",))
                self._gather(range(self.processes))
                gathered = True
            except BaseException:
                if not gathered:
                    self._abandon()
                raise
            self._keys.clear()
            self._known = [set() for _ in range(self.processes)]

    def _gather(self, workers: Sequence[int] | range) -> list[Any]:
        """Every worker's reply, then the first failure in a worker raised (so that no reply is left for the next call);
        any other exception (a dead worker, an interrupt) leaves replies unread: the callers then stop the pool."""
        parts: list[Any] = []
        error: _WorkerError | None = None
        for w in workers:
            try:
                parts.append(self._receive(w))
            except _WorkerError as exc:
                error = error or exc
                parts.append(None)
                self._known[w] = set()  # the worker has emptied its registry
        if error is not None:
            raise error
        return parts

    def _send(self, w: int, msg: Any) -> None:
        try:
            self._conns[w].send(msg)
        except (BrokenPipeError, EOFError, OSError) as exc:
            raise _Stopped(f"modal-form worker {w} has stopped (exit code {self._procs[w].exitcode}); "
                           "trusscodesign.control.modalpool.shared_pool() starts a new pool") from exc

    def _receive(self, w: int) -> Any:
        try:
            status, value = self._conns[w].recv()
        except (EOFError, OSError) as exc:
            raise _Stopped(f"modal-form worker {w} has stopped (exit code {self._procs[w].exitcode}); "
                           "trusscodesign.control.modalpool.shared_pool() starts a new pool") from exc
        if status == "error":
            raise _WorkerError(f"an evaluation failed in modal-form worker {w}:\n{value}")
        return value

    @property
    def alive(self) -> bool:
        """Whether the pool can be used: not stopped, every worker running."""
        return not self._stopped and all(p.is_alive() for p in self._procs)

    def _abandon(self) -> None:
        """Stop the workers at once (their pipes may hold replies no call will read) and refuse further calls."""
        self._broken = True
        self._release(wait=False)
        self._keys, self._known = {}, []

    def close(self) -> None:
        """Stop the workers (waiting up to 5 s for a call in progress in another thread)."""
        locked = self._lock.acquire(timeout=5)
        try:
            self._close()
        finally:
            if locked:
                self._lock.release()

    def _close(self) -> None:
        for conn in self._conns:
            try:
                conn.send(None)
            except (BrokenPipeError, EOFError, OSError):
                pass
        self._release(wait=True)

    def _release(self, wait: bool) -> None:
        """End the workers (``wait``: up to 5 s each for those asked to stop, else killed at once) and close the pipes."""
        for proc in self._procs:
            if wait:
                proc.join(timeout=5)
            if proc.is_alive():
                proc.kill()
            proc.join(timeout=5)
        for conn in self._conns:
            conn.close()
        self._conns, self._procs = [], []


_POOLS: dict[int, ModalPool] = {}
_POOLS_LOCK = threading.Lock()


def shared_pool(processes: int = 2) -> ModalPool:
    """The process's pool of ``processes`` workers, started at first use and kept (a co-design runs many syntheses;
    the forms are dropped after each by :meth:`ModalPool.forget`), stopped at exit. A pool that has been stopped, or
    whose workers have died, is replaced. Raises ``RuntimeError`` where processes cannot be started (a daemonic
    process, such as a Dask worker; see the module's notes)."""
    with _POOLS_LOCK:
        pool = _POOLS.get(processes)
        if pool is None or not pool.alive:
            if pool is not None:
                pool.close()
            pool = _POOLS[processes] = ModalPool(processes)
        return pool


@atexit.register
def _close_pools() -> None:
    for pool in _POOLS.values():
        pool.close()
    _POOLS.clear()
