"""Particle-swarm optimisation with MATLAB ``particleswarm``'s adaptive rules, checkpointable and batch-evaluated.

Paper: "Co-design optimization architecture" (the outer loop over the design parameter, MATLAB's Global
Optimization Toolbox). Written here rather than taken from a package because the co-design needs three things
the maintained ones (pymoo; pyswarms is unmaintained since 2021) do not give together: a whole iteration's swarm
evaluated as one batch (so that it can be farmed out to Dask and warm-started from the previous iteration's best
particle), the complete state saved after every iteration (so that an interrupted run resumes to the very same
result), and MATLAB's adaptive inertia and neighbourhood rules, for a faithful reproduction.

MATLAB's rules, as documented for ``particleswarm`` (``rule="documented"``, the default, with which the stored
co-design swarms were run): velocity ``v <- W v + y1 u1 (p - x) + y2 u2 (g - x)`` with ``p`` the particle's best,
``g`` the best of a random neighbourhood of ``N`` other particles and the particle itself, ``u1, u2 ~ U(0,1)`` per
component, ``y1 = y2 = 1.49``; positions clipped to the bounds (velocity zeroed there); after each iteration, if the
swarm's best improved: ``c = max(0, c - 1)``, ``N = N_min``, and ``W = 2 W`` if ``c < 2``, ``W = W / 2`` if
``c > 5`` (W kept in [0.1, 1.1]); otherwise ``c = c + 1`` and ``N = min(N + N_min, n - 1)``. ``N_min = max(2,
floor(0.25 n))``. Initial positions uniform in the bounds, velocities uniform in ``[-range, range]``.

``rule="matlab"`` follows MATLAB's code instead, where it differs from that text (read in a public copy of
``particleswarm.m``'s main loop): the inertia rule (``W = 2 W`` if ``c < 2``, ``W = W / 2`` if ``c > 5``) is
applied after *every* iteration, stalled ones included, so that a stalling swarm slows down and contracts, which
with the documented text it does only once the best improves again; and the neighbourhood is the particle itself
plus ``N - 1`` others, ``N`` growing up to ``n``. The random streams are numpy's, so neither rule reproduces a
MATLAB run draw for draw.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..infra.checks import check_option

__all__ = ["SwarmState", "init_swarm", "step_positions", "update_bests", "save_state", "load_state", "same_run", "run"]


@dataclass
class SwarmState:
    """Complete state of a swarm between iterations (JSON-serialisable through :func:`save_state`).

    Attributes
    ----------
    iteration : int
        Completed iterations (0: initial positions not yet evaluated).
    x, v : ndarray (n, d)
        Positions and velocities.
    p, p_f : ndarray (n, d), (n,)
        Each particle's best position and value.
    g, g_f : ndarray (d,), float
        Swarm's best position and value.
    inertia, counter, neighbours : float, int, int
        MATLAB's adaptive W, stall counter c and neighbourhood size N.
    rng : dict
        State of the numpy bit generator (PCG64) after the last random draw.
    history : list of dict
        One record per evaluated particle (whatever the objective returned, plus ``iteration`` and ``particle``).
    extra : dict
        Caller data kept with the state (e.g. the best particle's controller gain for the warm start).
    rule : str
        The adaptive rules: ``"documented"`` or ``"matlab"`` (see the module's description).
    """

    iteration: int
    x: NDArray[np.float64]
    v: NDArray[np.float64]
    p: NDArray[np.float64]
    p_f: NDArray[np.float64]
    g: NDArray[np.float64]
    g_f: float
    inertia: float
    counter: int
    neighbours: int
    rng: Mapping[str, Any]
    lower: NDArray[np.float64]
    upper: NDArray[np.float64]
    seed: int
    history: list[dict] = field(default_factory=list)
    extra: dict = field(default_factory=dict)
    rule: str = "documented"

    @property
    def n(self) -> int:
        """Swarm size."""
        return self.x.shape[0]


SELF_ADJUSTMENT = SOCIAL_ADJUSTMENT = 1.49
INERTIA_RANGE = (0.1, 1.1)
MIN_NEIGHBORS_FRACTION = 0.25
RULES = ("documented", "matlab")


def _check_rule(rule: str) -> str:
    if not isinstance(rule, str) or rule not in RULES:
        raise ValueError(f"rule must be one of {RULES} (MATLAB particleswarm's documented rules or its code's), got {rule!r}")
    return rule


def _n_min(n: int) -> int:
    """MATLAB's minimum neighbourhood size ``max(2, floor(0.25 n))``."""
    return max(2, int(np.floor(MIN_NEIGHBORS_FRACTION * n)))


def _max_neighbours(n: int, rule: str) -> int:
    """Largest neighbourhood: ``n - 1`` others (documented rule), or all ``n`` particles, itself included (MATLAB's code)."""
    return n if rule == "matlab" else n - 1


def _bounds(lower: Sequence[float], upper: Sequence[float]) -> tuple[NDArray, NDArray]:
    lo, hi = np.atleast_1d(np.asarray(lower, float)), np.atleast_1d(np.asarray(upper, float))
    if lo.shape != hi.shape or not np.all(np.isfinite(lo) & np.isfinite(hi)) or np.any(lo >= hi):
        raise ValueError(f"bounds must be finite with lower < upper componentwise, got lower={lo}, upper={hi}")
    return lo, hi


def init_swarm(n: int, lower: Sequence[float], upper: Sequence[float], seed: int, rule: str = "documented") -> SwarmState:
    """Initial swarm of ``n`` particles (not evaluated yet), adapted by ``rule`` (``"documented"`` or ``"matlab"``)."""
    check_option("n (swarm size)", n, 2, integer=True)
    check_option("seed", seed, 0, integer=True)
    _check_rule(rule)
    lo, hi = _bounds(lower, upper)
    rng = np.random.default_rng(seed)
    x = lo + (hi - lo) * rng.random((n, lo.size))
    span = hi - lo
    v = span * (2 * rng.random((n, lo.size)) - 1)
    return SwarmState(0, x, v, x.copy(), np.full(n, np.inf), x[0].copy(), np.inf, INERTIA_RANGE[1], 0,
                      min(_n_min(n), _max_neighbours(n, rule)), rng.bit_generator.state, lo, hi, int(seed), rule=rule)


def _rng(state: SwarmState) -> np.random.Generator:
    rng = np.random.default_rng()
    rng.bit_generator.state = state.rng
    return rng


def step_positions(state: SwarmState) -> SwarmState:
    """New velocities and positions from the particle and neighbourhood bests (MATLAB's update)."""
    rng = _rng(state)
    n, d = state.x.shape
    v = np.empty_like(state.v)
    n_others = state.neighbours - 1 if state.rule == "matlab" else state.neighbours  # MATLAB's code counts the particle
    for i in range(n):
        others = np.delete(np.arange(n), i)
        hood = rng.choice(others, size=n_others, replace=False)
        best = hood[np.argmin(state.p_f[hood])]
        g_local = state.p[best] if state.p_f[best] < state.p_f[i] else state.p[i]
        u1, u2 = rng.random(d), rng.random(d)
        v[i] = state.inertia * state.v[i] + SELF_ADJUSTMENT * u1 * (state.p[i] - state.x[i]) + SOCIAL_ADJUSTMENT * u2 * (g_local - state.x[i])
    x = state.x + v
    clipped = (x < state.lower) | (x > state.upper)
    x = np.clip(x, state.lower, state.upper)
    v[clipped] = 0.0
    state.x, state.v, state.rng = x, v, rng.bit_generator.state
    return state


def update_bests(state: SwarmState, values: Sequence[float]) -> bool:
    """Record the values of the current positions; adapt W, c and N. Returns True if the swarm's best improved."""
    f = np.asarray(values, float)
    if f.shape != (state.n,):
        raise ValueError(f"need one value per particle ({state.n}), got shape {f.shape}")
    f = np.where(np.isfinite(f), f, np.inf)
    better = f < state.p_f
    state.p[better], state.p_f[better] = state.x[better], f[better]
    i = int(np.argmin(state.p_f))
    improved = state.p_f[i] < state.g_f
    n_min, n_max = _n_min(state.n), _max_neighbours(state.n, state.rule)
    if improved:
        state.g, state.g_f = state.p[i].copy(), float(state.p_f[i])
        state.counter = max(0, state.counter - 1)
        state.neighbours = min(n_min, n_max)
    else:
        state.counter += 1
        state.neighbours = min(state.neighbours + n_min, n_max)
    if improved or state.rule == "matlab":  # the documented text adapts W on improvement only, MATLAB's code always
        if state.counter < 2:
            state.inertia *= 2.0
        elif state.counter > 5:
            state.inertia /= 2.0
        state.inertia = float(np.clip(state.inertia, *INERTIA_RANGE))
    state.iteration += 1
    return bool(improved)


def save_state(state: SwarmState, path: str | Path) -> Path:
    """Write the state as JSON, atomically (a crash while writing leaves the previous checkpoint intact)."""
    from ..infra.results import to_jsonable, write_json

    payload = {k: to_jsonable(getattr(state, k)) for k in state.__dataclass_fields__}
    payload["g_f"] = state.g_f if np.isfinite(state.g_f) else None
    payload["p_f"] = [v if np.isfinite(v) else None for v in state.p_f.tolist()]
    return write_json(path, payload)


def load_state(path: str | Path) -> SwarmState:
    """Read a state written by :func:`save_state` (non-finite values in the history restored as floats; a checkpoint
    written before the rules were selectable has the documented ones)."""
    from ..infra.results import from_jsonable, read_json

    d = read_json(path)
    arr = lambda k: np.array(d[k], dtype=float)  # noqa: E731
    p_f = np.array([np.inf if v is None else v for v in d["p_f"]], dtype=float)
    rng = d["rng"]
    rng["state"] = {k: int(v) for k, v in rng["state"].items()}
    return SwarmState(int(d["iteration"]), arr("x"), arr("v"), arr("p"), p_f, arr("g"), np.inf if d["g_f"] is None else float(d["g_f"]),
                      float(d["inertia"]), int(d["counter"]), int(d["neighbours"]), rng, arr("lower"), arr("upper"), int(d["seed"]),
                      from_jsonable(d["history"]), from_jsonable(d["extra"]), _check_rule(d.get("rule", "documented")))


def same_run(state: SwarmState, n: int, lower: ArrayLike, upper: ArrayLike, seed: int, rule: str) -> bool:
    """Whether a stored swarm ``state`` is of the run with this size, bounds, seed and rule (the one a checkpoint
    may be resumed by)."""
    same_bounds = (np.array_equal(state.lower, np.atleast_1d(np.asarray(lower, float)))
                   and np.array_equal(state.upper, np.atleast_1d(np.asarray(upper, float))))
    return state.n == n and state.seed == seed and same_bounds and state.rule == rule


def run(evaluate: Callable[[NDArray, SwarmState], list[dict]], n: int, lower: Sequence[float], upper: Sequence[float],
        iterations: int, seed: int = 0, checkpoint: str | Path | None = None, on_iteration: Callable[[SwarmState], None] | None = None,
        stop_after: int | None = None, rule: str = "documented") -> SwarmState:
    """Run (or resume) a particle swarm.

    Parameters
    ----------
    evaluate : callable
        ``evaluate(positions (n, d), state) -> list of n dicts`` each with at least ``"f"`` (the value to minimise;
        non-finite means failed). It sees the state (e.g. ``state.extra`` for a warm start) and may update
        ``state.extra``.
    n, lower, upper, iterations, seed
        Swarm size, bounds, number of iterations (the initial swarm counts as the first), random seed.
    checkpoint : path, optional
        JSON file written after every iteration; if it exists when the run starts, the run resumes from it
        (its swarm size, bounds, seed and rule must match).
    on_iteration : callable, optional
        Called with the state after every iteration (e.g. to print a summary).
    stop_after : int, optional
        Stop (as if interrupted) once this many iterations are complete; for tests of the resume.
    rule : {"documented", "matlab"}
        MATLAB ``particleswarm``'s adaptive rules as its documentation states them (default) or as its code applies
        them (see the module's description).

    Raises
    ------
    TypeError, ValueError
        For a non-integer or out-of-range ``n`` (>= 2), ``iterations`` (>= 1), ``seed`` (>= 0) or ``stop_after``
        (>= 0), an unknown ``rule``, or bounds that are not finite with ``lower < upper``, before anything is
        evaluated; for a checkpoint of another run (size, seed, bounds or rule) or with more completed iterations than
        ``iterations``.
    """
    check_option("n (swarm size)", n, 2, integer=True)
    check_option("iterations", iterations, 1, integer=True)
    check_option("seed", seed, 0, integer=True)
    if stop_after is not None:
        check_option("stop_after", stop_after, 0, integer=True)
    _check_rule(rule)
    lo, hi = _bounds(lower, upper)
    if checkpoint is not None and Path(checkpoint).exists():
        state = load_state(checkpoint)
        if not same_run(state, n, lo, hi, seed, rule):
            raise ValueError(f"checkpoint {checkpoint} is from another run (n={state.n}, seed={state.seed}, bounds "
                             f"[{state.lower}, {state.upper}], rule {state.rule!r}): delete it or choose another results folder")
        if state.iteration > iterations:
            raise ValueError(f"checkpoint {checkpoint} holds {state.iteration} completed iterations, more than the "
                             f"{iterations} asked: ask for {state.iteration} or more, or choose another results folder")
    else:
        state = init_swarm(n, lower, upper, seed, rule)
    while state.iteration < iterations:
        if stop_after is not None and state.iteration >= stop_after:
            break
        if state.iteration > 0:
            state = step_positions(state)
        records = evaluate(state.x.copy(), state)
        if len(records) != n:
            raise ValueError(f"evaluate returned {len(records)} records for {n} particles")
        for i, r in enumerate(records):
            state.history.append({**r, "iteration": state.iteration, "particle": i})
        update_bests(state, [r["f"] for r in records])
        if checkpoint is not None:
            save_state(state, checkpoint)
        if on_iteration is not None:
            on_iteration(state)
    return state
