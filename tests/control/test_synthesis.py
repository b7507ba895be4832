"""Structured synthesis building blocks: peak gradients against finite differences, peak-aware norms against the
Hamiltonian method and SLICOT's ab13dd, worst-case search against sampling, scenario validation."""

from dataclasses import replace

import numpy as np
import pytest
import slycot
from trusscodesign.control import synthesis
from trusscodesign.control.synthesis import optimiser, options, peaks, scenarios, search, steps
from trusscodesign.control.closedloop import LoopSettings
from trusscodesign.control.synthesis import Scenario, SynthesisOptions, plant_at
from trusscodesign.model import spacecraft
from trusscodesign.model.lft import LFT
from trusscodesign.study import robustness

ST = LoopSettings.from_parameters()
RNG = np.random.default_rng(11)
GAIN = -1.0 + 10.0 * RNG.normal(size=(4, 8))  # stabilising at the test scenarios (checked below)


@pytest.fixture(scope="module")
def plant(model, inertia):
    return plant_at(model, Scenario(-1.0, 1.0, -0.5, np.deg2rad(130.0)), inertia, ST)


@pytest.mark.parametrize("group", ["rpe", "effort"])
def test_peak_gradient_against_finite_differences(plant, group):
    lp = synthesis.loop_peaks(plant, GAIN)
    assert lp.stable
    w = lp.omega(group)
    value, grad = synthesis.peak_gradient(plant, GAIN, group, w)
    assert np.isclose(value, lp.norm(group), rtol=1e-8)
    h = 1e-4
    for i, j in [(0, 0), (1, 5), (3, 7), (2, 2)]:
        e = np.zeros((4, 8))
        e[i, j] = h
        fd = (synthesis.peak_gradient(plant, GAIN + e, group, w)[0] - synthesis.peak_gradient(plant, GAIN - e, group, w)[0]) / (2 * h)
        assert np.isclose(grad[i, j], fd, rtol=1e-5, atol=1e-9 * np.abs(grad).max())


def test_peaks_against_exact_norms(plant):
    """Peak-aware grid + nested-grid refinement = Hamiltonian norm = SLICOT ab13dd (to 1e-4 at worst, as required)."""
    lp = synthesis.loop_peaks(plant, GAIN)
    exact = synthesis.exact_norms(plant, GAIN)
    a, b, c, d = plant.closed_loop_matrices(GAIN)
    sl = plant.slices()
    for group in ("rpe", "effort"):
        norm, omega, certified = exact[group]
        assert certified
        assert abs(lp.norm(group) / norm - 1) < 1e-8
        assert abs(lp.omega(group) / omega - 1) < 1e-6
        bb, cc, dd = b[:, sl["p"]], c[sl[group]], d[sl[group], sl["p"]]
        n = a.shape[0]
        gpeak, fpeak = slycot.ab13dd("C", "I", "N", "D", n, bb.shape[1], cc.shape[0], a, np.eye(n), bb, cc, dd)
        assert abs(float(np.ravel(gpeak)[0]) / norm - 1) < 1e-4


def test_nested_grid_refinement_of_several_brackets():
    """Closed form: the peak of |1 / (j w - lambda)| (damping 1e-3) is 1 / |Re lambda|, at w = Im lambda;
    bracketed by its half-power points it is found to 1e-9 (and w to 3e-5 of the bandwidth), and brackets refined
    together give exactly what each gives alone (several peaks of one loop share each vectorised call)."""
    lams = [-1e-3 * w + 1j * w * np.sqrt(1 - 1e-6) for w in (0.7, 4.0, 97.7)]

    def mag(lam, logw):
        return np.abs(1.0 / (1j * np.exp(logw) - lam))

    los = np.array([np.log(lam.imag * (1 - 1e-3)) for lam in lams])
    his = np.array([np.log(lam.imag * (1 + 1e-3)) for lam in lams])
    values, logw = peaks._zoom_max(lambda x: np.stack([mag(lam, row) for lam, row in zip(lams, x)]), los, his)
    for j, lam in enumerate(lams):
        w_peak, exact = lam.imag, 1.0 / abs(lam.real)
        assert abs(values[j] / exact - 1) < 1e-9
        assert abs(np.exp(logw[j]) / w_peak - 1) < 3e-5 * 2e-3
        alone = peaks._zoom_max(lambda x, lam=lam: mag(lam, x), los[j:j + 1], his[j:j + 1])
        assert alone[0][0] == values[j] and alone[1][0] == logw[j]


def test_plain_grid_misses_the_peak(plant):
    """Why the peak-aware grid: a 2000-point log grid underestimates the closed-loop RPE norm."""
    a, b, c, d = plant.closed_loop_matrices(GAIN)
    sl = plant.slices()
    from trusscodesign.control.hinf import sigma_max

    s = sigma_max(a, b[:, sl["p"]], c[sl["rpe"]], d[sl["rpe"], sl["p"]], np.logspace(-2, 3.5, 2000)).max()
    exact = synthesis.exact_norms(plant, GAIN)["rpe"][0]
    assert s < exact * (1 - 1e-3)


def test_worst_case_not_beaten_by_sampling(model, inertia):
    """The box search finds a worst case at least as bad as 12 random scenarios (it could miss them)."""
    wc = synthesis.worst_case(model, GAIN, inertia, ST, thetas_deg=[0.0, 60.0, 120.0, 180.0], refine=1, max_evals=20)
    rng = np.random.default_rng(2)
    sampled = [synthesis.loop_peaks(plant_at(model, Scenario.from_vector(np.r_[rng.uniform(-1, 1, 3), rng.uniform(0, np.pi)]),
                                             inertia, ST), GAIN) for _ in range(12)]
    for group in ("rpe", "effort"):
        assert wc.value[group] >= max(s.norm(group) for s in sampled) * (1 - 1e-9)
        again = synthesis.loop_peaks(plant_at(model, wc.scenario[group], inertia, ST), GAIN)
        assert np.isclose(again.norm(group), wc.value[group], rtol=1e-9)


def test_worst_case_refinement_evaluates_its_group_only(model, inertia, monkeypatch):
    """The Nelder-Mead refinement of a group asks for that group's peaks only, and finds exactly what it finds with both
    groups computed (each group's peaks are computed apart): same values, frequencies, scenarios and evaluations."""
    kw = dict(thetas_deg=[0.0, 90.0, 180.0], refine=1, max_evals=12, workers=1)
    own = synthesis.worst_case(model, GAIN, inertia, ST, **kw)
    asked = []
    loop_peaks = synthesis.loop_peaks

    def both_groups(*args, **kwargs):
        asked.append(tuple(kwargs.get("groups", synthesis.GROUPS)))
        return loop_peaks(*args, **{**kwargs, "groups": synthesis.GROUPS})

    monkeypatch.setattr(search, "loop_peaks", both_groups)
    ref = synthesis.worst_case(model, GAIN, inertia, ST, **kw)
    assert ("rpe",) in asked and ("effort",) in asked
    assert own.evaluations == ref.evaluations
    for group in synthesis.GROUPS:
        assert own.value[group] == ref.value[group] and own.omega[group] == ref.omega[group]
        assert own.scenario[group] == ref.scenario[group]


def test_scenarios():
    sc = Scenario(1.0, -1.0, 0.5, np.pi / 2)
    assert np.isclose(sc.normalized()["tau"], np.tan(np.pi / 8))
    assert Scenario.from_vector(sc.vector()) == sc
    assert len(synthesis.default_scenarios()) == 1 + 5 * 4
    with pytest.raises(ValueError, match="d_mass"):
        Scenario(d_mass=1.5)


def test_bad_start(model, inertia):
    with pytest.raises(ValueError, match="gain0"):
        synthesis.synthesize(model, inertia, ST, gain0=np.ones((8, 4)))


