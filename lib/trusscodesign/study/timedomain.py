"""Time-domain view of a worst case: the response from rest to the worst sinusoidal disturbance.

Beyond the paper, whose performance indices are H-infinity norms: ``J_c = sup_w sigma_max(T(jw))`` is the
steady-state amplitude (2-norm over the outputs) when the normalised SADM torques ``p~`` are a sinusoid of unit
2-norm at the critical frequency, the two torques in the ratio and phase of the top right singular vector ``v`` of
``T(jw)`` (so neither SADM reaches p_max alone). :func:`sine_response` simulates that from rest by time stepping (:func:`control.forced_response`: exact
for an input linear between samples), and :func:`exact_sine_response` gives the same response in closed form,

``x(t) = Re(X e^{jwt}) - e^{At} Re(X)``,  ``X = (jwI - A)^-1 B v``,  ``y = C x + D Re(v e^{jwt})``,

with ``e^{At}`` applied through the eigen-decomposition of ``A``: two independent methods, which the notebooks
compare. Driven from rest at ``w`` close to the damped frequency of a lightly damped pole ``lambda`` that dominates
the response (``|w - Im lambda| << -Re lambda``, as at a resonance peak), the output's envelope grows as
``1 - e^{t Re lambda}``; detuned, ``|1 - e^{(lambda - jw) t}|`` beats. With the damping left on these structures
(3e-4 to 4e-3 after control) the worst case takes minutes to build up.
"""

from __future__ import annotations

from dataclasses import dataclass

import control as ct
import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..infra.checks import check_option
from ..control.closedloop import GeneralizedPlant

__all__ = ["SineResponse", "worst_direction", "sine_response", "exact_sine_response", "loop_sine_response"]

# eigenvector condition number above which exact_sine_response refuses A: its error grows as that number times 1e-16
# (a review measured 5e-13, 4e-11, 4e-9 at 2e4, 2e6, 2e8, and 0.4 of the response for a Jordan block); 1e10 keeps it
# near 1e-6. The spacecraft's closed loops reach 2e8 (the smoke run's design: a limit of 1e8 refused it)
MAX_EIGVEC_COND = 1e10


@dataclass(frozen=True)
class SineResponse:
    """Response from rest to the input ``Re(v e^{j omega t})``.

    Attributes
    ----------
    t : ndarray (n,)
        Time [s].
    inputs : ndarray (m, n)
        Input, ``Re(v e^{j omega t})`` (unit amplitude in the 2-norm of ``v``).
    outputs : ndarray (q, n)
        Output, simulated by time stepping.
    omega : float
        Input frequency [rad/s].
    direction : ndarray (m,), complex
        ``v``: the top right singular vector of the transfer at ``omega`` (unless given).
    steady : ndarray (q,), complex
        ``T(j omega) v``: the complex amplitude of the steady-state output.
    sigma : float
        Largest singular value of ``T(j omega)``: ``|T(j omega) v|`` when ``v`` is the worst direction.
    """

    t: NDArray[np.float64]
    inputs: NDArray[np.float64]
    outputs: NDArray[np.float64]
    omega: float
    direction: NDArray[np.complex128]
    steady: NDArray[np.complex128]
    sigma: float

    def amplitude(self, periods: int = 10) -> NDArray[np.complex128]:
        """Complex amplitude of each output at ``omega``, fitted over the last ``periods`` whole periods.

        The Fourier coefficient ``2/T int y(t) e^{-j omega t} dt`` over those periods (trapezoidal rule on the samples);
        it tends to :attr:`steady` as the transient decays.
        """
        check_option("periods", periods, 1, integer=True)
        window = self.t >= self.t[-1] - periods * 2 * np.pi / self.omega - 1e-9 * self.t[-1]
        t, y = self.t[window], self.outputs[:, window]
        span = t[-1] - t[0]
        if span < 0.999 * periods * 2 * np.pi / self.omega:
            raise ValueError(f"periods={periods}: the record holds only {self.omega * (self.t[-1] - self.t[0]) / (2 * np.pi):.1f} "
                             "periods; simulate longer or fit fewer periods")
        return 2.0 * np.trapezoid(y * np.exp(-1j * self.omega * t), t, axis=1) / span


