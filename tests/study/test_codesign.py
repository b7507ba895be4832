"""The co-design: its objective and penalties, the grid and the swarm on Dask, checkpoints, caches and their keys."""

import json
import re

import numpy as np
import pytest
from _locks import held_elsewhere, hold_lock
from trusscodesign.control import synthesis
from trusscodesign.control.closedloop import LoopSettings
from trusscodesign.study import cluster, codesign, objective, pso


@pytest.mark.parametrize("options, error", [({"tol": 1e-2}, TypeError), ("fast", TypeError)])
def test_codesign_checks_synthesis_options_before_any_particle(monkeypatch, options, error):
    def never(*args, **kwargs):
        raise AssertionError("a particle was evaluated")

    monkeypatch.setattr(codesign, "evaluate_particle", never)
    for run in (lambda: codesign.run_codesign(2, 1, synthesis_options=options, progress=False, log=lambda s: None),
                lambda: codesign.evaluate_grid([0.02], synthesis_options=options, progress=False)):
        with pytest.raises(error):
            run()
    codesign._check_synthesis_options(synthesis.SynthesisOptions(tol=1e-2, fast=True, restarts=1, search_thetas_deg=(0.0, 90.0)))
    codesign._check_synthesis_options(None)


@pytest.mark.parametrize("hs, kwargs, match", [([1.5, 3.0], {}, "design range"), ([0.02], {"m0": -1.0}, "m0")])
def test_grid_and_swarm_check_h_and_m0_before_any_particle(monkeypatch, hs, kwargs, match):
    def never(*args, **kw):
        raise AssertionError("a particle was evaluated")

    monkeypatch.setattr(codesign, "evaluate_particle", never)
    with pytest.raises(ValueError, match=match):  # h in cm: every point failed with a finite f; m0: after each synthesis
        codesign.evaluate_grid(hs, progress=False, **kwargs)
    with pytest.raises(ValueError, match=match):
        codesign.evaluate_swarm(hs, None, progress=False, **kwargs)


@pytest.mark.parametrize("h_min, h_max, n_particles, match", [
    (0.015, 0.025, 0, r"n_particles must be an integer in \[2, inf\), got 0"),
    (0.025, 0.02, 24, r"h_min = 0.025 m must be below h_max = 0.02 m"),
    (0.02, 0.02, 24, r"h_min = 0.02 m must be below h_max = 0.02 m"),
    (1.5, 3.0, 24, r"h_min = 1.5 m must lie in the design range \[0.015, 0.03\] m .*in centimetres\? 1.5 cm is 0.015 m"),
    (0.015, 0.04, 24, r"h_max = 0.04 m must lie in the design range"),
])
def test_a_codesign_study_is_checked_before_any_model(h_min, h_max, n_particles, match):
    """Notebook 07's range and sizes (an empty AssertionError, or an error only after the grid, before)."""
    with pytest.raises(ValueError, match=match):
        codesign.check_study(h_min, h_max, n_particles, 20, 31)


def test_a_codesign_range_given_as_text_names_the_parameter_and_unit():
    with pytest.raises(TypeError, match=r"h_min must be a real number \[m\], got str '2cm'"):
        codesign.check_study("2cm", 0.03, 24, 20, 31)
    codesign.check_study(0.02, 0.025, 24, 20, 31)  # a new range inside the design range is fine


def quadratic(x, state):
    return [{"f": float((xi[0] - 0.3) ** 2 + 0.1 * np.sin(20 * xi[0]) ** 2)} for xi in x]


def cheap(h):
    return {"h": h, "f": float(np.cos(40 * h) + h)}


def _poisoned(h, gain0=None, fail=False, **kw):
    """An evaluation that kills its worker process at h = 2.22 cm, and returns a plain record elsewhere."""
    import os

    if abs(h - 0.0222) < 1e-12:
        os._exit(3)
    return {"h": h, "f": h, "J_c": 0.1, "gain": None, "scenarios": None, "status": "ok"}


