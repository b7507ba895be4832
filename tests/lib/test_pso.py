"""Particle swarm: convergence on a known minimum, MATLAB's adaptive rules, reproducibility, resume from a checkpoint,
and the same result through Dask with 1 and 2 workers; the co-design objective's penalty and failure handling."""

import json

import numpy as np
import pytest

from lib import codesign, pso, synthesis
from lib.closedloop import LoopSettings


def quadratic(x, state):
    return [{"f": float((xi[0] - 0.3) ** 2 + 0.1 * np.sin(20 * xi[0]) ** 2)} for xi in x]


def test_finds_the_minimum_of_a_known_function():
    grid = np.linspace(0, 1, 200001)
    f = (grid - 0.3) ** 2 + 0.1 * np.sin(20 * grid) ** 2
    state = pso.run(quadratic, n=12, lower=[0.0], upper=[1.0], iterations=30, seed=1)
    assert abs(state.g_f - f.min()) < 1e-5 * (f.max() - f.min())  # the global basin (local minima near 0.15 and 0.45)
    assert abs(state.g[0] - grid[np.argmin(f)]) < 1e-2


@pytest.mark.parametrize("rule", pso.RULES)
def test_reproducible_and_resumable(tmp_path, rule):
    a = pso.run(quadratic, n=6, lower=[0.0], upper=[1.0], iterations=8, seed=7, rule=rule)
    b = pso.run(quadratic, n=6, lower=[0.0], upper=[1.0], iterations=8, seed=7, rule=rule)
    assert a.history == b.history
    ck = tmp_path / "state.json"
    part = pso.run(quadratic, n=6, lower=[0.0], upper=[1.0], iterations=8, seed=7, checkpoint=ck, stop_after=3, rule=rule)
    assert part.iteration == 3 and ck.exists()
    resumed = pso.run(quadratic, n=6, lower=[0.0], upper=[1.0], iterations=8, seed=7, checkpoint=ck, rule=rule)
    assert resumed.iteration == 8
    assert resumed.history == a.history and resumed.g_f == a.g_f and np.array_equal(resumed.x, a.x)
    assert resumed.inertia == a.inertia and resumed.neighbours == a.neighbours and resumed.rule == rule
    with pytest.raises(ValueError, match="another run"):
        pso.run(quadratic, n=6, lower=[0.0], upper=[1.0], iterations=8, seed=8, checkpoint=ck, rule=rule)
    other = "matlab" if rule == "documented" else "documented"
    with pytest.raises(ValueError, match="another run.*rule"):
        pso.run(quadratic, n=6, lower=[0.0], upper=[1.0], iterations=8, seed=7, checkpoint=ck, rule=other)
    with pytest.raises(ValueError, match="another run"):  # bounds must match exactly, not to np.allclose's 1e-5
        pso.run(quadratic, n=6, lower=[0.0], upper=[1.0 + 2e-7], iterations=8, seed=7, checkpoint=ck, rule=rule)
    with pytest.raises(ValueError, match="8 completed iterations, more than the 5 asked"):
        pso.run(quadratic, n=6, lower=[0.0], upper=[1.0], iterations=5, seed=7, checkpoint=ck, rule=rule)


def test_checkpoint_without_a_rule_resumes_with_the_documented_one(tmp_path):
    ck = tmp_path / "state.json"
    pso.run(quadratic, n=6, lower=[0.0], upper=[1.0], iterations=4, seed=7, checkpoint=ck, stop_after=2)
    payload = json.loads(ck.read_text())
    del payload["rule"]  # as written before the rules were selectable (the stored co-design swarms)
    ck.write_text(json.dumps(payload))
    assert pso.load_state(ck).rule == "documented"
    resumed = pso.run(quadratic, n=6, lower=[0.0], upper=[1.0], iterations=4, seed=7, checkpoint=ck)
    assert resumed.history == pso.run(quadratic, n=6, lower=[0.0], upper=[1.0], iterations=4, seed=7).history
    with pytest.raises(ValueError, match="rule must be one of"):
        pso.run(quadratic, n=6, lower=[0.0], upper=[1.0], iterations=4, seed=7, rule="MATLAB")


