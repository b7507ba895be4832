"""Particle swarm: convergence on a known minimum, MATLAB's adaptive rules, reproducibility, resume from a checkpoint,
and the same result through Dask with 1 and 2 workers; the co-design objective's penalty and failure handling."""

import json

import numpy as np
import pytest
from trusscodesign.study import pso


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


def test_checkpoint_keeps_non_finite_values(tmp_path):
    def evaluate(x, state):
        return [{"f": np.inf if i == 0 else float(xi[0]), "J_c": np.inf if i == 0 else 0.1} for i, xi in enumerate(x)]

    ck = tmp_path / "state.json"
    a = pso.run(evaluate, n=3, lower=[0.0], upper=[1.0], iterations=2, seed=0, checkpoint=ck)
    b = pso.load_state(ck)
    assert b.history[0]["J_c"] == np.inf and isinstance(b.history[0]["J_c"], float)
    assert b.history == a.history


# ---- mutation-testing additions (review of 2026-12-03)


def test_velocity_update_uses_inertia_and_the_documented_weights_1_49():
    """v <- W v + y1 u1 (p - x) + y2 u2 (g - x), u ~ U(0, 1) per component, y1 = y2 = 1.49 (module docstring). With many
    components, the ratio of each term to its lever arm spans [0, 1.49] (max of 20000 uniforms: within 1e-3 of 1)."""
    n, d = 4, 20000
    state = pso.init_swarm(n, -10 * np.ones(d), 10 * np.ones(d), seed=5)
    state.x[:] = 0.0
    state.v[:] = 0.0
    state.v[0] = 1.0
    state.inertia = 0.5
    state.p[:] = 1.0
    state.p[0] = 0.0  # particle 0 at its own best: only W v and the social term towards the better particles at 1
    state.p_f[:] = 0.0
    state.p_f[0] = 1.0
    pso.step_positions(state)
    social = state.v[0] - 0.5  # = 1.49 u2 (1 - 0)
    assert social.min() >= 0.0 and social.max() <= 1.49 + 1e-12 and social.max() > 1.49 * (1 - 2e-3)
    both = state.v[1]  # no better neighbour: g = p, so v = 1.49 (u1 + u2) (1 - 0)
    assert both.min() >= 0.0 and both.max() <= 2.98 + 1e-12 and both.max() > 2.98 * (1 - 0.05)
    assert np.array_equal(state.x, state.v)  # x = 0 + v, nothing clipped


def test_clipped_components_have_their_velocity_zeroed():
    """Positions are clipped to the bounds and the velocity zeroed there (module docstring), not elsewhere."""
    state = pso.init_swarm(4, [0.0, 0.0], [1.0, 1.0], seed=1)
    state.x[:] = [0.99, 0.5]
    state.p[:] = state.x
    state.p_f[:] = 1.0
    state.v[:] = [0.5, 0.001]
    state.inertia = 1.0
    pso.step_positions(state)
    assert np.all(state.x[:, 0] == 1.0) and np.all(state.v[:, 0] == 0.0)  # clipped: velocity reset
    assert np.allclose(state.v[:, 1], 0.001) and np.allclose(state.x[:, 1], 0.501)  # inside: v = W v (p = x = g)


@pytest.mark.parametrize("rule", pso.RULES)
def test_largest_neighbourhood_sees_every_particle(rule):
    """At its largest, the neighbourhood is all the other particles (documented: N = n - 1 others and the particle;
    MATLAB's code: N = n, the particle included): every particle is pulled towards the only one with a finite best."""
    n = 6
    for seed in range(25):
        state = pso.init_swarm(n, [-10.0], [10.0], seed=seed, rule=rule)
        state.neighbours = n if rule == "matlab" else n - 1
        state.x[:, 0] = np.linspace(-1.0, 0.0, n)
        state.p[:] = state.x
        state.v[:] = 0.0
        k = seed % n
        state.p[k] = 5.0
        state.p_f[:] = np.inf
        state.p_f[k] = 0.0
        pso.step_positions(state)
        others = np.delete(np.arange(n), k)
        assert np.all(state.v[others, 0] > 0.0), seed  # g = p_k for every one: a velocity towards +5


def test_a_particle_best_moves_only_on_a_strictly_better_value():
    """MATLAB particleswarm (documented algorithm): "if f < fun(p), then set p = x"; an equal value keeps p."""
    state = pso.init_swarm(3, [0.0], [1.0], seed=2)
    pso.update_bests(state, [1.0, 2.0, 3.0])
    kept = state.p.copy()
    state.x = state.x + 0.1
    improved = pso.update_bests(state, [1.0, 2.0, 3.0])
    assert not improved and np.array_equal(state.p, kept) and state.counter == 1