def test_same_result_with_one_and_two_dask_workers():
    pytest.importorskip("dask.distributed")
    results = []
    for n_workers in (1, 2):
        client = cluster.local_client(n_workers)
        try:
            def evaluate(x, state, client=client):
                return client.gather(client.map(cheap, [float(v[0]) for v in x], pure=False))

            results.append(pso.run(evaluate, n=4, lower=[0.015], upper=[0.03], iterations=4, seed=3))
        finally:
            client.close()
            client.cluster.close()
    assert results[0].history == results[1].history


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
    m0 = objective.M0_PAPER
    assert objective.objective_value(93.55, 0.9011, m0) == pytest.approx(93.55 / m0 + 0.0011)
    assert objective.objective_value(50.0, 2.5, m0) == pytest.approx(50.0 / m0 + 10)
    assert objective.objective_value(50.0, np.inf, m0) == pytest.approx(50.0 / m0 + 10)
    r = objective.evaluate_particle(0.02, fail=True)
    assert r["status"].startswith("failed: RuntimeError") and r["f"] == pytest.approx(r["mass"] / m0 + 10)
    assert objective.objective_value(50.0, np.nan, m0) == pytest.approx(50.0 / m0 + 10)
    for mass, j_c, m in ((50.0, 0.1, 0.0), (np.nan, 0.1, m0), (-5.0, 0.1, m0), (50.0, -0.1, m0)):
        with pytest.raises(ValueError, match="mass|m0|j_c"):
            objective.objective_value(mass, j_c, m)
    bad = objective.evaluate_particle(-0.02)  # never raises: a failed particle with an infinite objective
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
                              synthesis_options=objective.synthesis_options(fast=True))
    monkeypatch.setattr(synthesis, "ALGORITHM", "another version")
    with pytest.raises(ValueError, match="delete it"):
        codesign.run_codesign(2, 2, seed=0, checkpoint=ck, progress=False, log=lambda s: None)


def test_codesign_refuses_a_checkpoint_of_another_objective_and_normalises_options(tmp_path, monkeypatch):
    """Settings, parameters and m0 are recorded (a resume with another m0 was accepted, mixing two objectives); equal
    options are the same options (a tuple of angles and its list, None and the default)."""
    def fake(h, gain0=None, fail=False, **kw):
        return {"h": h, "f": h, "J_c": 0.1, "gain": None, "scenarios": None, "status": "ok"}

    monkeypatch.setattr(codesign, "evaluate_particle", fake)
    ck = tmp_path / "state.json"
    opts = synthesis.SynthesisOptions(tol=1e-2, search_thetas_deg=(0.0, 90.0, 180.0))
    run = dict(seed=0, checkpoint=ck, progress=False, log=lambda s: None)
    codesign.run_codesign(2, 3, stop_after=1, synthesis_options=opts, **run)
    codesign.run_codesign(2, 3, stop_after=2, synthesis_options=opts.replace(search_thetas_deg=[0.0, 90.0, 180.0]), **run)
    for change in ({"m0": 100.0}, {"settings": LoopSettings.from_parameters(t_delta=0.03)}):
        with pytest.raises(ValueError, match="another objective"):
            codesign.run_codesign(2, 3, synthesis_options=opts, **run, **change)
    with pytest.raises(ValueError, match="m0"):  # checked before any evaluation
        codesign.run_codesign(2, 3, m0=-1.0, seed=0, progress=False, log=lambda s: None)
    ck2 = tmp_path / "default.json"
    codesign.run_codesign(2, 2, seed=0, checkpoint=ck2, progress=False, log=lambda s: None, stop_after=1)
    codesign.run_codesign(2, 2, seed=0, checkpoint=ck2, progress=False, log=lambda s: None,
                          synthesis_options=objective.CODESIGN_OPTIONS)  # None means the default options