def test_matlab_code_rules_adapt_the_inertia_after_every_iteration():
    """MATLAB's code (not its documentation's text): W adapts after stalled iterations too, N counts the particle
    itself and grows to n."""
    state = pso.init_swarm(24, [0.0], [1.0], seed=0, rule="matlab")
    assert state.inertia == 1.1 and state.neighbours == 6
    pso.update_bests(state, np.arange(24.0))
    expected_w = [1.1, 1.1, 1.1, 1.1, 1.1, 0.55, 0.275]  # c = 1 (< 2: doubled, clipped), 2-5 (kept), 6 and 7 (> 5: halved)
    expected_n = [12, 18, 24, 24, 24, 24, 24]
    for w, n_hood in zip(expected_w, expected_n):
        pso.update_bests(state, np.full(24, 100.0))
        assert np.isclose(state.inertia, w) and state.neighbours == n_hood
    pso.update_bests(state, np.r_[-1.0, np.full(23, 100.0)])  # improvement: c = 6 > 5, halved again; N back to N_min
    assert state.counter == 6 and np.isclose(state.inertia, 0.1375) and state.neighbours == 6
    for _ in range(3):
        pso.update_bests(state, np.full(24, 100.0))
    assert state.inertia == pso.INERTIA_RANGE[0]  # halved to below 0.1, clipped
    pso.step_positions(state)  # a neighbourhood of all 24 particles: the particle and its 23 others


def test_only_the_matlab_code_rules_slow_a_stalled_swarm():
    """On a flat objective the best never improves after the first evaluation: with the documented text W stays at
    its maximum and the swarm keeps its spread; with MATLAB's code W falls to its minimum."""
    def flat(x, state):
        return [{"f": 1.0} for _ in x]

    runs = {rule: pso.run(flat, n=8, lower=[0.0], upper=[1.0], iterations=12, seed=3, rule=rule) for rule in pso.RULES}
    assert runs["documented"].inertia == 1.1 and runs["matlab"].inertia == 0.1
    assert runs["matlab"].counter == runs["documented"].counter == 11


def test_matlab_adaptive_rules():
    state = pso.init_swarm(24, [0.0], [1.0], seed=0)
    assert state.inertia == 1.1 and state.neighbours == 6  # max(2, floor(0.25 * 24))
    pso.update_bests(state, np.arange(24.0))  # improvement from inf: c = 0 < 2 -> W doubled, clipped to 1.1
    assert state.inertia == 1.1 and state.neighbours == 6 and state.counter == 0
    for _ in range(7):  # no improvement: c grows, N grows by N_min up to n - 1
        pso.update_bests(state, np.full(24, 100.0))
    assert state.counter == 7 and state.neighbours == 23
    pso.update_bests(state, np.r_[-1.0, np.full(23, 100.0)])  # improvement with c = 6 > 5: W halved
    assert state.counter == 6 and np.isclose(state.inertia, 0.55) and state.neighbours == 6
    with pytest.raises(ValueError, match="swarm size"):
        pso.init_swarm(1, [0.0], [1.0], 0)
    with pytest.raises(ValueError, match="bounds"):
        pso.init_swarm(4, [1.0], [0.0], 0)


def cheap(h):
    return {"h": h, "f": float(np.cos(40 * h) + h)}


def test_same_result_with_one_and_two_dask_workers():
    pytest.importorskip("dask.distributed")
    results = []
    for n_workers in (1, 2):
        client = codesign.local_client(n_workers)
        try:
            def evaluate(x, state, client=client):
                return client.gather(client.map(cheap, [float(v[0]) for v in x], pure=False))

            results.append(pso.run(evaluate, n=4, lower=[0.015], upper=[0.03], iterations=4, seed=3))
        finally:
            client.close()
            client.cluster.close()
    assert results[0].history == results[1].history


def test_bad_run_settings_raise_before_any_evaluation():
    """Swarm size, iterations, seed and stop point are checked up front (TypeError for a wrong type, ValueError out
    of range, each naming the parameter), before anything is evaluated or written."""
    calls = []

    def evaluate(x, state):
        calls.append(x)
        return quadratic(x, state)

    base = dict(n=4, lower=[0.0], upper=[1.0], iterations=3, seed=0)
    for name, bad, error in (("iterations", 0, ValueError), ("iterations", -1, ValueError), ("iterations", 2.0, TypeError),
                             ("seed", -1, ValueError), ("seed", "x", TypeError), ("n", 1, ValueError), ("n", 2.5, TypeError),
                             ("stop_after", -1, ValueError), ("stop_after", 1.5, TypeError)):
        with pytest.raises(error, match=name):
            pso.run(evaluate, **{**base, name: bad})
    assert not calls