def _checked(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike) -> tuple[NDArray, ...]:
    a, b, c, d = (np.asarray(x, dtype=float) for x in (a, b, c, d))
    n = a.shape[0]
    if a.shape != (n, n) or b.shape[0] != n or c.shape[1] != n or d.shape != (c.shape[0], b.shape[1]):
        raise ValueError(f"inconsistent state-space shapes: A {a.shape}, B {b.shape}, C {c.shape}, D {d.shape}")
    if not all(np.all(np.isfinite(x)) for x in (a, b, c, d)):
        raise ValueError("the state-space matrices must be finite")
    return a, b, c, d


def _transfer(a: NDArray, b: NDArray, c: NDArray, d: NDArray, omega: float) -> tuple[NDArray, NDArray]:
    """``X = (j omega I - A)^-1 B`` and ``T(j omega) = C X + D``."""
    x = np.linalg.solve(1j * omega * np.eye(a.shape[0]) - a, b)
    return x, c @ x + d


def _top(t_w: NDArray) -> tuple[float, NDArray]:
    """Largest singular value of ``T(j omega)`` and its input direction (the top right singular vector)."""
    _, s, vh = np.linalg.svd(t_w)
    return float(s[0]), vh[0].conj()


def worst_direction(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike, omega: float) -> tuple[float, NDArray[np.complex128]]:
    """Largest singular value of ``T(j omega)`` and its input direction (unit complex vector; any unit vector of the
    top singular subspace if the largest singular value is repeated).

    Parameters
    ----------
    a, b, c, d : array_like
        State-space model.
    omega : float
        Frequency [rad/s], > 0.
    """
    a, b, c, d = _checked(a, b, c, d)
    check_option("omega", omega, 0.0, open_low=True)
    return _top(_transfer(a, b, c, d, omega)[1])


def sine_response(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike, omega: float, duration: float,
                  samples_per_period: int = 32, direction: ArrayLike | None = None) -> SineResponse:
    """Simulate from rest the response to ``Re(v e^{j omega t})`` (time stepping, :func:`control.forced_response`).

    Parameters
    ----------
    a, b, c, d : array_like
        Stable state-space model (e.g. a closed loop).
    omega : float
        Input frequency [rad/s], > 0.
    duration : float
        Simulated time [s], from one period to 1e6 periods of the input.
    samples_per_period : int
        Time steps per period of the input (>= 8). The step is exact for an input linear between samples: the error
        is that of the linear interpolation of the sinusoid, whose component at ``omega`` is ``sinc^2(pi / n)`` of it,
        ``n = samples_per_period``: for a strictly proper model small at ``(n +- 1) omega`` (as at a resonance), the
        steady-state amplitude comes out ``pi^2 / (3 n^2)`` low (3.2e-3 at 32), and the response is that of the
        sinusoid of direction ``sinc^2(pi / n) v``.
    direction : array_like (m,), optional
        Complex input direction ``v`` (normalised to unit 2-norm); default the worst one (:func:`worst_direction`).
    """
    a, b, c, d = _checked(a, b, c, d)
    check_option("omega", omega, 0.0, open_low=True)
    check_option("samples_per_period", samples_per_period, 8, integer=True)
    abscissa = float(np.linalg.eigvals(a).real.max()) if a.size else -np.inf
    if abscissa >= 0:
        raise ValueError(f"the model is not stable (largest real part of a pole {abscissa:.3g} 1/s): it has no steady state")
    period = 2 * np.pi / omega
    check_option("duration", duration, period, 1e6 * period)
    _, t_w = _transfer(a, b, c, d, omega)
    sigma, v = _top(t_w)
    if direction is not None:
        v = np.asarray(direction, dtype=complex).ravel()
        if v.shape != (b.shape[1],) or not np.all(np.isfinite(v)) or np.linalg.norm(v) == 0:
            raise ValueError(f"direction must be a finite nonzero vector of {b.shape[1]} entries, got {np.shape(direction)}")
        v = v / np.linalg.norm(v)
    n_steps = int(np.ceil(duration / period * samples_per_period))
    t = (np.arange(n_steps + 1) * (period / samples_per_period)).astype(np.float64)
    u = np.real(np.outer(v, np.exp(1j * omega * t)))
    sim = ct.forced_response(ct.ss(a, b, c, d), t, u, squeeze=False)
    outputs = np.asarray(sim.outputs).reshape(c.shape[0], t.size)
    return SineResponse(t, u, outputs, float(omega), v, t_w @ v, sigma)