def test_synthesis_options_keep_the_stored_runs_keys():
    """The co-design's options plus only what differs, as keys: those the box-only runs (None), the stored ball runs
    and the benchmarks were written with; the stored checkpoints and caches of notebook 07 hold notebook 07's."""
    from trusscodesign.infra import paths

    assert codesign._options_key(None) == objective.synthesis_options().key() == {"tol": 1e-2}
    assert objective.synthesis_options(fast=True).key() == {"tol": 1e-2, "fast": True}
    assert objective.synthesis_options(True, "ball").key() == {"tol": 1e-2, "fast": True, "trust_region": "ball"}
    assert objective.synthesis_options(trust_region="ball").key() == {"tol": 1e-2, "trust_region": "ball"}
    notebook_07 = objective.synthesis_options(True, "ball", "least_change")
    assert notebook_07.key() == {"tol": 1e-2, "fast": True, "trust_region": "ball", "restoration": "least_change"}
    stored = paths.ROOT / "data" / "results"
    assert pso.load_state(stored / "07_pso_checkpoint_paper_calibrated.json").extra["options"] == notebook_07.key()
    assert json.loads((stored / "07_grid.json").read_text())["key"]["synthesis"] == notebook_07.key()
    evaluations = json.loads((stored / "07_pso_checkpoint_paper_calibrated.evaluations.json").read_text())["key"]
    assert evaluations["options"] == codesign.evaluation_key(None, None, synthesis_options=notebook_07)["options"]
    with pytest.raises(ValueError, match="trust_region must be 'box' or 'ball'"):  # the learnt metric, removed
        objective.synthesis_options(True, "bfgs", "least_change")
    with pytest.raises(ValueError, match="restoration"):
        objective.synthesis_options(restoration="least-change")
    with pytest.raises(ValueError, match="trust_region"):
        objective.synthesis_options(trust_region="ellipse")


def test_default_settings_given_or_not_are_the_same_objective(tmp_path, monkeypatch):
    """``settings=None`` is what the synthesis then takes, the data file's settings: a run started with None resumes with
    those settings given explicitly (a notebook passes them) and the other way round, also from a checkpoint that stored
    None (written before 2026-12-05); other settings are still another objective."""
    import json

    def fake(h, gain0=None, fail=False, **kw):
        return {"h": h, "f": h, "J_c": 0.1, "gain": None, "scenarios": None, "status": "ok"}

    monkeypatch.setattr(codesign, "evaluate_particle", fake)
    run = dict(seed=0, progress=False, log=lambda s: None)
    explicit = LoopSettings.from_parameters()
    for first, then in ((None, explicit), (explicit, None)):
        ck = tmp_path / f"state_{first is None}.json"
        codesign.run_codesign(2, 3, checkpoint=ck, settings=first, stop_after=1, **run)
        assert codesign.run_codesign(2, 3, checkpoint=ck, settings=then, **run).iteration == 3
    old = tmp_path / "old.json"
    codesign.run_codesign(2, 3, checkpoint=old, stop_after=1, **run)
    state = json.loads(old.read_text())
    state["extra"]["objective"]["settings"] = None  # as checkpoints stored settings=None before
    old.write_text(json.dumps(state))
    assert codesign.run_codesign(2, 3, checkpoint=old, settings=explicit, **run).iteration == 3
    other = tmp_path / "other.json"
    codesign.run_codesign(2, 3, checkpoint=other, stop_after=1, **run)
    with pytest.raises(ValueError, match="another objective"):
        codesign.run_codesign(2, 3, checkpoint=other, settings=explicit.replace(t_delta=0.03), **run)


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
        client = cluster.local_client(scheduler=address)
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


def test_m0_is_the_papers_truss_mass_at_3_cm():
    """Paper: "the initial design having m0 = 183.11 kg" (and Table: 183.11)."""
    assert objective.M0_PAPER == 183.11


def test_objective_at_the_jc_limit_is_not_penalised():
    """Paper: f^n = m/m0 + |0.9 - J_c| if J_c <= 2 (the limit included), else m/m0 + 10."""
    m0 = objective.M0_PAPER
    assert objective.objective_value(50.0, 2.0, m0) == pytest.approx(50.0 / m0 + 1.1)
    assert objective.objective_value(50.0, np.nextafter(2.0, 3.0), m0) == pytest.approx(50.0 / m0 + 10)
    assert objective.objective_value(50.0, 0.0, m0) == pytest.approx(50.0 / m0 + 0.9)


def test_particle_with_jc_at_the_limit_is_ok_and_above_is_penalised(monkeypatch):
    """evaluate_particle with stand-in models and synthesis: J_c = 2 is "ok" with f = m/m0 + 1.1; J_c > 2 is penalised."""
    from trusscodesign.model import spacecraft
    from trusscodesign.study import design

    jc = {"v": 2.0}
    monkeypatch.setattr(design, "models_at", lambda h, params=None: design.DesignModels(h, None, None, None, np.eye(3), 0.0, 0.0))
    monkeypatch.setattr(objective, "truss_mass_from_dc", lambda models, p=None: spacecraft.truss_mass(models.h))
    monkeypatch.setattr(design, "robust_design", lambda models, settings, options, **kw: synthesis.SynthesisResult(
        -np.ones((4, 8)), jc["v"], 0.5, True, "converged", [], None, 1, 0.0, 1))
    r = objective.evaluate_particle(0.02)
    m = spacecraft.truss_mass(0.02)
    assert r["status"] == "ok" and r["f"] == pytest.approx(m / objective.M0_PAPER + 1.1)
    jc["v"] = 2.5
    r = objective.evaluate_particle(0.02)
    assert r["status"] == "penalty: J_c > 2" and r["f"] == pytest.approx(m / objective.M0_PAPER + 10)


