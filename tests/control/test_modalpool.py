"""Worker processes for the fast path (trusscodesign.control.modalpool): the same values as in this process, to the last bit, errors
carried back with their traceback, and the synthesis's optimiser taking the same steps on processes as on threads."""

import numpy as np
import pytest
from threadpoolctl import threadpool_limits
from trusscodesign.control import synthesis
from trusscodesign.control.closedloop import LoopSettings
from trusscodesign.control.modalloop import ModalLoop
from trusscodesign.control.modalpool import ModalPool, shared_pool
from trusscodesign.control.synthesis import Scenario, plant_at

ST = LoopSettings.from_parameters()
SCENARIOS = [Scenario(-1.0, 1.0, -0.5, np.deg2rad(130.0)), Scenario(1.0, -1.0, 1.0, np.deg2rad(40.0)),
             Scenario(0.3, 0.2, -1.0, 1.0)]


@pytest.fixture(scope="module")
def pool():
    p = ModalPool(2)
    yield p
    p.close()


@pytest.fixture(scope="module")
def plants(model, inertia):
    return [plant_at(model, s, inertia, ST) for s in SCENARIOS]


def test_pool_peaks_equal_the_in_process_ones_to_the_last_bit(pool, plants):
    """Over a sequence of gains (each form's pole iteration starting from the last gain's poles), the workers' peaks,
    poles, margins, pole vectors and iteration counts equal those of the same forms evaluated here, bit for bit:
    the state a form carries travels with each task, so which worker computes a plant does not matter. (Here BLAS on
    one thread, as in the workers and in a synthesis: two threads sum matrix products in another order, 1e-13 apart.)"""
    with threadpool_limits(1):
        _compare(pool, plants)


def _compare(pool, plants):
    here = [ModalLoop.of(p) for p in plants]
    there = [ModalLoop.of(p) for p in plants]
    rng = np.random.default_rng(3)
    for step in range(4):
        gain = -np.ones((4, 8)) * (1 + 0.01 * step) + 1e-3 * rng.standard_normal((4, 8))
        order = list(range(len(plants)))[::(-1) ** step]  # each plant on another worker from one step to the next
        got = synthesis._pool_peaks(pool, [plants[i] for i in order], [there[i] for i in order], gain, min_damping=2e-4)
        for i, lp in zip(order, got):
            ref = synthesis.loop_peaks(plants[i], gain, min_damping=2e-4, modal=here[i])
            assert lp.peaks == ref.peaks and lp.abscissa == ref.abscissa and lp.stable == ref.stable
            assert np.array_equal(lp.poles(), ref.poles()) and np.array_equal(lp.decomposition().value, ref.decomposition().value)
            for a, b in zip(lp.decomposition().vectors(), ref.decomposition().vectors()):
                assert np.array_equal(a, b)
            assert np.array_equal(there[i].start, here[i].start) and there[i].sweeps == here[i].sweeps
            assert there[i].fallbacks == here[i].fallbacks


def test_a_failure_in_a_worker_comes_back_with_its_traceback(pool, plants):
    """A bad gain fails in both workers: the first failure is raised with the worker's traceback, and both replies are
    read (the next call gets its own). With a local share, this process's own failure is raised as is."""
    opts = dict(min_damping=2e-4)
    with pytest.raises(RuntimeError, match="(?s)failed in modal-form worker 0.*ValueError: gain must be"):
        pool.map(synthesis._remote_peaks, [(p, None) for p in plants], np.ones((3, 3)), opts)
    got = pool.map(synthesis._remote_peaks, [(p, None) for p in plants], -np.ones((4, 8)), opts)
    assert len(got) == 3 and all(g[2] for g in got)  # stable, and each plant's own reply
    form = ModalLoop.of(plants[0])
    with pytest.raises(ValueError, match="gain must be"):
        synthesis._pool_peaks(pool, plants[:1], [form], np.ones((3, 3)))