def test_codesign_checks_its_design_range_before_starting(tmp_path):
    """h_range must be (low, high) in metres with 0 < low < high, inside the parameters' design range: a negative,
    reversed or too wide range is refused before any model is built and before the checkpoint is written."""
    ck = tmp_path / "ck.json"
    for bad in ((-0.01, 0.03), (0.0, 0.03), (0.03, 0.015), (0.015, float("nan")), (0.015,), "0.015-0.03"):
        with pytest.raises((ValueError, TypeError), match="h_range"):
            codesign.run_codesign(n_particles=2, n_iterations=1, h_range=bad, checkpoint=ck, progress=False)
    with pytest.raises(ValueError, match="leaves the design range"):  # models_at would refuse every particle
        codesign.run_codesign(n_particles=2, n_iterations=1, h_range=(0.01, 0.03), checkpoint=ck, progress=False)
    with pytest.raises(ValueError, match="n_particles"):
        codesign.run_codesign(n_particles=1, n_iterations=1, checkpoint=ck, progress=False)
    with pytest.raises(ValueError, match="n_iterations"):
        codesign.run_codesign(n_particles=2, n_iterations=0, checkpoint=ck, progress=False)
    for bad in ([], [0.02, -0.01], [0.02, float("inf")]):  # the dense grid of notebook 07
        with pytest.raises(ValueError, match="hs must be"):
            codesign.evaluate_grid(bad, cache=ck, progress=False)
    assert not ck.exists()


def test_objective_and_failures():
    m0 = codesign.M0_PAPER
    assert codesign.objective_value(93.55, 0.9011, m0) == pytest.approx(93.55 / m0 + 0.0011)
    assert codesign.objective_value(50.0, 2.5, m0) == pytest.approx(50.0 / m0 + 10)
    assert codesign.objective_value(50.0, np.inf, m0) == pytest.approx(50.0 / m0 + 10)
    r = codesign.evaluate_particle(0.02, fail=True)
    assert r["status"].startswith("failed: RuntimeError") and r["f"] == pytest.approx(r["mass"] / m0 + 10)
    assert codesign.objective_value(50.0, np.nan, m0) == pytest.approx(50.0 / m0 + 10)
    for mass, j_c, m in ((50.0, 0.1, 0.0), (np.nan, 0.1, m0), (-5.0, 0.1, m0), (50.0, -0.1, m0)):
        with pytest.raises(ValueError, match="mass|m0|j_c"):
            codesign.objective_value(mass, j_c, m)
    bad = codesign.evaluate_particle(-0.02)  # never raises: a failed particle with an infinite objective
    assert bad["status"].startswith("failed: ValueError") and bad["f"] == np.inf
    # a PSO run in which one particle fails keeps going and records it
    def evaluate(x, state):
        out = quadratic(x, state)
        out[1] = {"f": np.inf, "status": "failed: injected"}
        return out

    state = pso.run(evaluate, n=4, lower=[0.0], upper=[1.0], iterations=3, seed=0)
    assert state.iteration == 3 and sum(r.get("status", "") == "failed: injected" for r in state.history) == 3
    assert np.isfinite(state.g_f)


def test_particles_at_the_same_h_share_one_evaluation(monkeypatch):
    calls = []

    def fake(h, gain0=None, fail=False, **kw):
        calls.append((h, fail))
        return {"h": h, "f": h + fail, "gain": None, "scenarios": kw.get("scenarios0")}

    monkeypatch.setattr(codesign, "evaluate_particle", fake)
    out = codesign.evaluate_swarm([0.015, 0.02, 0.015, 0.015], None, fail_particles=[3], progress=False,
                                  scenarios0=[[0.0, 0.0, 0.0, 1.0]])
    assert calls == [(0.015, False), (0.02, False), (0.015, True)]  # a particle with an injected failure is not shared
    assert [r["f"] for r in out] == [0.015, 0.02, 0.015, 1.015]
    assert out[2]["shared_with"] == 0 and "shared_with" not in out[0] and "shared_with" not in out[3]
    assert out[1]["scenarios"] == [[0.0, 0.0, 0.0, 1.0]]  # the warm-start scenario set reaches the evaluation