def exact_sine_response(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike, omega: float, direction: ArrayLike,
                        t: ArrayLike) -> NDArray[np.float64]:
    """Closed-form response from rest to ``Re(v e^{j omega t})`` at the times ``t`` [s].

    ``y(t) = Re((C X + D v) e^{j omega t}) - C e^{At} Re(X)``, ``X = (j omega I - A)^-1 B v``, with ``e^{At}``
    through the eigen-decomposition ``A = V diag(lambda) V^-1``; ``v`` is used as given (not normalised). Returns the
    outputs, shape (q, len(t)).

    Raises
    ------
    ValueError
        If ``A`` is defective or nearly so (condition number of ``V`` above ``MAX_EIGVEC_COND``): the error of the
        eigen-decomposition grows as that condition number times the machine precision.
    """
    a, b, c, d = _checked(a, b, c, d)
    check_option("omega", omega, 0.0, open_low=True)
    v = np.asarray(direction, dtype=complex).ravel()
    if v.shape != (b.shape[1],) or not np.all(np.isfinite(v)):
        raise ValueError(f"direction must be a finite vector of {b.shape[1]} entries, got shape {np.shape(direction)}")
    t = np.asarray(t, dtype=float).ravel()
    x, t_w = _transfer(a, b, c, d, omega)
    lam, vec = np.linalg.eig(a)
    cond = np.linalg.cond(vec)
    if not cond <= MAX_EIGVEC_COND:
        raise ValueError(f"A is defective or nearly so (eigenvector condition number {cond:.2g} > {MAX_EIGVEC_COND:g}): "
                         "the closed form through eig is not accurate; use sine_response (time stepping)")
    z0 = np.linalg.solve(vec, (x @ v).real)  # the initial state X_r in modal coordinates
    transient = (c @ vec) @ (z0[:, None] * np.exp(np.outer(lam, t)))
    return np.real(np.outer(t_w @ v, np.exp(1j * omega * t))) - transient.real


def loop_sine_response(plant: GeneralizedPlant, gain: ArrayLike, group: str, omega: float, duration: float,
                       samples_per_period: int = 32) -> SineResponse:
    """:func:`sine_response` of the closed loop ``p~ -> group`` (``"rpe"`` or ``"effort"``) with a static PMA gain.

    Parameters
    ----------
    plant : trusscodesign.control.closedloop.GeneralizedPlant
        Without open Delta channels (e.g. :func:`trusscodesign.control.synthesis.plant_at` at a worst-case scenario).
    gain : array_like (4, 8)
        PMA gain.
    group : str
        ``"rpe"``: outputs RPE / eps_max (2 LOS axes); ``"effort"``: PMA efforts / u_max (4).
    omega, duration, samples_per_period
        As :func:`sine_response` ([rad/s], [s]).
    """
    if group not in ("rpe", "effort"):
        raise ValueError(f"group must be 'rpe' or 'effort', got {group!r}")
    if plant.n_delta:
        raise ValueError("loop_sine_response needs a plant without open Delta channels (substitute the uncertain parameters)")
    a, b, c, d = plant.closed_loop_matrices(gain)
    sl = plant.slices()
    return sine_response(a, b[:, sl["p"]], c[sl[group]], d[sl[group], sl["p"]], omega, duration, samples_per_period)