def test_forget_empties_the_registries(pool, plants):
    forms = [ModalLoop.of(p) for p in plants]
    synthesis._pool_peaks(pool, plants, forms, -np.ones((4, 8)))
    assert pool._keys and any(pool._known)
    pool.forget()
    assert not pool._keys and not any(pool._known)
    # the plants are sent again and give the same values (BLAS on one thread, as in the workers)
    with threadpool_limits(1):
        again = synthesis._pool_peaks(pool, plants, [ModalLoop.of(p) for p in plants], -np.ones((4, 8)))
        here = [synthesis.loop_peaks(p, -np.ones((4, 8)), modal=ModalLoop.of(p)).peaks for p in plants]
    assert [lp.peaks for lp in again] == here


def test_bad_pool_size():
    with pytest.raises(ValueError, match="processes"):
        ModalPool(0)


def test_a_pool_that_cannot_start_falls_back_to_threads(monkeypatch):
    def refuse(n):
        raise RuntimeError("a daemonic process cannot start the modal-form workers")

    monkeypatch.setattr(synthesis, "shared_pool", refuse)
    with pytest.warns(RuntimeWarning, match="using threads"):
        with synthesis._pooled(True, 2) as got:
            assert got is None
    with synthesis._pooled(False, 2) as got:
        assert got is None


def test_the_optimiser_takes_the_same_steps_on_processes_as_on_threads(plants):
    """From an effort-infeasible start (3 x the stored 2.1 cm grid gain at 2.139 cm; Z = 8.24), stabilisation then
    the feasibility and optimisation phases for 12 iterations, fast path, two threads: with the evaluations on the
    shared pool's two processes the gains, J, Z and the history are the same to the last bit."""
    from test_synthesis import _grid_gain

    def run(pool):
        with synthesis._workers(2) as pmap:
            prob = synthesis._Problem(list(plants), [], pmap, 1e-7, ST.gamma_u, 0.7, 0.02, 2e-3, 1.0, 12, False,
                                      min_damping_all=2e-4, chunk=2, fast=True, trust_region="ball",
                                      restoration="least_change", pool=pool)
            state, _ = synthesis._optimise(prob, synthesis._stabilise(prob, prob.evaluate_all(3.0 * _grid_gain(0.021))))
        return state, prob

    ref, ref_prob = run(None)
    pool = shared_pool(1)  # as synthesize takes it for two workers: one process and this one
    try:
        got, prob = run(pool)
    finally:
        pool.forget()
    assert len(ref_prob.history) > 5 and ref_prob.iterations == prob.iterations
    assert np.array_equal(got.gain, ref.gain) and prob.history == ref_prob.history
    assert got.value("rpe") == ref.value("rpe") and got.value("effort") == ref.value("effort")
    assert prob.evaluations == ref_prob.evaluations


def test_synthesize_on_processes_equals_it_on_threads(model, inertia):
    """A short synthesis (one round of 5 iterations from all gains at -1, a small search) with ``processes=True`` and
    with threads: the same gain, J_c, Z_c and history to the last bit, and the pool's plants forgotten at the end."""
    kw = dict(fast=True, workers=2, max_rounds=1, max_iter=5, search_thetas_deg=(0.0, 90.0), search_max_evals=3,
              fast_search=True, peak_refine="parabolic", trust_region="ball", restoration="least_change")
    ref = synthesis.synthesize(model, inertia, **kw)
    got = synthesis.synthesize(model, inertia, processes=True, **kw)
    assert ref.iterations == got.iterations == 5 and got.history == ref.history
    assert np.array_equal(got.gain, ref.gain) and got.j_c == ref.j_c and got.z_c == ref.z_c
    assert not shared_pool(1)._keys


def _sleep(form, state, delay):
    """A task for the pool that takes ``delay`` seconds and returns its state."""
    import time

    time.sleep(delay)
    return state