def test_checkpoint_keeps_non_finite_values(tmp_path):
    def evaluate(x, state):
        return [{"f": np.inf if i == 0 else float(xi[0]), "J_c": np.inf if i == 0 else 0.1} for i, xi in enumerate(x)]

    ck = tmp_path / "state.json"
    a = pso.run(evaluate, n=3, lower=[0.0], upper=[1.0], iterations=2, seed=0, checkpoint=ck)
    b = pso.load_state(ck)
    assert b.history[0]["J_c"] == np.inf and isinstance(b.history[0]["J_c"], float)
    assert b.history == a.history


def test_codesign_refuses_a_checkpoint_of_another_synthesis(tmp_path, monkeypatch):
    """A swarm checkpoint records the synthesis version and options; resuming it with another would mix results."""
    def fake(h, gain0=None, fail=False, **kw):
        return {"h": h, "f": h, "J_c": 0.1, "gain": None, "scenarios": None, "status": "ok"}

    monkeypatch.setattr(codesign, "evaluate_particle", fake)
    ck = tmp_path / "state.json"
    codesign.run_codesign(2, 2, seed=0, checkpoint=ck, progress=False, log=lambda s: None, stop_after=1)
    assert pso.load_state(ck).extra["algorithm"] == synthesis.ALGORITHM
    codesign.run_codesign(2, 2, seed=0, checkpoint=ck, progress=False, log=lambda s: None)  # same version: resumes
    with pytest.raises(ValueError, match="synthesis options"):  # e.g. a dense run resumed by the fast path
        codesign.run_codesign(2, 2, seed=0, checkpoint=ck, progress=False, log=lambda s: None,
                              synthesis_options={"tol": 1e-2, "fast": True})
    monkeypatch.setattr(synthesis, "ALGORITHM", "another version")
    with pytest.raises(ValueError, match="delete it"):
        codesign.run_codesign(2, 2, seed=0, checkpoint=ck, progress=False, log=lambda s: None)


def test_codesign_refuses_a_checkpoint_of_another_objective_and_normalises_options(tmp_path, monkeypatch):
    """Settings, parameters and m0 are recorded (a resume with another m0 was accepted, mixing two objectives); options
    equal once stored as JSON (a tuple and its list, None and the default) are the same options."""
    def fake(h, gain0=None, fail=False, **kw):
        return {"h": h, "f": h, "J_c": 0.1, "gain": None, "scenarios": None, "status": "ok"}

    monkeypatch.setattr(codesign, "evaluate_particle", fake)
    ck = tmp_path / "state.json"
    opts = {"tol": 1e-2, "search_thetas_deg": (0.0, 90.0, 180.0)}
    run = dict(seed=0, checkpoint=ck, progress=False, log=lambda s: None)
    codesign.run_codesign(2, 3, stop_after=1, synthesis_options=opts, **run)
    codesign.run_codesign(2, 3, stop_after=2, synthesis_options={**opts, "search_thetas_deg": [0.0, 90.0, 180.0]}, **run)
    for change in ({"m0": 100.0}, {"settings": LoopSettings.from_parameters(t_delta=0.03)}):
        with pytest.raises(ValueError, match="another objective"):
            codesign.run_codesign(2, 3, synthesis_options=opts, **run, **change)
    with pytest.raises(ValueError, match="m0"):  # checked before any evaluation
        codesign.run_codesign(2, 3, m0=-1.0, seed=0, progress=False, log=lambda s: None)
    ck2 = tmp_path / "default.json"
    codesign.run_codesign(2, 2, seed=0, checkpoint=ck2, progress=False, log=lambda s: None, stop_after=1)
    codesign.run_codesign(2, 2, seed=0, checkpoint=ck2, progress=False, log=lambda s: None,
                          synthesis_options=dict(codesign.SYNTHESIS_OPTIONS))  # None means the default options