def test_margin_gradient_against_finite_differences(plant):
    """Gradient of ``Re lambda + zeta_req |lambda|`` (the |lambda| term included) for a large zeta_req, where
    dropping it would be off by far more than the tolerance."""
    zeta_req = 0.05
    eig = peaks._eigen(plant, GAIN, min_damping=zeta_req, omega_check=0.0)
    rng = np.random.default_rng(3)
    for value, grad, req in eig.rows(3):
        i = int(np.argmin(np.abs(eig.value - value)))
        assert np.isclose(req, zeta_req * abs(eig.lam[i]))
        step = 1e-4 * rng.normal(size=(4, 8))
        moved = peaks._eigen(plant, GAIN + step, min_damping=zeta_req, omega_check=0.0)
        j = int(np.argmin(np.abs(moved.lam - eig.lam[i])))
        fd = moved.value[j] - value
        assert abs(fd - np.sum(grad * step)) < 1e-3 * abs(fd) + 1e-12


def test_elastic_lp():
    """min t s.t. t >= d, d <= -1 (hard) is infeasible in |d| <= 0.5; with the constraint soft it takes the slack."""
    objective = [(0.0, np.array([1.0]))]
    assert steps._lp(objective, [(0.0, np.array([1.0]), -1.0)], np.array([0.5])) is None
    d, t, s = steps._lp(objective, [], np.array([0.5]), soft=[(0.0, np.array([1.0]), -1.0)], penalty=10.0)
    assert np.allclose([d[0], t, s], [-0.5, -0.5, 0.5])
    d, t, s = steps._lp(objective, [], np.array([0.5]), soft=[(0.0, np.array([1.0]), 1.0)], penalty=10.0)
    assert np.allclose([d[0], t, s], [-0.5, -0.5, 0.0])


def test_margin_rows_within_the_trust_region_pick_the_sensitive_pole():
    """Two modes: a lightly damped one the gain cannot move, and a well-damped one it moves strongly. Ranked by margin
    alone the first is linearised; given the trust region, also the second (its margin can rise highest in it)."""
    lam = np.array([-0.01 + 10j, -0.01 - 10j, -1.0 + 100j, -1.0 - 100j])
    vr = np.eye(4, dtype=complex)
    b_v = np.zeros((4, 4), dtype=complex)
    c_y = np.zeros((8, 4), dtype=complex)
    b_v[2:, 0], c_y[0, 2:] = 1.0, 1.0  # only the 100 rad/s mode is coupled to the gain
    eig = peaks._Eigen.dense(lam, vr, lam.real.copy(), b_v, c_y)
    assert len(eig.rows(1)) == 1 and np.allclose(eig.rows(1)[0][0], -0.01)
    rows = eig.rows(1, radius=np.full(32, 10.0))  # reach 10 > 1 - 0.01
    assert len(rows) == 2 and np.isclose(rows[0][0], -0.01) and not np.any(rows[0][1])
    value, grad, _ = rows[1]
    assert np.isclose(value, -1.0) and np.isclose(grad[0, 0], 1.0) and np.count_nonzero(grad) == 1


def test_lazy_cap_gives_the_same_decision(model, inertia, monkeypatch):
    """The worst-case search's lazy damping cap: same ``stable`` and peaks as the eager cap, at damping requirements
    below and above the closed loop's least damping, with a cap that binds (the real passive damping) or not (a
    large one); the passive poles are computed only when the uncapped requirement fails."""
    from trusscodesign.control.closedloop import GeneralizedPlant

    sc = Scenario(0.5, -1.0, 1.0, np.deg2rad(60.0))
    plant = plant_at(model, sc, inertia, ST)
    lam = plant.closed_loop_poles(GAIN)
    zeta_cl = float(np.min(-lam.real / np.abs(lam)))
    calls = []
    outcomes = set()
    for passive in (plant.passive_damping(), 1.0):
        monkeypatch.setattr(GeneralizedPlant, "passive_damping", lambda self, v=passive: calls.append(v) or v)
        for factor in (0.3, 0.9, 1.1, 2.0, 5.0):
            eager = synthesis.loop_peaks(plant, GAIN, min_damping=factor * zeta_cl)
            calls.clear()
            lazy = synthesis.loop_peaks(plant, GAIN, min_damping=factor * zeta_cl, lazy_cap=True)
            assert lazy.stable == eager.stable
            assert lazy.peaks == eager.peaks
            assert bool(calls) == (factor > 1)  # the cap is computed only when the uncapped requirement fails
            outcomes.add(eager.stable)
    assert outcomes == {True, False}  # both decisions exercised


def test_passive_damping_bound_by_inverse_iteration(model, inertia):
    """The cheap upper bound on a new scenario's passive damping (inverse iteration near the nominal plant's least damped
    passive pole): never below the dense value, and equal to it within the stated margin when it finds the same mode;
    no bound (inf) when the iteration cannot converge (a shift halfway between two poles)."""
    from trusscodesign.control.closedloop import PASSIVE_BOUND_MARGIN

    near = plant_at(model, Scenario(), inertia, ST).passive_pole()
    for sc in (Scenario(0.5, -1.0, 1.0, np.deg2rad(60.0)), Scenario(-1.0, 1.0, -1.0, np.deg2rad(150.0))):
        bound = plant_at(model, sc, inertia, ST).passive_damping_bound(near)
        exact = plant_at(model, sc, inertia, ST).passive_damping()
        assert exact <= bound <= exact * (1 + PASSIVE_BOUND_MARGIN) * (1 + 1e-6)
    lam = np.linalg.eigvals(plant_at(model, Scenario(), inertia, ST).a)
    upper = lam[lam.imag > 1.0]
    upper = upper[np.argsort(upper.imag)]
    middle = 0.5 * (upper[0] + upper[1])  # equidistant from two poles: the iteration has no preferred direction
    assert plant_at(model, Scenario(), inertia, ST).passive_damping_bound(middle, iterations=3) == np.inf


def test_lazy_cap_with_the_passive_bound_gives_the_same_decision(model, inertia, monkeypatch):
    """With ``passive_near``, the lazy cap first uses the cheap bound on the passive damping: same ``stable`` and peaks
    as the eager cap at every requirement; the dense passive poles are computed only where the bound cannot decide:
    never with the nominal least damped passive pole as the shift (the same mode), at high requirements with the shift
    on a well damped mode (a loose bound)."""
    from trusscodesign.control.closedloop import PASSIVE_BOUND_MARGIN, GeneralizedPlant

    sc = Scenario(0.5, -1.0, 1.0, np.deg2rad(60.0))
    probe = plant_at(model, sc, inertia, ST)
    lam = probe.closed_loop_poles(GAIN)
    zeta_cl = float(np.min(-lam.real / np.abs(lam)))
    passive_poles = np.linalg.eigvals(probe.a)
    zeta_passive = -passive_poles.real / np.abs(passive_poles)
    damped = passive_poles[np.argmax(np.where((passive_poles.imag > 1.0) & (zeta_passive < 0.1), zeta_passive, 0.0))]
    dense = []
    original = GeneralizedPlant.passive_pole
    monkeypatch.setattr(GeneralizedPlant, "passive_pole", lambda self: dense.append(1) or original(self))
    near = plant_at(model, Scenario(), inertia, ST).passive_pole()
    branches = set()
    for shift in (near, damped):
        found = zeta_passive[np.argmin(np.abs(passive_poles - shift))]  # the mode the iteration converges to
        for req in (0.9 * zeta_cl, 1.1 * zeta_cl, 2.5 * zeta_cl, 5.0 * zeta_cl, 50.0 * zeta_cl):
            eager = synthesis.loop_peaks(plant_at(model, sc, inertia, ST), GAIN, min_damping=req)
            dense.clear()
            lazy = synthesis.loop_peaks(plant_at(model, sc, inertia, ST), GAIN, min_damping=req, lazy_cap=True, passive_near=shift)
            assert lazy.stable == eager.stable and lazy.peaks == eager.peaks
            expected = req > zeta_cl and zeta_cl <= min(req, 0.5 * found * (1 + PASSIVE_BOUND_MARGIN))
            assert bool(dense) == expected
            branches.add(expected)
    assert branches == {True, False}