def test_inertia_doubles_only_below_two_and_halves_only_above_five():
    """Documented rule on improvement: c = max(0, c - 1); W = 2 W if c < 2, W / 2 if c > 5, else unchanged."""
    for c_before, w_after in ((3, 0.4), (2, 0.8), (6, 0.4), (7, 0.2), (1, 0.8)):
        state = pso.init_swarm(24, [0.0], [1.0], seed=0)
        pso.update_bests(state, np.arange(24.0))
        state.inertia, state.counter = 0.4, c_before
        assert pso.update_bests(state, np.r_[-1.0, np.full(23, 100.0)])
        assert state.counter == max(0, c_before - 1) and np.isclose(state.inertia, w_after), c_before


def test_minus_infinity_is_a_failed_evaluation_not_a_best():
    """Non-finite values mean a failed evaluation (run's docstring): -inf must not become the swarm's best."""
    state = pso.init_swarm(3, [0.0], [1.0], seed=0)
    pso.update_bests(state, [-np.inf, 2.0, np.nan])
    assert state.g_f == 2.0 and np.array_equal(state.g, state.x[1]) and state.p_f[0] == np.inf


def test_the_first_iteration_evaluates_the_initial_swarm():
    """The initial swarm counts as the first iteration: the first batch evaluated is init_swarm's positions."""
    seen = []

    def evaluate(x, state):
        seen.append(x.copy())
        return quadratic(x, state)

    pso.run(evaluate, n=5, lower=[0.2, -1.0], upper=[0.7, 3.0], iterations=2, seed=11)
    assert np.array_equal(seen[0], pso.init_swarm(5, [0.2, -1.0], [0.7, 3.0], seed=11).x)
    assert not np.array_equal(seen[1], seen[0])


def test_each_step_advances_the_random_stream():
    """The state keeps the generator state after the last draw: two steps from the same positions draw anew."""
    state = pso.init_swarm(4, [0.0], [1.0], seed=3)
    pso.update_bests(state, [1.0, 2.0, 3.0, 4.0])
    x0, v0, rng0 = state.x.copy(), state.v.copy(), state.rng
    pso.step_positions(state)
    first = state.v.copy()
    assert state.rng != rng0
    state.x, state.v = x0.copy(), v0.copy()
    pso.step_positions(state)
    assert not np.array_equal(state.v, first)


def test_unevaluated_swarm_round_trips_through_a_checkpoint(tmp_path):
    """save_state / load_state keep infinite bests (an unevaluated swarm) as inf, not NaN."""
    state = pso.init_swarm(4, [0.0], [1.0], seed=3)
    pso.save_state(state, tmp_path / "s.json")
    back = pso.load_state(tmp_path / "s.json")
    assert np.all(back.p_f == np.inf) and back.g_f == np.inf
    assert np.array_equal(back.x, state.x) and np.array_equal(back.v, state.v) and back.rng == state.rng
    pso.update_bests(back, [3.0, 1.0, np.inf, 2.0])
    assert back.g_f == 1.0 and np.array_equal(back.p_f, [3.0, 1.0, np.inf, 2.0])


def test_a_complete_checkpoint_is_returned_without_evaluating(tmp_path):
    """Only a checkpoint with *more* completed iterations than asked is refused: a complete one resumes to itself."""
    ck = tmp_path / "state.json"
    done = pso.run(quadratic, n=4, lower=[0.0], upper=[1.0], iterations=3, seed=2, checkpoint=ck)
    calls = []

    def evaluate(x, state):
        calls.append(x)
        return quadratic(x, state)

    again = pso.run(evaluate, n=4, lower=[0.0], upper=[1.0], iterations=3, seed=2, checkpoint=ck)
    assert not calls and again.iteration == 3 and again.history == done.history and again.g_f == done.g_f


def test_initial_swarm_is_uniform_in_the_bounds_with_velocities_in_plus_minus_the_range():
    """Initial positions uniform in the bounds, velocities uniform in [-range, range] (module docstring)."""
    lo, hi = np.array([0.2, -1.0]), np.array([0.7, 3.0])
    state = pso.init_swarm(400, lo, hi, seed=9)
    assert np.all(state.x >= lo) and np.all(state.x <= hi)
    assert np.allclose(state.x.min(axis=0), lo, atol=0.02 * (hi - lo)) and np.allclose(state.x.max(axis=0), hi, atol=0.02 * (hi - lo))
    span = hi - lo
    assert np.all(np.abs(state.v) <= span)
    assert np.allclose(state.v.min(axis=0), -span, atol=0.03 * span) and np.allclose(state.v.max(axis=0), span, atol=0.03 * span)
    assert state.neighbours == 100 and state.inertia == 1.1 and np.all(state.p_f == np.inf)
    for n, n_min in ((2, 1), (3, 2), (6, 2), (8, 2), (12, 3), (24, 6)):  # min(max(2, floor(n / 4)), n - 1)
        assert pso.init_swarm(n, [0.0], [1.0], seed=0).neighbours == n_min