def test_a_failed_synthesis_never_becomes_the_warm_start(monkeypatch):
    starts = []

    def fake(h, gain0=None, fail=False, **kw):
        starts.append(None if gain0 is None else np.asarray(gain0).tolist())
        good = gain0 is None  # the first (cold) iteration succeeds, every warm one fails (with a gain)
        return {"h": h, "f": h if good else h + 10, "J_c": 0.1 if good else np.inf, "scenarios": None,
                "gain": [[1.0]] if good else [[-99.0]], "status": "ok" if good else "failed: not a valid design"}

    monkeypatch.setattr(codesign, "evaluate_particle", fake)
    codesign.run_codesign(2, 3, seed=0, progress=False, log=lambda s: None)
    warm = [g for g in starts if g is not None]
    assert len(warm) >= 2 and all(g == [[1.0]] for g in warm)  # the third iteration started from [[-99.0]], a failed gain


def test_grid_resumes_after_an_interruption(tmp_path, monkeypatch):
    """The grid is saved after every chunk: an interrupted run loses at most its current chunk, and the resumed
    grid equals an uninterrupted one; another key recomputes everything."""
    calls, broken = [], {"at": 0.023}

    def fake(h, gain0=None, fail=False, **kw):
        if h == broken["at"]:
            raise RuntimeError("worker lost")
        calls.append(h)
        return {"h": h, "f": 2 * h, "J_c": np.inf if h == 0.021 else 0.1, "gain": [[h]], "scenarios": None}

    monkeypatch.setattr(codesign, "evaluate_particle", fake)
    hs = [0.020, 0.021, 0.022, 0.023, 0.024]
    cache, key = tmp_path / "grid.json", {"h": hs, "settings": {"t_delta": 0.003}}
    with pytest.raises(RuntimeError):
        codesign.evaluate_grid(hs, cache=cache, key=key, chunk=2, progress=False)
    assert calls == [0.020, 0.021, 0.022]  # chunk (0.022, 0.023) was interrupted
    broken["at"] = None
    records, _ = codesign.evaluate_grid(hs, cache=cache, key=key, chunk=2, progress=False)
    assert calls[3:] == [0.022, 0.023, 0.024]  # only the missing points
    assert [r["f"] for r in records] == [2 * h for h in hs] and records[1]["J_c"] == np.inf
    again, _ = codesign.evaluate_grid(hs, cache=cache, key=key, chunk=2, progress=False)
    assert again == records and len(calls) == 6  # complete: read back, nothing evaluated
    codesign.evaluate_grid(hs, cache=cache, key={**key, "settings": {"t_delta": 0.03}}, chunk=2, progress=False)
    assert len(calls) == 11  # another key: all recomputed


def test_grid_cache_of_other_points_is_refused_and_shared_rows_are_the_grids(tmp_path, monkeypatch):
    def fake(h, gain0=None, fail=False, **kw):
        return {"h": h, "f": h, "J_c": 0.1, "gain": None, "scenarios": None}

    monkeypatch.setattr(codesign, "evaluate_particle", fake)
    cache = tmp_path / "grid.json"
    codesign.evaluate_grid([0.02, 0.025], cache=cache, key={"mine": 1}, progress=False)
    with pytest.raises(ValueError, match="other h"):  # same key, other points: was returned as the grid's records
        codesign.evaluate_grid([0.015, 0.03], cache=cache, key={"mine": 1}, progress=False)
    cache2 = tmp_path / "grid2.json"
    codesign.evaluate_grid([0.02, 0.025], cache=cache2, progress=False)
    records, _ = codesign.evaluate_grid([0.015, 0.03], cache=cache2, progress=False)  # default key names the grid
    assert [r["h"] for r in records] == [0.015, 0.03]
    records, _ = codesign.evaluate_grid([0.02, 0.021, 0.022, 0.023, 0.024, 0.024], chunk=4, progress=False)
    assert records[5]["shared_with"] == 4  # was 0, an index within the second chunk


