"""The mass / pointing trade-off: non-dominated designs, the area they dominate, and the expected gain of a candidate.

Both objectives are minimised: the truss mass ``m`` [kg] and a pointing measure ``y`` (the worst-case J_c, or its log).
The mass of a design is known exactly (closed form of its section sides); its pointing is what an expensive robust
synthesis returns, so a search predicts it (a normal prediction ``mu``, ``sigma``) before paying for it.
:func:`expected_improvement` is the expected growth of the dominated area (hypervolume) if the candidate were added,
in closed form for that case (no Monte Carlo). Written here, not taken from a multi-objective library, because those
model every objective as uncertain; with one exact objective the expectation is a one-dimensional integral.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import ndtr

__all__ = ["expected_improvement", "hypervolume", "nondominated"]


def _pair(m: ArrayLike, y: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    m, y = np.asarray(m, dtype=float).ravel(), np.asarray(y, dtype=float).ravel()
    if m.shape != y.shape:
        raise ValueError(f"mass and pointing must have the same length, got {m.size} and {y.size}")
    return m, y


def nondominated(m: ArrayLike, y: ArrayLike) -> NDArray[np.intp]:
    """Indices of the non-dominated points, by increasing mass (of equal points, the first).

    Parameters
    ----------
    m, y : array_like (n,)
        Mass [kg] and pointing of each point, both minimised.
    """
    m, y = _pair(m, y)
    order = np.lexsort((np.arange(m.size), y, m))  # by mass, then pointing, then position
    keep, best = [], np.inf
    for i in order:
        if y[i] < best:
            keep.append(i)
            best = y[i]
    return np.asarray(keep, dtype=np.intp)


def _front(m: NDArray[np.float64], y: NDArray[np.float64], ref: Sequence[float]) -> tuple[NDArray, NDArray]:
    """The non-dominated points strictly inside the reference box, by increasing mass (decreasing pointing)."""
    idx = nondominated(m, y)
    inside = (m[idx] < ref[0]) & (y[idx] < ref[1])
    return m[idx][inside], y[idx][inside]


def hypervolume(m: ArrayLike, y: ArrayLike, ref: Sequence[float]) -> float:
    """Area of the (mass, pointing) box below ``ref`` dominated by the points [kg x pointing unit]."""
    fm, fy = _front(*_pair(m, y), ref)
    widths = np.diff(np.append(fm, ref[0]))
    return float(np.sum(widths * (ref[1] - fy)))


def _psi(z: NDArray[np.float64]) -> NDArray[np.float64]:
    """z Phi(z) + phi(z): the integral of Phi from -inf to z (0 at z = -inf)."""
    out = np.zeros_like(z)
    finite = np.isfinite(z)
    zf = z[finite]
    out[finite] = zf * ndtr(zf) + np.exp(-0.5 * zf**2) / np.sqrt(2 * np.pi)
    out[z == np.inf] = np.inf
    return out


def expected_improvement(mass: ArrayLike, mu: ArrayLike, sigma: ArrayLike, m: ArrayLike, y: ArrayLike,
                         ref: Sequence[float]) -> NDArray[np.float64]:
    """Expected hypervolume improvement of candidates with exact mass and normally predicted pointing.

    With the front's mass M(t) = min{m_i : y_i <= t}, a candidate (mass, y) adds the area
    ``int_y^ref_y max(0, min(M(t), ref_m) - mass) dt``; its expectation over y ~ N(mu, sigma^2) is a sum over the
    front's steps of ``c_j sigma [psi((b_j+1 - mu)/sigma) - psi((b_j - mu)/sigma)]``, psi(z) = z Phi(z) + phi(z).

    Parameters
    ----------
    mass, mu, sigma : array_like (n,)
        Each candidate's exact mass [kg] and the mean and standard deviation (> 0) of its predicted pointing.
    m, y : array_like (p,)
        The evaluated points (mass, pointing); only the non-dominated ones matter.
    ref : (float, float)
        Reference point (mass, pointing): the box the area is counted in.

    Returns
    -------
    ndarray (n,)
        The expected improvement of each candidate [kg x pointing unit].
    """
    mass, mu = _pair(mass, mu)
    sigma = np.asarray(sigma, dtype=float).ravel()
    if sigma.shape != mu.shape or not np.all(sigma > 0):
        raise ValueError(f"sigma must be positive, one per candidate, got {sigma!r}")
    fm, fy = _front(*_pair(m, y), ref)
    # steps by increasing pointing: below the best pointing nothing dominates (M = ref_m), then M = fm[j]
    order = np.argsort(fy)
    edges = np.concatenate([[-np.inf], fy[order], [ref[1]]])            # (p + 2,)
    level = np.concatenate([[ref[0]], np.minimum(fm[order], ref[0])])   # M on each step, (p + 1,)
    c = np.maximum(0.0, level[None, :] - mass[:, None])                 # (n, p + 1)
    z = (edges[None, :] - mu[:, None]) / sigma[:, None]                 # (n, p + 2)
    pieces = sigma[:, None] * np.diff(_psi(z), axis=1)                  # (n, p + 1)
    return np.sum(c * pieces, axis=1)