def test_an_interrupted_call_stops_the_pool_and_shared_pool_replaces_it(plants):
    """An interrupt while the workers compute would leave their replies for the next call (which would return the
    previous call's results): the pool stops its workers and refuses further calls; shared_pool starts a new one."""
    import signal

    pool = shared_pool(1)

    def interrupt(*_):
        raise KeyboardInterrupt

    old = signal.signal(signal.SIGALRM, interrupt)
    try:
        signal.setitimer(signal.ITIMER_REAL, 0.3)
        with pytest.raises(KeyboardInterrupt):
            pool.map(_sleep, [(plants[0], "first"), (plants[1], "first")], 2.0)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    assert not pool.alive
    with pytest.raises(RuntimeError, match="has been stopped"):
        pool.map(_sleep, [(plants[0], "second")], 0.0)
    pool.forget()  # nothing to do on a stopped pool (a synthesis's exit path calls it)
    fresh = shared_pool(1)
    assert fresh is not pool and fresh.map(_sleep, [(plants[0], "third"), (plants[1], "fourth")], 0.0) == ["third", "fourth"]


def test_a_request_that_cannot_be_pickled_leaves_the_pool_in_step(pool, plants):
    """The second worker's request cannot be pickled after the first's was sent: the first's reply is read before the
    error is raised, and the next calls get their own results with the plants each worker holds."""
    with pytest.raises(Exception, match="pickle"):
        pool.map(_sleep, [(plants[0], "A"), (plants[1], lambda: 0)], 0.0)
    assert pool.alive
    for tag in "BC":
        assert pool.map(_sleep, [(plants[0], tag + "0"), (plants[1], tag + "1")], 0.0) == [tag + "0", tag + "1"]


def test_workers_stop_when_the_main_process_is_killed(tmp_path):
    """A main process killed outright (SIGKILL: no atexit, no close) leaves no worker behind: each closes the main
    process's pipe ends it inherited, sees the end of its pipe and stops (and the kernel stops it, on Linux)."""
    import os
    import subprocess
    import sys
    import time
    from pathlib import Path

    script = tmp_path / "killed.py"
    script.write_text("import os, signal\nfrom trusscodesign.control.modalpool import ModalPool\npool = ModalPool(2)\n"
                      "print(' '.join(str(p.pid) for p in pool._procs), flush=True)\nos.kill(os.getpid(), signal.SIGKILL)\n")
    root = Path(__file__).parents[2]
    run = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120,
                         env={**os.environ, "PYTHONPATH": str(root)})
    pids = [int(p) for p in run.stdout.split()]
    assert len(pids) == 2

    def alive(pid):
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return False
        with open(f"/proc/{pid}/stat") as f:  # a zombie has stopped
            return f.read().split()[2] != "Z"

    deadline = time.monotonic() + 10
    while any(alive(p) for p in pids) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not any(alive(p) for p in pids)


def test_a_pool_created_in_a_thread_outlives_the_thread(plants):
    """The kernel's parent-death signal fires when the creating thread ends, not the process: a pool created by a
    thread that then exits (a synthesis run in a thread) must keep its workers (measured before the fix: killed, exit
    code -9)."""
    import threading
    import time

    made = []
    t = threading.Thread(target=lambda: made.append(ModalPool(1)))
    t.start()
    t.join()
    time.sleep(0.5)
    pool = made[0]
    try:
        assert pool.alive
        assert pool.map(_sleep, [(plants[0], "after")], 0.0) == ["after"]
    finally:
        pool.close()


def test_the_pickling_error_is_raised_and_not_a_worker_failure(pool, plants):
    """A request that cannot be pickled after another worker's request failed there: the pickling error is the one
    raised (the worker's failure chained to it), and the pool stays usable."""
    from trusscodesign.control.modalpool import _WorkerError

    with pytest.raises(Exception, match="pickle") as caught:
        pool.map(synthesis._remote_peaks, [(plants[0], None), (plants[1], lambda: 0)], np.ones((3, 3)), {})
    assert not isinstance(caught.value, _WorkerError) and isinstance(caught.value.__cause__, _WorkerError)
    assert pool.alive and pool.map(_sleep, [(plants[0], "x"), (plants[1], "y")], 0.0) == ["x", "y"]