def test_merged_worst_case_takes_each_group_from_the_loop_where_it_is_worst():
    """The search of a synthesis with variants (several open loops): per group the largest value with its scenario and
    frequency, every unstable scenario of every loop, the evaluations summed; one loop is returned unchanged."""
    a_sc, b_sc, u_sc = Scenario(-1.0, 0.0, 0.0, 0.3), Scenario(1.0, 1.0, -1.0, 2.0), Scenario(0.5, 0.5, 0.5, 1.0)
    a = synthesis.WorstCase({"rpe": 0.03, "effort": 0.9}, {"rpe": a_sc, "effort": a_sc}, {"rpe": 4.1, "effort": 3.7}, 200)
    b = synthesis.WorstCase({"rpe": 0.05, "effort": 0.4}, {"rpe": b_sc, "effort": b_sc}, {"rpe": 420.0, "effort": 161.0}, 180, [u_sc])
    m = search._merge([a, b])
    assert m.value == {"rpe": 0.05, "effort": 0.9} and m.omega == {"rpe": 420.0, "effort": 3.7}
    assert m.scenario["rpe"] is b_sc and m.scenario["effort"] is a_sc
    assert m.evaluations == 380 and m.unstable == [u_sc]
    assert search._merge([a]) is a


def test_bad_variants(model, inertia):
    with pytest.raises(TypeError, match=r"variants\[0\]"):
        synthesis.synthesize(model, inertia, ST, variants=[model])
    with pytest.raises(ValueError, match=r"variants\[1\].*3x3"):
        synthesis.synthesize(model, inertia, ST, variants=[(model, inertia), (model, np.eye(2))])
    with pytest.raises(ValueError, match=r"variants\[0\].*finite"):
        synthesis.synthesize(model, inertia, ST, variants=[(model, np.full((3, 3), np.nan))])


def test_truss_variants_refuse_bad_shifts():
    from trusscodesign.study import design

    base = design.DesignModels(0.015, None, None, None, np.eye(3), 45.8, 0.0)
    for bad in (0.6, float("nan"), "0.01", 0.0):
        with pytest.raises(ValueError, match="nonzero relative change"):
            design.truss_variants(base, [bad])


def test_truss_variants_may_leave_the_design_range(monkeypatch):
    """A variant is a model error of a design, not a design: 3 cm + 2 % (3.06 cm) and 1.5 cm - 2 % are built, with
    the model's own limits (slender members) and the design's spillover cut."""
    from trusscodesign.study import design

    built = []
    monkeypatch.setattr(design, "_models", lambda h, p, omega_max: built.append((round(h, 12), omega_max)) or h)
    for h in (0.03, 0.015):
        design.truss_variants(design.DesignModels(h, None, None, None, np.eye(3), 0.0, 0.0, 400.0), [-0.02, 0.02])
    assert built == [(0.0294, 400.0), (0.0306, 400.0), (0.0147, 400.0), (0.0153, 400.0)]
    with pytest.raises(ValueError, match="h must be a section side in metres"):  # 20 cm + 1 %: beyond the beam model
        design.truss_variants(design.DesignModels(0.2, None, None, None, np.eye(3), 0.0, 0.0), [0.01])


def test_variants_are_built_at_every_scenario_and_searched(monkeypatch, model, inertia):
    """Wiring of ``variants`` (plants, searches and optimiser replaced by stand-ins): a plant per (loop, scenario), the
    scenario a variant's search finds worse is added on every loop, each loop is searched in every round, and J_c is
    the worst over all plants."""
    inertia = np.asarray(inertia)
    built, searched = [], []
    s1, s2, s_new = Scenario(), Scenario(1.0, 1.0, 1.0, 0.5), Scenario(-1.0, 1.0, -1.0, 2.0)

    def fake_plant(m, sc, inertia_p1, settings, keep=()):
        built.append((float(inertia_p1[0, 0] / inertia[0, 0]), sc))
        return len(built) - 1  # the plant is its index

    def fake_peaks(p, gain, **kwargs):  # J grows with the plant index, every plant stable
        return synthesis.LoopPeaks({"rpe": [(0.01 * (1 + p), 1.0)], "effort": [(0.1, 2.0)]}, -1.0, True)

    def fake_search(m, gain, inertia_p1, settings, thetas=None, **kwargs):
        scale = float(inertia_p1[0, 0] / inertia[0, 0])
        searched.append(scale)
        worse = scale == 2.0 and len(searched) <= 2  # the variant's first search finds a worse scenario
        return synthesis.WorstCase({"rpe": 1.0 if worse else 0.001, "effort": 0.1}, {"rpe": s_new if worse else s1, "effort": s1},
                                   {"rpe": 3.0, "effort": 2.0}, 10)

    monkeypatch.setattr(optimiser, "plant_at", fake_plant)
    monkeypatch.setattr(optimiser, "loop_peaks", fake_peaks)
    monkeypatch.setattr(optimiser, "worst_case", fake_search)
    monkeypatch.setattr(optimiser, "_optimise", lambda prob, state: (state, False))
    res = synthesis.synthesize(model, inertia, ST, scenarios=[s1, s2], variants=[(model, 2.0 * inertia)], workers=1)
    assert built == [(1.0, s1), (1.0, s2), (2.0, s1), (2.0, s2), (1.0, s_new), (2.0, s_new)]
    assert searched == [1.0, 2.0, 1.0, 2.0]
    assert res.searches == 2  # two rounds, each searching both loops
    assert res.scenarios == [s1, s2, s_new] and res.message.startswith("converged")
    assert res.success and np.isclose(res.j_c, 0.06)  # plant 5: the variant at the added scenario


def test_robust_design_keeps_every_variant_spillover_loop(monkeypatch):
    from trusscodesign.study import design

    seen = {}
    monkeypatch.setattr(design, "plant_at", lambda m, sc, inertia, settings: ("plant", m))
    monkeypatch.setattr(design, "synthesize", lambda g_r, inertia, settings, options, **kw: seen.update(kw, g_r=g_r, options=options))
    base = design.DesignModels(0.02, "G_r", "G_r_low", "check", np.eye(3), 60.0, 0.0)
    shifted = design.DesignModels(0.0202, "G_r+1%", "G_r_low+1%", "check+1%", 2 * np.eye(3), 61.2, 0.0)
    design.robust_design(base, ST, variants=[shifted])
    assert seen["stability_models"] == [("plant", "check"), ("plant", "check+1%")]
    assert seen["g_r"] == "G_r" and len(seen["variants"]) == 1 and seen["variants"][0][0] == "G_r+1%"
    assert np.array_equal(seen["variants"][0][1], 2 * np.eye(3)) and seen["options"].omega_check == 500.0
    design.robust_design(base, ST, SynthesisOptions(spillover=False), variants=[shifted])
    assert seen["stability_models"] == []
    # the spillover modes keep half the truss damping of the parameters: 5e-4 for the paper's 1e-3, 5e-5 for 1e-4
    assert seen["options"].min_damping == 5e-4
    design.robust_design(replace(base, truss_damping=1e-4), ST)
    assert seen["options"].min_damping == 5e-5
    design.robust_design(replace(base, truss_damping=1e-4), ST, SynthesisOptions(min_damping=2e-4))
    assert seen["options"].min_damping == 2e-4


def _result(gain, success, message, n=1):
    return synthesis.SynthesisResult(np.full((4, 8), gain), 0.02, 0.98 if success else 1.2, success, message, [], None,
                                     10 * n, 1.0 * n, 100 * n, [dict(phase="optimise", n=n)], n, 2 * n)