@pytest.mark.parametrize("error", [np.linalg.LinAlgError("singular matrix"), ZeroDivisionError("x"), RuntimeError("no convergence")])
def test_a_numerical_failure_is_a_penalised_particle(monkeypatch, error):
    from trusscodesign.model import spacecraft
    from trusscodesign.study import design

    def fails(h, params=None):
        raise error

    monkeypatch.setattr(design, "models_at", fails)
    r = objective.evaluate_particle(0.02)
    assert r["status"].startswith(f"failed: {type(error).__name__}") and "traceback" in r
    assert r["f"] == pytest.approx(spacecraft.truss_mass(0.02) / objective.M0_PAPER + 10)


@pytest.mark.parametrize("error", [TypeError("bad call"), NameError("x"), AttributeError("x"), KeyError("x"), NotImplementedError("x")])
def test_a_programming_error_stops_the_evaluation_with_its_traceback(monkeypatch, error):
    """Only numerics are penalised: a TypeError and the like raise, so a bug does not show as failed particles."""
    from trusscodesign.study import design

    def broken(h, params=None):
        raise error

    monkeypatch.setattr(design, "models_at", broken)
    with pytest.raises(type(error)):
        objective.evaluate_particle(0.02)


def test_a_lost_evaluation_is_penalised_as_documented_and_a_bad_h_is_an_error():
    from trusscodesign.model import spacecraft

    r = objective.lost_evaluation(0.02, "killed its worker")
    assert r["status"] == "failed: killed its worker"
    assert r["f"] == pytest.approx(spacecraft.truss_mass(0.02) / objective.M0_PAPER + 10)  # the documented penalty, finite
    with pytest.raises(ValueError, match="h"):
        objective.lost_evaluation(-0.02, "killed its worker")


def test_warm_start_is_the_gain_of_the_iterations_best_particle(monkeypatch):
    """Step 3: the synthesis is warm-started from the previous iteration's best particle (lowest f^n), not any other."""
    starts = []

    def fake(h, gain0=None, fail=False, **kw):
        starts.append(None if gain0 is None else float(np.asarray(gain0)[0, 0]))
        return {"h": h, "f": (h - 0.021) ** 2, "J_c": 0.1, "gain": [[h]], "scenarios": [[h, 0.0, 0.0, 0.0]], "status": "ok"}

    def log(s):
        pass

    monkeypatch.setattr(codesign, "evaluate_particle", fake)
    state = codesign.run_codesign(6, 2, seed=4, progress=False, log=log)
    first = [r for r in state.history if r["iteration"] == 0]
    best_h = min(first, key=lambda r: r["f"])["h"]
    assert starts[:6] == [None] * 6
    assert set(starts[6:]) == {best_h}