def test_codesign_interrupted_inside_an_iteration_loses_no_finished_particle(tmp_path, monkeypatch):
    """Particles finished before an interruption are kept (a partial file next to the checkpoint) and not evaluated
    again on resume; the resumed run ends as an uninterrupted one."""
    calls, broken = [], {"at": None}

    def fake(h, gain0=None, fail=False, **kw):
        if h == broken["at"]:
            raise RuntimeError("killed")
        calls.append(h)
        return {"h": h, "f": (h - 0.021) ** 2, "J_c": 0.1, "gain": [[h]], "scenarios": None, "status": "ok"}

    monkeypatch.setattr(codesign, "evaluate_particle", fake)
    quiet = dict(progress=False, log=lambda s: None)
    ref = codesign.run_codesign(4, 3, seed=1, checkpoint=tmp_path / "ref.json", **quiet)
    n_ref = len(calls)
    second = [r["h"] for r in ref.history if r["iteration"] == 1]
    calls.clear()
    ck = tmp_path / "state.json"
    broken["at"] = second[2]  # the third particle of the second iteration
    with pytest.raises(RuntimeError, match="killed"):
        codesign.run_codesign(4, 3, seed=1, checkpoint=ck, **quiet)
    assert calls[-2:] == second[:2]
    broken["at"] = None
    before = len(calls)
    out = codesign.run_codesign(4, 3, seed=1, checkpoint=ck, **quiet)
    assert calls[before:before + 2] == second[2:]  # the resumed iteration evaluates only the missing particles
    assert len(calls) == n_ref
    assert [r["f"] for r in out.history] == [r["f"] for r in ref.history] and out.g_f == ref.g_f
    assert not codesign.partial_path(ck).exists()  # removed once its iteration is in the checkpoint


def test_evaluate_swarm_through_a_separately_started_scheduler(tmp_path):
    """The cluster path of notebook 07 (``scheduler_address``): a scheduler and a worker started as their own processes,
    as dask-jobqueue or ``dask scheduler`` / ``dask worker`` would on a cluster, reached by address. The particles
    (failures injected, so that each evaluation is quick but runs the real ``evaluate_particle`` on the worker) come
    back as from a serial evaluation."""
    import subprocess
    import sys
    import time

    pytest.importorskip("dask.distributed")
    sched_file = tmp_path / "scheduler.json"
    procs = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0",
                               "--no-dashboard", "--scheduler-file", str(sched_file)],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        for _ in range(300):
            if sched_file.exists() and sched_file.stat().st_size:
                break
            time.sleep(0.1)
        import json

        address = json.loads(sched_file.read_text())["address"]
        procs.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--nthreads", "1",
                                       "--no-dashboard"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        client = codesign.local_client(scheduler=address)
        try:
            client.wait_for_workers(1, timeout=60)
            hs = [0.015, 0.02, 0.015, 0.03]
            remote = codesign.evaluate_swarm(hs, None, client, fail_particles=[0, 1, 2, 3], progress=False)
        finally:
            client.close()
        local = codesign.evaluate_swarm(hs, None, None, fail_particles=[0, 1, 2, 3], progress=False)
        timing = {"t_model", "t_build", "t_reduction", "t_synthesis", "t_total", "traceback"}
        strip = [{k: v for k, v in r.items() if k not in timing} for r in remote]
        assert strip == [{k: v for k, v in r.items() if k not in timing} for r in local]
        assert [r["status"] for r in remote] == ["failed: RuntimeError: injected failure (test)"] * 4
        assert [r["mass"] for r in remote] == [r["mass_check"] for r in remote] and remote[0]["mass"] < remote[3]["mass"]
    finally:
        for p in procs[::-1]:
            p.terminate()
            p.wait(timeout=30)


def test_local_workers_keep_glibc_dynamic_mmap_threshold():
    """Dask's nanny would start the workers with MALLOC_TRIM_THRESHOLD_ set, which pins glibc's mmap threshold and made
    a fast-path synthesis twice as slow in a worker as in a plain process (measured: 33.3 s against 16.8 s)."""
    import os

    pytest.importorskip("dask.distributed")
    client = codesign.local_client(1)
    try:
        env = client.run(lambda: os.environ.get("MALLOC_TRIM_THRESHOLD_"))
        blas = client.run(lambda: os.environ.get("OPENBLAS_NUM_THREADS"))
    finally:
        client.close()
        client.cluster.close()
    assert list(env.values()) == [None]
    assert list(blas.values()) == ["1"]