def test_robust_design_restarts_a_failed_synthesis_from_its_final_gain(monkeypatch):
    """A failed attempt is started again from its final gain with the caller's starting scenario set, the counters add
    up, the message keeps the first failure; a success is not restarted, nor a failure to stabilise; restarts=0 (the
    default) returns the failure flagged."""
    from trusscodesign.study import design

    calls = []
    outcomes = []

    def fake(g_r, inertia, settings, options, gain0=None, **kw):
        calls.append((None if gain0 is None else float(np.asarray(gain0)[0, 0]), kw.get("scenarios")))
        return outcomes[len(calls) - 1]

    monkeypatch.setattr(design, "synthesize", fake)
    base = design.DesignModels(0.02, "G_r", "G_r_low", "check", np.eye(3), 60.0, 0.0)
    stop = "stopped after 6 rounds with the worst-case search still finding worse scenarios"
    outcomes[:] = [_result(-3.0, False, stop), _result(-4.0, False, stop, 2), _result(-5.0, True, "converged", 3)]
    res = design.robust_design(base, ST, SynthesisOptions(spillover=False, restarts=2), gain0=-np.ones((4, 8)), scenarios=["s"])
    assert calls == [(-1.0, ["s"]), (-3.0, ["s"]), (-4.0, ["s"])]
    assert res.success and res.restarts == 2 and res.gain[0, 0] == -5.0
    assert (res.iterations, res.time_s, res.evaluations, res.fallbacks, res.searches) == (60, 6.0, 600, 6, 12)
    assert [h["n"] for h in res.history] == [1, 2, 3]
    assert res.message.startswith("converged") and stop in res.message
    for restarts, first, n_calls in ((0, _result(-3.0, False, stop), 1), (3, _result(-3.0, True, "converged"), 1),
                                     (3, _result(-1.0, False, "could not stabilise every scenario from the starting gain"), 1)):
        calls.clear()
        outcomes[:] = [first, _result(-9.0, True, "converged")]
        res = design.robust_design(base, ST, SynthesisOptions(spillover=False, restarts=restarts))
        assert len(calls) == n_calls and res is first and res.restarts == 0
    # the gain moved before a later round failed to stabilise the scenarios its search added: worth a restart
    calls.clear()
    outcomes[:] = [_result(-3.0, False, "could not stabilise the scenarios the worst-case search added in round 1"),
                   _result(-9.0, True, "converged")]
    res = design.robust_design(base, ST, SynthesisOptions(spillover=False, restarts=1))
    assert calls == [(None, None), (-3.0, None)] and res.success and res.restarts == 1
    with pytest.raises(ValueError, match="restarts must be an integer in \\[0, inf\\)"):
        SynthesisOptions(restarts=-1)
    for bad in (1.5, True, "2"):  # wrong types: TypeError, as every option of the synthesis
        with pytest.raises(TypeError, match="restarts must be an integer"):
            SynthesisOptions(restarts=bad)


def test_truss_shift_check_judges_validity_beyond_the_design_range(monkeypatch):
    """Stand-in models and searches: shift 0 always checked, shifts leaving the design range checked as well (a model
    error, not a design), a row per gain and shift, valid = no unstable box point, Z_c < gamma_u and (with spillover)
    a stable spillover loop."""
    from trusscodesign.study import design

    built = []

    def fake_models(h, params=None):
        built.append(round(h, 12))
        return design.DesignModels(h, ("G_r", h), None, ("check", h), np.eye(3), 0.0, 0.0)

    class Loop:
        def __init__(self, h):
            self.h = h

        def closed_loop_poles(self, gain):
            return np.array([1.0 if self.h > 0.0155 else -1.0])  # the spillover loop is unstable above 1.55 cm

    def fake_search(g_r, gain, inertia, settings):
        z = 2.0 if gain[0, 0] > 0 else 0.5
        return synthesis.WorstCase({"rpe": 0.02, "effort": z}, {"rpe": Scenario(), "effort": Scenario()}, {"rpe": 4.0, "effort": 3.0}, 7)

    monkeypatch.setattr(design, "_models", fake_models)
    monkeypatch.setattr(design, "worst_case", fake_search)
    monkeypatch.setattr(design, "plant_at", lambda m, sc, inertia, settings: Loop(m[1]))
    gains = {"ok": -np.ones((4, 8)), "too much effort": np.ones((4, 8))}
    rows = design.truss_shift_check(0.015, gains, [-0.02, 0.04], ST, spillover=True)
    assert built == [0.0147, 0.015, 0.0156]
    assert [(r["design"], round(r["shift_pct"], 9), r["valid"]) for r in rows] == [
        ("ok", -2.0, True), ("too much effort", -2.0, False), ("ok", 0.0, True), ("too much effort", 0.0, False),
        ("ok", 4.0, False), ("too much effort", 4.0, False)]
    assert rows[4]["spillover_stable"] is False and rows[0]["evaluations"] == 7
    rows = design.truss_shift_check(0.015, gains, [0.04], ST)  # without the spillover check
    assert "spillover_stable" not in rows[0] and [r["valid"] for r in rows] == [True, False, True, False]


@pytest.mark.parametrize("option, value, error", [
    ("max_iter", 0, ValueError), ("max_rounds", 2.5, TypeError), ("tol", 0.0, ValueError), ("min_damping", 1.0, ValueError),
    ("min_damping_all", -1e-4, ValueError), ("omega_check", -1.0, ValueError), ("omega_check", "500", TypeError),
    ("trust_region", "sphere", ValueError), ("trust_region", None, ValueError), ("restoration", "smallest", ValueError),
    ("fast", "yes", TypeError), ("spillover", 1, TypeError), ("restarts", -1, ValueError), ("restarts", 1.5, TypeError),
    ("search_thetas_deg", [0.0, 200.0], ValueError), ("tol", float("inf"), ValueError), ("tol", 1.0, ValueError)])
def test_synthesis_options_are_checked_when_created(option, value, error):
    """A bad option is named with its allowed range when the options are created, before any model is touched."""
    with pytest.raises(error, match=option):
        SynthesisOptions(**{option: value})


def test_synthesize_checks_its_own_arguments_before_any_work():
    """The options must be a SynthesisOptions (an old keyword is a TypeError naming it), the workers a count."""
    with pytest.raises(TypeError, match="SynthesisOptions"):
        synthesis.synthesize(None, np.eye(3), LoopSettings(), {"tol": 1e-2})
    with pytest.raises(TypeError, match="band"):
        synthesis.synthesize(None, np.eye(3), band=0.5)
    with pytest.raises(ValueError, match="workers"):
        synthesis.synthesize(None, np.eye(3), workers=0)


def test_options_key_holds_what_differs_from_the_defaults_and_reads_back():
    """The key stored results record: the co-design's options as notebook 07's stored runs hold them; a key with an
    option this version no longer has is refused by name."""
    assert SynthesisOptions().key() == {}
    stored = {"tol": 0.01, "fast": True, "trust_region": "ball", "restoration": "least_change"}
    opts = SynthesisOptions(tol=0.01, fast=True, trust_region="ball", restoration="least_change")
    assert opts.key() == stored and SynthesisOptions.from_key(stored) == opts
    assert SynthesisOptions(search_thetas_deg=[0, 90]).key() == {"search_thetas_deg": [0.0, 90.0]}
    assert SynthesisOptions.from_key(None) == SynthesisOptions()
    with pytest.raises(TypeError, match="stall_steps"):
        SynthesisOptions.from_key({"tol": 0.01, "stall_steps": 3})
    with pytest.raises(AttributeError):
        opts.tol = 0.02  # frozen: one object shared by every particle cannot change under them


@pytest.mark.parametrize("option, value, error", [
    ("refine", -1, ValueError), ("max_evals", 0, ValueError), ("thetas_deg", [0.0, 270.0], ValueError),
    ("thetas_deg", [], ValueError), ("min_damping", 1.0, ValueError), ("refine", True, TypeError)])
def test_search_options_are_checked(option, value, error):
    with pytest.raises(error, match=option):
        synthesis.worst_case(None, -np.ones((4, 8)), np.eye(3), LoopSettings.from_parameters(), **{option: value})


# ---- mutation-testing additions (review of 2026-12-03)


def test_a_single_small_angle_in_degrees_is_accepted():
    """Only a grid of *several* angles all within pi is refused as radians: one angle of 2 deg is a valid grid."""
    assert scenarios._thetas_deg([2.0]).tolist() == [2.0]
    assert len(synthesis.default_scenarios([1.0])) == 1 + 4
    with pytest.raises(ValueError, match="radians"):
        scenarios._thetas_deg([0.0, 3.0])


def test_default_scenarios_convert_the_angles_to_radians():
    """Nominal first, then the corners at each angle [deg], stored as theta [rad]."""
    sc = synthesis.default_scenarios([0.0, 90.0, 180.0])
    assert sc[0] == Scenario()
    assert [s.theta for s in sc[1:]] == pytest.approx([0.0] * 4 + [np.pi / 2] * 4 + [np.pi] * 4, abs=1e-15)
    assert [tuple(s.vector()[:3]) for s in sc[1:5]] == list(synthesis.CORNERS)