def test_truss_mass_from_the_inverted_dc_gain_with_an_offset_cog():
    """The DC gain W_P1 -> a_P1 is the inverse of the rigid mass matrix at P1 (CoG away from P1): its inverse's (1, 1)
    entry is the spacecraft mass, minus the hub, panels, antenna and PMAs gives the truss. A stand-in model whose DC
    gain is exactly that inverse (with dynamics: D - C A^-1 B) gives back the truss mass of rho h^2 L."""
    from types import SimpleNamespace

    from trusscodesign.model import spacecraft

    h = 0.02
    masses = spacecraft.component_masses(h)
    m = sum(masses.values())
    r = np.array([0.3, -0.8, 1.4])  # CoG offset from P1 [m]
    rx = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
    rigid = np.block([[m * np.eye(3), -m * rx], [m * rx, np.diag([900.0, 1100.0, 700.0]) - m * rx @ rx]])
    rng = np.random.default_rng(0)
    ni, no = len(spacecraft.INPUTS), len(spacecraft.OUTPUTS)
    a = -np.diag([2.0, 3.0, 5.0])
    b, c = rng.normal(size=(3, ni)), rng.normal(size=(no, 3))
    d = rng.normal(size=(no, ni)) + c @ np.linalg.solve(a, b)  # DC gain D - C A^-1 B = random + 0
    ii = [spacecraft.INPUTS.index(f"W_P1_{x}") for x in ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz")]
    oo = [spacecraft.OUTPUTS.index(f"a_P1_{x}") for x in ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz")]
    d[np.ix_(oo, ii)] = np.linalg.inv(rigid) + (c @ np.linalg.solve(a, b))[np.ix_(oo, ii)]
    g_r = SimpleNamespace(params={}, evaluate=lambda values: (a, b, c, d))
    got = objective.truss_mass_from_dc(SimpleNamespace(h=h, g_r=g_r))
    assert got == pytest.approx(masses["truss"], rel=1e-9)


def test_edited_parameters_refuse_the_stored_swarm_and_recompute_the_grid(tmp_path, monkeypatch):
    """The silent wrong result of a rerun after editing parameters.json: the swarm's checkpoint is refused with a message
    naming the parameters (a checkpoint written before the fingerprint, with none, too), and the grid is recomputed."""
    from trusscodesign.model import spacecraft

    def fake(h, gain0=None, fail=False, **kw):
        return {"h": h, "f": h, "J_c": 0.1, "gain": None, "scenarios": None, "status": "ok"}

    monkeypatch.setattr(codesign, "evaluate_particle", fake)
    run = dict(seed=0, progress=False, log=lambda s: None)
    edited = json.loads(json.dumps(spacecraft.load_parameters()))
    edited["hub"]["mass"] = 400.0
    ck = tmp_path / "07_pso_checkpoint.json"
    codesign.run_codesign(2, 3, checkpoint=ck, stop_after=1, **run)
    with pytest.raises(ValueError, match=r"another objective \(the spacecraft parameters \(their fingerprint\): '[0-9a-f]{64}' stored"):
        codesign.run_codesign(2, 3, checkpoint=ck, params=edited, **run)
    state = json.loads(ck.read_text())
    state["extra"]["objective"]["params_sha256"] = None  # as checkpoints stored the package's parameters before
    ck.write_text(json.dumps(state))
    with pytest.raises(ValueError, match=r"the spacecraft parameters \(their fingerprint\): None stored"):
        codesign.run_codesign(2, 3, checkpoint=ck, **run)
    # notebook 07's choice: the stale checkpoint is set aside (kept as it was) and the swarm recomputed, saying why
    stale, logged = ck.read_bytes(), []
    state = codesign.run_codesign(2, 3, checkpoint=ck, params=edited, on_stale="restart", **dict(run, log=logged.append))
    assert state.iteration == 3 and len(state.history) == 6  # every iteration evaluated afresh
    assert (tmp_path / "07_pso_checkpoint.stale.json").read_bytes() == stale
    assert re.search(r"set aside as 07_pso_checkpoint.stale.json, and the swarm starts afresh: it was computed for another "
                     r"objective \(the spacecraft parameters \(their fingerprint\): None stored", logged[0]), logged[0]
    assert json.loads(ck.read_text())["extra"]["objective"]["params_sha256"] == spacecraft.parameters_fingerprint(edited)
    with pytest.raises(ValueError, match=r"from another swarm \(n_particles=2, seed=0"):  # another swarm on the same file
        codesign.run_codesign(3, 3, checkpoint=ck, params=edited, **run)
    with pytest.raises(ValueError, match="on_stale must be 'refuse' or 'restart'"):
        codesign.run_codesign(2, 3, checkpoint=ck, on_stale="recompute", **run)

    evaluated = []

    def swarm(hs, *args, **kwargs):
        evaluated.extend(hs)
        return [fake(h) for h in hs]

    monkeypatch.setattr(codesign, "evaluate_swarm", swarm)
    hs, settings, cache = [0.02, 0.025], LoopSettings.from_parameters(), tmp_path / "07_grid.json"
    codesign.evaluate_grid(hs, None, settings, cache=cache, key=codesign.grid_key(hs, settings))
    codesign.evaluate_grid(hs, None, settings, cache=cache, key=codesign.grid_key(hs, settings))  # read back
    assert evaluated == hs
    codesign.evaluate_grid(hs, None, settings, cache=cache, key=codesign.grid_key(hs, settings, params=edited))
    assert evaluated == hs + hs  # recomputed for the edited parameters


def test_a_second_run_on_the_same_folder_stops_at_once_naming_the_first(tmp_path, monkeypatch):
    """Two co-design runs on one results folder: the second stops before any evaluation with the first run's process and
    host in its message, and the first run's checkpoint and grid are untouched; a lock is free again once its run ended
    (also when it was killed: the operating system releases it)."""
    import multiprocessing as mp
    import os

    def fake(h, gain0=None, fail=False, **kw):
        return {"h": h, "f": h, "J_c": 0.1, "gain": None, "scenarios": None, "status": "ok"}

    monkeypatch.setattr(codesign, "evaluate_particle", fake)
    run = dict(seed=3, progress=False, log=lambda s: None)
    ck, grid = tmp_path / "07_pso_checkpoint.json", tmp_path / "07_grid.json"
    codesign.run_codesign(2, 3, checkpoint=ck, stop_after=1, **run)
    before = ck.read_bytes()
    ctx = mp.get_context("fork")
    for target in (ck, grid):
        with held_elsewhere(target) as holder:
            with pytest.raises(RuntimeError, match=rf"{target.name} is in use by another run \(process {holder.pid} on {os.uname().nodename}"):
                if target == ck:
                    codesign.run_codesign(2, 3, checkpoint=ck, **dict(run, seed=4))
                else:
                    codesign.evaluate_grid([0.02], None, LoopSettings.from_parameters(), cache=grid, key={"k": 1})
    assert ck.read_bytes() == before and not grid.exists()
    assert codesign.run_codesign(2, 3, checkpoint=ck, **run).iteration == 3  # the first run resumes once the other ended
    held = ctx.Event()
    killed = ctx.Process(target=hold_lock, args=(str(ck), held, ctx.Event()))
    killed.start()
    assert held.wait(30)
    killed.kill()
    killed.join(30)
    assert codesign.run_codesign(2, 3, checkpoint=ck, **run).iteration == 3  # no stale lock after a kill


def test_a_particle_that_kills_its_worker_is_a_failed_particle_not_the_end_of_the_run(tmp_path, monkeypatch):
    """Dask gives up on a task that killed its workers (KilledWorker), which ended the whole co-design and every resume.
    Now the particle is recorded as failed with its h and the reason, penalised (m(h)/m0 + 10), saved in the partial
    file, and a resume does not run it again."""
    import sys

    import cloudpickle
    import dask

    pytest.importorskip("dask.distributed")
    from trusscodesign.model import spacecraft

    monkeypatch.setattr(codesign, "evaluate_particle", _poisoned)
    cloudpickle.register_pickle_by_value(sys.modules[__name__])  # the workers run this module's function as it is here
    part, key = tmp_path / "07_pso_checkpoint.partial.json", {"iteration": 1}
    try:
        with dask.config.set({"distributed.scheduler.allowed-failures": 1}):
            client = cluster.local_client(1)
        try:
            recs = codesign.evaluate_swarm([0.02, 0.0222], None, client, progress=False, partial=part, partial_key=key)
        finally:
            cluster.close_client(client)
    finally:
        cloudpickle.unregister_pickle_by_value(sys.modules[__name__])
    assert recs[0]["status"] == "ok"
    lost = recs[1]
    assert lost["h"] == 0.0222 and lost["status"].startswith("failed: the evaluation ended its worker every time (KilledWorker")
    assert lost["f"] == pytest.approx(spacecraft.truss_mass(0.0222) / objective.M0_PAPER + 10) and lost["gain"] is None

    def never(*args, **kwargs):
        raise AssertionError("a saved evaluation was run again")

    monkeypatch.setattr(codesign, "evaluate_particle", never)
    again = codesign.evaluate_swarm([0.02, 0.0222], None, None, progress=False, partial=part, partial_key=key)
    assert [r["status"] for r in again] == [r["status"] for r in recs]


def test_a_cluster_whose_workers_all_died_stops_the_run_instead_of_hanging(monkeypatch):
    """A nanny that could not restart its worker on an overloaded machine left a co-design (and the test above) waiting
    for ever: the wait now gives up once the cluster has had no worker for cluster.WORKERLESS_S, saying what to do."""
    pytest.importorskip("dask.distributed")
    from dask.distributed import Client, LocalCluster

    monkeypatch.setattr(cluster, "WORKERLESS_S", 1.0)
    monkeypatch.setattr(cluster, "_POLL_S", 0.2)
    with LocalCluster(n_workers=0, processes=False, dashboard_address=None) as empty, Client(empty) as client:
        with pytest.raises(RuntimeError, match=r"the Dask cluster has had no worker for 1 s .* with 1 evaluations waiting: restart"):
            codesign.evaluate_swarm([0.02], None, client, progress=False)


def test_tolerance_shifts_are_the_ends_and_the_midpoints_of_the_tolerance():
    assert objective.tolerance_shifts(0.02) == (-0.02, -0.01, 0.01, 0.02)
    assert objective.tolerance_shifts(0) == ()
    for bad in (-0.01, 2.0, 0.2, True, "0.02", float("nan")):
        with pytest.raises(ValueError, match="truss_tolerance must be a relative section-side error"):
            objective.tolerance_shifts(bad)


def test_a_truss_tolerant_particle_is_synthesised_on_the_shifted_trusses(monkeypatch):
    """evaluate_particle with truss_tolerance builds the trusses at h (1 + s) for the four shifts and hands them to the
    synthesis as variants; without it, none (the paper's recipe)."""
    from types import SimpleNamespace

    from trusscodesign.study import design

    seen = {}
    models = SimpleNamespace(h=0.02, assembly_time_s=0.1, build_time_s=0.3)
    monkeypatch.setattr(design, "models_at", lambda h, params=None: models)
    monkeypatch.setattr(design, "truss_variants", lambda m, shifts, p=None: [("variant", s) for s in shifts])
    monkeypatch.setattr(objective, "truss_mass_from_dc", lambda m, p=None: codesign.spacecraft.truss_mass(0.02, p))

    def robust_design(m, settings, options, gain0=None, variants=(), scenarios=None, workers=None):
        seen["variants"] = list(variants)
        return SimpleNamespace(j_c=0.9, z_c=0.95, gain=-np.ones((4, 8)), iterations=3, scenarios=[], success=True, message="ok",
                               restarts=0, worst=None, time_s=1.0)

    monkeypatch.setattr(design, "robust_design", robust_design)
    rec = objective.evaluate_particle(0.02, truss_tolerance=0.02)
    assert rec["status"] == "ok" and seen["variants"] == [("variant", s) for s in (-0.02, -0.01, 0.01, 0.02)]
    assert rec["t_model"] >= rec["t_variants"] >= 0.0
    objective.evaluate_particle(0.02)
    assert seen["variants"] == []
    with pytest.raises(ValueError, match="truss_tolerance"):  # refused before any particle
        codesign.evaluate_swarm([0.02], None, truss_tolerance=0.5, progress=False)


def test_a_cold_started_swarm_evaluates_each_h_once_on_its_resolution_and_shares_with_the_grid(tmp_path, monkeypatch):
    """start="cold": every particle's synthesis starts from all gains at -1, h is rounded to h_resolution, every
    evaluation is kept (evaluations_path) and any later particle at that h, in the swarm or in a grid evaluated under
    evaluation_key, reuses it; a killed run resumes without evaluating a finished h again and ends as an uninterrupted
    one; a checkpoint of another start rule, resolution or tolerance is not resumed."""
    calls, broken = [], {"at": None}

    def fake(h, gain0=None, fail=False, scenarios0=None, truss_tolerance=0.0, **kw):
        assert gain0 is None and scenarios0 is None and truss_tolerance == 0.02
        if h == broken["at"]:
            raise RuntimeError("killed")
        calls.append(h)
        return {"h": h, "f": abs(h - 0.0213) + h, "J_c": 0.9, "gain": [[h]], "scenarios": None, "status": "ok"}

    monkeypatch.setattr(codesign, "evaluate_particle", fake)
    run = dict(seed=3, progress=False, log=lambda s: None, truss_tolerance=0.02, start="cold", h_resolution=1e-4)
    ref = codesign.run_codesign(6, 8, checkpoint=tmp_path / "ref.json", **run)
    hs = [r["h"] for r in ref.history]
    assert all(abs(h / 1e-4 - round(h / 1e-4)) < 1e-9 for h in hs)
    assert sorted(calls) == sorted(set(hs)) and len(set(hs)) < len(hs)  # one evaluation per h, shared across iterations
    store = json.loads(codesign.evaluations_path(tmp_path / "ref.json").read_text())
    assert store["key"] == json.loads(json.dumps(codesign.evaluation_key(None, None, synthesis_options=None, truss_tolerance=0.02)))
    assert len(store["records"]) == len(set(hs))

    # a grid under the same key reads the swarm's evaluations and adds its own
    calls.clear()
    grid = [0.015, hs[0], 0.03]
    recs = codesign.evaluate_swarm(grid, None, progress=False, truss_tolerance=0.02, partial=codesign.evaluations_path(tmp_path / "ref.json"),
                                   partial_key=codesign.evaluation_key(None, None, truss_tolerance=0.02))
    assert [r["h"] for r in recs] == grid and sorted(calls) == sorted(set(grid) - set(hs))

    # killed inside the fourth iteration: the rerun evaluates only what was not finished
    calls.clear()
    ck = tmp_path / "state.json"
    fourth = [r["h"] for r in ref.history if r["iteration"] == 3]
    new = [h for h in dict.fromkeys(fourth) if h not in {r["h"] for r in ref.history if r["iteration"] < 3}]
    assert len(new) >= 2
    broken["at"] = new[1]
    with pytest.raises(RuntimeError, match="killed"):
        codesign.run_codesign(6, 8, checkpoint=ck, **run)
    done = list(calls)
    broken["at"] = None
    out = codesign.run_codesign(6, 8, checkpoint=ck, **run)
    assert len(calls) == len(set(calls)) == len(set(hs))  # nothing evaluated twice over the two calls
    assert done and set(calls[len(done):]).isdisjoint(done)
    assert out.history == ref.history and out.g_f == ref.g_f
    for change in ({"start": "previous_best"}, {"h_resolution": 1e-5}, {"truss_tolerance": 0.01}):
        with pytest.raises(ValueError, match="cannot be resumed"):
            codesign.run_codesign(6, 9, checkpoint=ck, **{**run, **change})
    with pytest.raises(ValueError, match=r"h_resolution = 0.0005 m is more than a tenth of the h range \(0.02, 0.021\) m"):
        codesign.run_codesign(6, 2, h_range=(0.02, 0.021), **{**run, "h_resolution": 5e-4})
    with pytest.raises(ValueError, match=r"h_resolution must be a number in \[1e-07, 0.001\] m, got 0.002"):
        codesign.run_codesign(6, 2, **{**run, "h_resolution": 0.002})


def test_evaluation_counts_of_a_cold_and_of_a_warm_started_swarm():
    """Cold: one evaluation per h over the whole run; previous_best: particles share only within an iteration."""
    hist = [dict(h=0.02, status="ok"), dict(h=0.02, status="ok", shared_with=0), dict(h=0.021, status="penalty: J_c > 2"),
            dict(h=0.02, status="ok"), dict(h=0.022, status="failed: x")]
    assert codesign.evaluation_counts(hist, "cold") == dict(particles=5, distinct=3, shared=2, failed=2, failed_particles=2)
    assert codesign.evaluation_counts(hist) == dict(particles=5, distinct=4, shared=1, failed=2, failed_particles=2)
    with pytest.raises(ValueError, match="start must be one of"):
        codesign.evaluation_counts(hist, "warm")


def test_on_resolution_gives_the_floats_a_swarm_and_a_grid_share():
    """A grid point and a swarm position at the same multiple of the resolution are the same float (the key of a shared
    evaluation), whatever the arithmetic that produced them; the range's ends are kept."""
    grid = [codesign.on_resolution(h, 1e-4, (0.015, 0.03)) for h in np.linspace(0.015, 0.03, 31)]
    assert grid[1] == 0.0155 and grid[-1] == 0.03 and all(repr(h) == repr(round(h, 12)) for h in grid)
    assert codesign.on_resolution(0.0155 + 3e-6, 1e-4, (0.015, 0.03)) == grid[1]
    assert codesign.on_resolution(0.01826, 1e-4, (0.0183, 0.03)) == 0.0183  # kept in the range
    assert codesign.on_resolution(0.0212345, None, (0.015, 0.03)) == 0.0212345