def test_zoom_max_stays_inside_its_bracket():
    """A maximum at a bracket's end is found there and never outside the bracket (the refined grids are clipped)."""
    values, x = peaks._zoom_max(lambda x: x.copy(), np.array([0.0, -2.0]), np.array([1.0, -1.0]))
    assert x.tolist() == [1.0, -1.0] and values.tolist() == [1.0, -1.0]
    values, x = peaks._zoom_max(lambda x: -x, np.array([0.0]), np.array([1.0]))
    assert x.tolist() == [0.0] and values.tolist() == [0.0]


def test_initial_simplex_is_inside_the_box_with_the_documented_steps():
    """Steps 0.3 (normalised) and 10 deg, one coordinate per vertex, every vertex inside [-1, 1]^3 x [0, pi]."""
    steps = np.array([0.3, 0.3, 0.3, np.deg2rad(10.0)])
    for x0 in (np.zeros(4), np.array([1.0, -1.0, 0.9, np.pi]), np.array([-1.0, 1.0, -0.8, 0.0]), np.array([0.5, 0.75, 1.0, 3.1])):
        s = search._simplex(x0)
        assert s.shape == (5, 4) and np.array_equal(s[0], x0)
        assert np.all(s[:, :3] >= -1.0) and np.all(s[:, :3] <= 1.0) and np.all(s[:, 3] >= 0.0) and np.all(s[:, 3] <= np.pi)
        np.testing.assert_allclose(np.abs(s[1:] - x0), np.diag(steps), atol=1e-15)


class _SetValues:
    """Stand-in for the scenario set's state: its worst J and Z."""

    def __init__(self, rpe, effort):
        self.values = {"rpe": rpe, "effort": effort}

    def value(self, group):
        return self.values[group]


def test_uncovered_adds_unstable_and_worse_scenarios_only():
    """Covered = within cover_tol of the set's J (or Z); an effort scenario is added only if worse than the set's Z and
    above gamma (1 - margin); an unstable one (the first) always; each once."""
    s_j, s_z, s_u, s_v = Scenario(1.0, 0, 0, 0.1), Scenario(-1.0, 0, 0, 0.2), Scenario(0, 1.0, 0, 0.3), Scenario(0, -1.0, 0, 0.4)

    def search(j, z, unstable=()):
        return synthesis.WorstCase({"rpe": j, "effort": z}, {"rpe": s_j, "effort": s_z}, {"rpe": 1.0, "effort": 2.0}, 1, list(unstable))

    state = _SetValues(0.10, 0.90)
    assert optimiser._uncovered(state, search(0.1009, 0.95), 1.0) == []  # J within 1 %, Z below 0.98
    assert optimiser._uncovered(state, search(0.1011, 0.95), 1.0) == [s_j]
    assert optimiser._uncovered(state, search(0.10, 0.985), 1.0) == [s_z]  # above 0.98 and 1.01 x 0.90
    assert optimiser._uncovered(_SetValues(0.1, 0.99), search(0.10, 0.995), 1.0) == []  # within 1 % of the set's Z
    assert optimiser._uncovered(state, search(0.10, 0.5, [s_u, s_v]), 1.0) == [s_u]
    both = synthesis.WorstCase({"rpe": np.inf, "effort": np.inf}, {"rpe": s_u, "effort": s_u}, {"rpe": 1.0, "effort": 1.0}, 1, [s_u])
    assert optimiser._uncovered(state, both, 1.0) == [s_u]


def test_per_group_evaluates_each_point_with_its_own_group():
    group_of = np.array([1, 0, 1, 1, 0])
    out = peaks._per_group(("rpe", "effort"), group_of, lambda g, at: np.full(at.sum(), 1.0 if g == "rpe" else 2.0))
    assert out.tolist() == [2.0, 1.0, 2.0, 2.0, 1.0]


def test_ball_trust_region_cuts_the_corner_of_the_box():
    """min t s.t. t >= -d_1 - d_2 with |d_i| <= 1: the box's step is its corner (1, 1), t = -2; with the ball
    ||d||_2 <= sqrt(2) / 2 cut in, the step goes along the gradient to (1/2, 1/2), t = -1 (by hand)."""
    obj = [(0.0, np.array([-1.0, -1.0]))]
    d, t, s = steps._lp(obj, [], np.ones(2))
    assert np.allclose([*d, t, s], [1.0, 1.0, -2.0, 0.0])
    d, t, s = steps._lp(obj, [], np.ones(2), shape="ball")
    assert np.allclose([*d, t, s], [0.5, 0.5, -1.0, 0.0], atol=1e-6)


def test_ball_trust_region_keeps_an_interior_optimum_and_the_elastic_rows():
    """In 1-D the ball is |d| <= r / 2. t = max(2 - d, d) is least at d = 1, inside the ball of r = 5 (as in the box);
    d <= -1 (hard) cannot hold in |d| <= 0.25 (None); soft, it takes the slack: min t + 10 s over d in [-0.25, 0.25]
    with s = d + 1 is at d = -0.25, s = 0.75 (by hand)."""
    obj = [(2.0, np.array([-1.0])), (0.0, np.array([1.0]))]
    d, t, _ = steps._lp(obj, [], np.array([5.0]), shape="ball")
    assert np.allclose([d[0], t], [1.0, 1.0], atol=1e-6)
    objective = [(0.0, np.array([1.0]))]
    assert steps._lp(objective, [(0.0, np.array([1.0]), -1.0)], np.array([0.5]), shape="ball") is None
    d, t, s = steps._lp(objective, [], np.array([0.5]), soft=[(0.0, np.array([1.0]), -1.0)], penalty=10.0, shape="ball")
    assert np.allclose([d[0], t, s], [-0.25, -0.25, 0.75], atol=1e-6)


def _socp_by_cvxpy(objective, constraints, radius, soft, penalty):
    """The ball step written in cvxpy, the way it was solved until 2026-12-05: the reference of the direct cone program."""
    import cvxpy as cp

    n = radius.size
    d, t, s = cp.Variable(n), cp.Variable(), cp.Variable(nonneg=True)
    cons = [cp.norm(cp.multiply(1.0 / radius, d), 2) <= steps._BALL * np.sqrt(n), cp.abs(d) <= radius]
    cons += [f + g @ d <= t for f, g in objective] + [c + h @ d <= b for c, h, b in constraints]
    cons += [c + h @ d <= b + s for c, h, b in soft] if soft else [s == 0]
    prob = cp.Problem(cp.Minimize(t + penalty * s), cons)
    prob.solve(solver=cp.CLARABEL)
    return None if prob.status != cp.OPTIMAL else (d.value, float(t.value), float(s.value))


@pytest.mark.parametrize("seed", range(8))
def test_ball_step_equals_the_cvxpy_formulation(seed):
    """The ball step, a cone program given to Clarabel directly, against the same program written in cvxpy, on random
    problems of the synthesis's size (32 gains, 5-40 peak rows, hard and elastic rows, radii spread over two decades):
    the same optimum; with elastic rows that cannot hold (seeds 1, 5) the same slack; both infeasible where a hard row
    cannot hold (seeds 2, 6)."""
    rng = np.random.default_rng(seed)
    n, case = 32, seed % 4
    radius = 10.0 ** rng.uniform(-1, 1, n)
    objective = [(rng.normal(), rng.normal(size=n)) for _ in range(rng.integers(5, 40))]
    constraints = [(rng.normal(), rng.normal(size=n), rng.uniform(-0.5, 2.0)) for _ in range(rng.integers(0, 6))]
    constraints += [(0.0, rng.normal(size=n), -1e4)] if case == 2 else []  # |h d| <= sum |h| r < 1e4: cannot hold
    soft = [(rng.normal(), rng.normal(size=n), -1e3 if case == 1 else rng.uniform(0.0, 1.0)) for _ in range(case % 2 + case // 3)]
    penalty = 10.0 if soft else 0.0
    got = steps._lp(objective, constraints, radius, soft, penalty, shape="ball")
    ref = _socp_by_cvxpy(objective, constraints, radius, soft, penalty)
    assert (got is None) == (ref is None) == (case == 2)
    if case == 1:
        assert got[2] > 100.0  # the slack is taken
    if ref is not None:
        assert got[1] + penalty * got[2] == pytest.approx(ref[1] + penalty * ref[2], rel=1e-6, abs=1e-7)
        assert np.allclose(got[0], ref[0], rtol=1e-4, atol=1e-5 * radius.max())
        # feasible to the interior-point method's tolerance (3e-7 relative seen, with a slack of 1e3 in the problem)
        assert np.linalg.norm(got[0] / radius) <= steps._BALL * np.sqrt(n) * (1 + 1e-6)
        assert np.all(np.abs(got[0]) <= radius * (1 + 1e-6))


def test_lp_minimises_the_largest_linearised_peak_in_the_trust_region():
    """min t s.t. f_j + g_j d <= t, |d| <= r, by hand: t = max(2 - d, d) is least at d = 1 (t = 1) inside r = 5, at the
    trust-region edge d = 0.5 (t = 1.5) for r = 0.5; t may be negative (the objective has no lower bound)."""
    obj = [(2.0, np.array([-1.0])), (0.0, np.array([1.0]))]
    d, t, s = steps._lp(obj, [], np.array([5.0]))
    assert np.allclose([d[0], t, s], [1.0, 1.0, 0.0])
    d, t, _ = steps._lp(obj, [], np.array([0.5]))
    assert np.allclose([d[0], t], [0.5, 1.5])
    d, t, _ = steps._lp([(-1.0, np.array([1.0]))], [], np.array([0.5]))
    assert np.allclose([d[0], t], [-0.5, -1.5])


def test_scenario_physical_values_give_theta_in_degrees():
    from types import SimpleNamespace

    from trusscodesign.model.lft import Parameter

    params = {"M_SC": Parameter("M_SC", 100.0, 90.0, 110.0), "Iyy_SC": Parameter("Iyy_SC", 50.0, 40.0, 60.0),
              "omega1_SP": Parameter("omega1_SP", 3.0, 2.0, 4.0)}
    phys = Scenario(1.0, -0.5, 0.0, np.pi / 3).physical(SimpleNamespace(params=params))
    assert phys == pytest.approx({"M_SC": 110.0, "Iyy_SC": 45.0, "omega1_SP": 3.0, "theta_deg": 60.0})


def test_scenario_from_vector_clips_to_the_box():
    sc = Scenario.from_vector([2.0, -3.0, 0.5, 4.0])
    assert sc == Scenario(1.0, -1.0, 0.5, np.pi)
    assert Scenario.from_vector([0.0, 0.0, 0.0, -0.2]).theta == 0.0


# ---- the stabilisation phase (session of 2026-12-03, sixth: no unit test reached it before; notebooks 06/07 only)
# The robust gain at h = 2.1 cm of the co-design grid computed with the box trust region alone (dense path, min-max
# restoration; the J_c 0.01921 design of that grid), kept here to the last bit when that grid's folder was removed: the
# tests below quote values measured from it (margins, Z, steps), so the stored grid's 2.1 cm design does not replace it.
_GRID_GAIN_2_1CM = np.array([
    [-9.320057787022893, 61.92073110318891, 27.248848581744376, 9.153501221844492,
     -53.15038995046266, -410.8564080552094, -174.0272336774172, -914.4546346768973],
    [21.602832524716817, 1592.071972095391, -147.18210993037025, -5.648747992058468,
     -349.32268513093015, 737.6754109497095, 1027.4209226703776, -674.121559315545],
    [-642.6888164185698, 122.51606985137501, -200.8934434272189, -4.1513725891664635,
     -30.375808476221636, -990.2699876205003, -213.67669939471793, -908.1225483567257],
    [-147.37072964340874, -85.25140869536075, -53.60421685550077, 10.668639752851742,
     -1173.6845892344156, 1738.6583952610315, -781.3426223414127, -666.2955647554081],
])


def _grid_gain(h: float) -> np.ndarray:
    """The co-design grid's robust gain at section side ``h`` [m] (only 2.1 cm is kept: :data:`_GRID_GAIN_2_1CM`)."""
    if abs(h - 0.021) > 1e-9:
        raise ValueError(f"only the 2.1 cm grid gain is kept, not h = {h} m")
    return _GRID_GAIN_2_1CM.copy()


@pytest.mark.parametrize("scale", [1.0, 3.0])
def test_stabilise_restores_a_warm_start_that_is_unstable_at_the_new_h(model, inertia, scale):
    """The warm start the co-design makes: the 2.1 cm grid design's gain (times ``scale``) at 2.139 cm leaves a pole
    with a positive margin (0.149 and 6.64 1/s, measured). The stabilisation phase must end with every plant stable
    and damped as required, each accepted step lowering the abscissa, and its reported abscissa must be that of a
    fresh dense evaluation of the returned gain (not a stale or a modal one)."""
    scs = [Scenario(-1.0, 1.0, -0.5, np.deg2rad(130.0)), Scenario(1.0, -1.0, 1.0, np.deg2rad(40.0))]
    plants = [plant_at(model, s, inertia, ST) for s in scs]
    prob = _problem(plants, tol=2e-3, min_damping_all=2e-4)
    start = prob.evaluate_all(scale * _grid_gain(0.021))
    assert start.abscissa() > 0.1 and not start.stable()
    end = optimiser._stabilise(prob, start)
    assert end.stable() and end.abscissa() < -1e-7
    steps = [h["abscissa"] for h in prob.history if h["phase"] == "stabilise"]
    assert steps and steps[-1] == end.abscissa()
    assert np.all(np.diff([start.abscissa(), *steps]) < 0)
    # every pole of the returned loops is stable with a damping of at least the required 2e-4 (capped at half the
    # plant's passive damping, loop_peaks): checked on the dense closed loops, independently of the LP's rows
    for p in plants:
        lam = np.linalg.eigvals(p.closed_loop_matrices(end.gain)[0])
        zeta_req = min(2e-4, 0.5 * p.passive_damping())
        assert np.max(lam.real + zeta_req * np.abs(lam)) < -1e-7
    assert np.isclose(prob.evaluate_all(end.gain, dense=True).abscissa(), end.abscissa(), rtol=1e-9, atol=1e-12)


def test_stabilise_leaves_a_stable_start_untouched(model, inertia):
    """A start already stable at every plant is returned as is, with no iteration counted."""
    plants = [plant_at(model, Scenario(), inertia, ST)]
    prob = _problem(plants, tol=2e-3, min_damping_all=2e-4)
    start = prob.evaluate_all(-np.ones((4, 8)))
    assert start.stable()
    assert optimiser._stabilise(prob, start) is start and prob.iterations == 0 and not prob.history


@pytest.mark.parametrize("shape, restoration", [("box", "minmax"), ("ball", "minmax"), ("ball", "least_change")])
def test_feasibility_then_optimisation_phases_on_an_infeasible_start(model, inertia, shape, restoration, monkeypatch):
    """From an effort-infeasible start (3 x the 2.1 cm grid gain at 2.139 cm, stabilised: Z = 8.24, measured) the
    optimiser first lowers the worst effort peak at every accepted step until Z < gamma_u, then lowers the merit
    with Z kept below gamma_u, and stops by its own tests (not the iteration limit). The final J and Z are those of
    the true norms, not grid values: at the frequency where the certified H-infinity norm (Hamiltonian method) of each
    closed loop peaks, sigma_max by a direct solve is not above the loop's optimised peak by more than the 1e-6 to which
    :func:`trusscodesign.control.synthesis.loop_peaks` checks its top peak against a direct solve (a peak the optimiser missed would be;
    measured: 1.0e-7 with the ball), and the norm is the optimised value to the issue's 1e-4. The same with either trust region (from the
    same start, stabilised in the box), and with least-change restoration steps (some of them taken), whose feasibility
    phase lasts until Z < ``gamma_u (1 - margin / 2)`` (they aim at ``gamma_u (1 - margin)``).

    The norms are not held to 1e-6: the optimiser equalises peaks (here 0.0146383234 at 4.37 and 75.68 rad/s, equal to
    4e-10 by direct solves, gains up to 1.5e4) and there the independent methods themselves spread by more: measured on
    one such end gain, the balanced Hamiltonian bisection gave 3.1e-6 above the direct-solve maximum, the unbalanced one
    1e-7, SLICOT's ab13dd 8.4e-6 (the ball, in one environment, ended 1.04e-6 below the Hamiltonian norm)."""
    scs = [Scenario(-1.0, 1.0, -0.5, np.deg2rad(130.0)), Scenario(1.0, -1.0, 1.0, np.deg2rad(40.0))]
    plants = [plant_at(model, s, inertia, ST) for s in scs]
    prob = _problem(plants, tol=1e-2, min_damping_all=2e-4)
    start = optimiser._stabilise(prob, prob.evaluate_all(3.0 * _grid_gain(0.021)))
    assert start.stable() and start.value("effort") > 2.0 * ST.gamma_u
    prob.opts = prob.opts.replace(trust_region=shape, restoration=restoration)
    n_stab = len(prob.history)
    steps_taken: list[bool] = []
    least = steps._least_change

    def recording(*args, **kwargs):
        out = least(*args, **kwargs)
        steps_taken.append(out is not None)
        return out

    monkeypatch.setattr(optimiser, "_least_change", recording)
    end, at_limit = optimiser._optimise(prob, start)
    assert any(steps_taken) if restoration == "least_change" else not steps_taken
    accepted = prob.history[n_stab:]
    phases = [s["phase"] for s in accepted]
    n_feas = phases.count("feasibility")
    assert n_feas >= 1 and phases == ["feasibility"] * n_feas + ["optimise"] * (len(accepted) - n_feas)
    z_feas = [start.value("effort")] + [s["Z"] for s in accepted[:n_feas]]
    assert np.all(np.diff(z_feas) < 0)
    assert z_feas[-1] < ST.gamma_u * (1 - 0.01 if restoration == "least_change" else 1) and all(s["Z"] < ST.gamma_u for s in accepted[n_feas:])
    assert end.value("rpe") < accepted[n_feas]["J"]  # the optimisation phase improved on its first feasible point
    assert not at_limit and prob.iterations < n_stab + 60
    assert end.stable() and end.value("effort") < ST.gamma_u
    exact = [synthesis.exact_norms(p, end.gain) for p in plants]
    for group in ("rpe", "effort"):
        assert all(e[group][2] for e in exact)
        assert max(e[group][0] for e in exact) == pytest.approx(end.value(group), rel=1e-4)
        for p, e, lp in zip(plants, exact, end.peaks):
            a, b, c, d = p.closed_loop_matrices(end.gain)
            sl = p.slices()
            w = e[group][1]
            t = d[sl[group], sl["p"]] + c[sl[group]] @ np.linalg.solve(1j * w * np.eye(a.shape[0]) - a, b[:, sl["p"]])
            assert np.linalg.svd(t, compute_uv=False)[0] <= lp.norm(group) * (1 + 1e-6)  # loop_peaks's direct-check tolerance


@pytest.mark.parametrize("region", ["box", "ball"])
def test_synthesize_passes_its_trust_region_to_every_step(model, inertia, monkeypatch, region):
    """Every LP of a synthesis (stabilisation and optimisation) gets the shape given to synthesize."""
    shapes: list[str] = []
    lp = steps._lp

    def recording(*args, **kwargs):
        shapes.append(kwargs["shape"] if "shape" in kwargs else args[5])
        return lp(*args, **kwargs)

    monkeypatch.setattr(optimiser, "_lp", recording)
    synthesis.synthesize(model, inertia, ST, SynthesisOptions(max_iter=3, max_rounds=1, search_thetas_deg=[0.0], trust_region=region),
                         gain0=3.0 * _grid_gain(0.021), scenarios=[Scenario()], workers=1)
    assert len(shapes) >= 3 and set(shapes) == {region}


@pytest.mark.parametrize("fast", [False, True])
def test_extend_evaluates_only_the_added_plants_and_equals_a_full_evaluation(model, inertia, fast):
    """A round after the first starts from the last state (at its gain) with only the scenarios the search added still
    to evaluate: the extended state must hold the same peaks, margins and stability-only plants as an evaluation of the
    whole set at that gain, and count only the new plants' evaluations."""
    scs = [Scenario(-1.0, 1.0, -0.5, np.deg2rad(130.0)), Scenario(1.0, -1.0, 1.0, np.deg2rad(40.0)), Scenario(0.3, 0.2, -1.0, 1.0)]
    plants = [plant_at(model, s, inertia, ST) for s in scs]
    checks = [plant_at(model, Scenario(), inertia, ST)]
    prob = _problem(plants[:2], checks=checks, tol=2e-3, min_damping_all=2e-4, fast=fast)
    gain = -np.ones((4, 8))
    first = prob.evaluate_all(gain)
    assert first.stable() and all(x is not None for x in first.extra)
    prob.plants += plants[2:]
    n = prob.evaluations
    ext = prob.extend(first)
    assert prob.evaluations == n + 1 and len(ext.peaks) == 3 and np.array_equal(ext.gain, gain)
    full = _problem(plants, checks=checks, tol=2e-3, min_damping_all=2e-4, fast=fast).evaluate_all(gain)
    for group in ("rpe", "effort"):
        assert ext.value(group) == pytest.approx(full.value(group), rel=1e-9)
        for a, b in zip(ext.peaks, full.peaks):
            assert a.norm(group) == pytest.approx(b.norm(group), rel=1e-9)
    assert ext.stable() == full.stable() and ext.abscissa() == pytest.approx(full.abscissa(), rel=1e-9)
    assert [p.abscissa for p in ext.peaks] == pytest.approx([p.abscissa for p in full.peaks], rel=1e-9)
    assert (id(plants[2]) in prob._modal) == fast  # the new plant by the same path as the others
    assert [x.margin for x in ext.extra] == pytest.approx([x.margin for x in full.extra], rel=1e-9)
    assert prob.extend(ext) is ext  # nothing added: nothing evaluated


def test_least_change_step_is_the_scaled_projection_onto_the_violated_constraint():
    """One violated constraint ``c + h d <= b``: the smallest step in ``||d / r||_2`` is ``-(c - b) R^2 h / (h^T R^2 h)``
    (``R = diag(r)``, closed form), a satisfied constraint leaves it unchanged, and when the box cannot reach the bound
    there is no step (None)."""
    rng = np.random.default_rng(3)
    r = rng.uniform(0.5, 2.0, 6)
    h = rng.normal(size=6)
    c, b = 1.0, 0.2
    d = steps._least_change([(c, h, b), (0.0, rng.normal(size=6), 10.0)], r)
    expected = -(c - b) * r**2 * h / np.sum(r**2 * h**2)
    assert np.all(np.abs(expected) < r)  # the closed form is inside the box (else it would not be the answer)
    np.testing.assert_allclose(d, expected, rtol=1e-6, atol=1e-8)
    assert steps._least_change([(c, 1e-3 * h, b)], r) is None  # the bound is out of the box's reach
    np.testing.assert_allclose(steps._least_change([(0.0, h, 1.0)], r), 0.0, atol=1e-8)


@pytest.mark.parametrize("ball", [False, True])
def test_least_change_step_against_a_general_solver_with_the_trust_region_active(ball):
    """A least-change step that needs the box (and the ball) to bind: the same step as SCS (another solver, through
    cvxpy) on the problem written directly (``min ||d / r||^2`` s.t. the rows, ``|d| <= r``, with the ball
    ``||d / r|| <= sqrt(n) / 2``), or None exactly where SCS finds it infeasible."""
    import cvxpy as cp

    rng = np.random.default_rng(7)
    n = 8
    r = rng.uniform(0.5, 2.0, n)
    r[0] = 1.0
    x_f = -0.9 * r  # a point of the box that meets every row
    # the first row alone would move d_0 by about -1.45 (its scaled projection), past the box's 1: the box binds
    rows = [(1.0, np.r_[1.0, np.full(n - 1, 0.1)], -0.5)]
    rows += [(0.0, h, float(h @ x_f) + 0.2) for h in rng.normal(size=(2, n))]
    d = steps._least_change(rows, r, ball)
    x = cp.Variable(n)
    cons = [np.array([h for _, h, _ in rows]) @ x <= np.array([bd - c for c, _, bd in rows]), cp.abs(x) <= r]
    if ball:
        cons.append(cp.norm(cp.multiply(x, 1 / r)) <= 0.5 * np.sqrt(n))
    problem = cp.Problem(cp.Minimize(cp.sum_squares(cp.multiply(x, 1 / r))), cons)
    problem.solve(solver="SCS", eps=1e-10, max_iters=200000)
    if problem.status == "infeasible":
        assert d is None
        return
    assert problem.status == "optimal" and d is not None
    assert np.any(np.abs(x.value) >= r * (1 - 1e-5))  # the box binds
    np.testing.assert_allclose(d, x.value, atol=1e-5 * r.max())


@pytest.mark.parametrize("floor", [2e-4, 0.0])
def test_least_change_restoration_moves_the_gain_less_than_the_min_max_step(model, inertia, floor):
    """The warm start of the stabilisation test (the 2.1 cm grid gain at 2.139 cm, a pole with a positive margin 0.149
    1/s): both restorations end stable, the least-change one with a smaller change of the gain (scaled by the trust
    radius) and an abscissa nearer its target (measured: 0.25 against 1.35, -4.0e-4 against -6.3e-3 1/s, in 1 step
    against 2). Not a lower J: the step ignores J (0.0283 against 0.0209 here), which the optimiser then lowers. Also with
    no damping floor (``min_damping_all = 0``: the margins' targets are then ``-min_decay`` itself, which a step aimed
    exactly at would reach only on the boundary)."""
    scs = [Scenario(-1.0, 1.0, -0.5, np.deg2rad(130.0)), Scenario(1.0, -1.0, 1.0, np.deg2rad(40.0))]
    plants = [plant_at(model, s, inertia, ST) for s in scs]
    gain = _grid_gain(0.021)
    ends = {}
    for mode in ("minmax", "least_change"):
        prob = _problem(plants, tol=2e-3, min_damping_all=floor, restoration=mode)
        start = prob.evaluate_all(gain)
        assert not start.stable()
        ends[mode] = optimiser._stabilise(prob, start)
        assert ends[mode].stable()
    size = {m: np.linalg.norm((e.gain - gain).ravel() / optimiser._Problem.radius(prob, gain)) for m, e in ends.items()}
    assert size["least_change"] < 0.5 * size["minmax"]
    if floor:  # (without a floor the abscissa is that of a slow pole that neither step moves: -6.7e-3 1/s for both)
        assert ends["minmax"].abscissa() < ends["least_change"].abscissa() < -1e-7


def test_synthesize_passes_its_restoration_to_the_problem(model, inertia, monkeypatch):
    """``restoration="least_change"`` reaches the stabilisation: its QP is called (and never with the default)."""
    calls: list[int] = []
    least = steps._least_change

    def recording(*args, **kwargs):
        calls.append(1)
        return least(*args, **kwargs)

    monkeypatch.setattr(optimiser, "_least_change", recording)
    kw = dict(gain0=3.0 * _grid_gain(0.021), scenarios=[Scenario()], workers=1)
    opts = SynthesisOptions(max_iter=3, max_rounds=1, search_thetas_deg=[0.0])
    synthesis.synthesize(model, inertia, ST, opts, **kw)
    assert not calls
    synthesis.synthesize(model, inertia, ST, opts.replace(restoration="least_change"), **kw)
    assert calls


# ---- the stopping test
def _problem(plants, checks=(), tol: float = 2e-3, min_damping_all: float = 2e-4, **options) -> "optimiser._Problem":
    """The optimiser's problem on ``plants`` (threads: none), stability-only ``checks`` with no damping floor above 0."""
    opts = SynthesisOptions(tol=tol, min_damping_all=min_damping_all, **options)
    return optimiser._Problem(list(plants), list(checks), map, ST.gamma_u, opts, 0.0, 0.0)


def _stall(js: list[float], k: int, tol: float) -> list[bool]:
    """Where the stopping test holds along the accepted J values: a relative decrease below ``tol`` over ``k`` steps."""
    return [i >= k and js[i - k] - js[i] < tol * js[i] for i in range(len(js))]


def _stall_problem(plants):
    return _problem(plants, tol=1e-2, trust_region="ball")


def _optimised(prob, state) -> list[float]:
    """The J values of the optimisation-phase steps ``_optimise`` accepts from ``state`` (not at its iteration limit)."""
    _, at_limit = optimiser._optimise(prob, state)
    assert not at_limit
    return [h["J"] for h in prob.history if h["phase"] == "optimise"]


@pytest.fixture(scope="module")
def stall_round(model, inertia):
    """Two scenario plants at 2.139 cm, the 2.1 cm grid gain stabilised (Z = 1.29, J = 0.038, measured), then one
    optimisation: the plants, the start, the problem after it and the state it ended at."""
    plants = [plant_at(model, s, inertia, ST) for s in (Scenario(-1.0, 1.0, -0.5, np.deg2rad(130.0)),
                                                         Scenario(1.0, -1.0, 1.0, np.deg2rad(40.0)))]
    prob = _stall_problem(plants)
    start = optimiser._stabilise(prob, prob.evaluate_all(_grid_gain(0.021)))
    prob.history.clear()
    end, _ = optimiser._optimise(prob, start)
    return plants, start, prob, end


def test_optimiser_stops_at_the_first_stall(stall_round):
    """The optimisation phase (after its feasibility step) stops at the first accepted step where J has decreased by
    less than ``tol`` over the last :data:`_STALL_STEPS` (5), not before, and not at the iteration limit."""
    _, _, prob, end = stall_round
    js = [h["J"] for h in prob.history if h["phase"] == "optimise"]
    stalled = _stall(js, options._STALL_STEPS, 1e-2)
    assert options._STALL_STEPS == 5 and stalled[-1] and not any(stalled[:-1]) and len(js) >= 7
    assert [h["phase"] for h in prob.history][0] == "feasibility"
    assert end.value("rpe") == js[-1]


@pytest.mark.parametrize("thetas", [np.deg2rad([0.0, 45.0, 90.0, 135.0, 180.0]), [0.0, 1.0, 2.0, 3.0]])
def test_panel_angle_grids_in_radians_are_refused(thetas):
    with pytest.raises(ValueError, match="radians"):
        synthesis.default_scenarios(thetas)
    with pytest.raises(ValueError, match="radians"):  # before any plant is built (the model is not even looked at)
        synthesis.worst_case(None, np.zeros((4, 8)), np.eye(3), LoopSettings(), thetas_deg=thetas)
    assert len(synthesis.default_scenarios([0.0, 90.0])) == 9 and len(synthesis.default_scenarios([0.0])) == 5


def test_plant_at_refuses_unknown_kept_names(monkeypatch):
    monkeypatch.setattr(scenarios, "generalized_plant", lambda *args, **kwargs: "plant")
    params = spacecraft.uncertain_parameters()
    model = sum((LFT.param(p) for p in params.values()), LFT.constant([[0.0]]))
    assert synthesis.plant_at(model, Scenario(), np.eye(3), LoopSettings(), keep=robustness.KEEP) == "plant"
    with pytest.raises(ValueError, match=r"not parameters of the model.*'Iyy_SC', 'M_SC', 'omega1_SP', 'tau'"):
        synthesis.plant_at(model, Scenario(), np.eye(3), LoopSettings(), keep=["hub_mass"])  # was ignored: M_SC substituted
    with pytest.raises(TypeError, match="keep"):
        synthesis.plant_at(model, Scenario(), np.eye(3), LoopSettings(), keep="M_SC")


def test_synthesize_refuses_an_empty_scenario_set():
    with pytest.raises(ValueError, match="at least one Scenario"):  # was "max() arg is an empty sequence"
        synthesis.synthesize(None, np.eye(3), LoopSettings(), scenarios=[])
    with pytest.raises(TypeError, match=r"scenarios\[0\] must be a Scenario"):
        synthesis.synthesize(None, np.eye(3), LoopSettings(), scenarios=[(0.0, 0.0, 0.0, 0.0)])
