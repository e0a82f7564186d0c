"""Thrust allocation: body wrench <-> thruster thrusts (paper Eq. 11, ``f0 = Lambda T``).

Each thruster ``h`` at position ``r_h`` (body frame, from the vehicle's centre of mass) pushing along the
unit direction ``e_h`` contributes the column ``[r_h x e_h; e_h]`` (``[moment; force]``) to the
``(6, m)`` matrix ``Lambda``.

Allocation inverts ``Lambda`` under thrust limits ``lower <= T <= upper``:

* :func:`allocate` -- saturation-aware least squares. It minimises ``|Lambda T - wrench|`` within the limits
  and, among the minimisers, returns the one of minimum norm ``|T|``. The minimum-norm least-squares
  solution ``pinv(Lambda) wrench`` is tried first: if it is within the limits it is the answer. Otherwise the
  bounded least-squares problem is solved with :func:`scipy.optimize.lsq_linear` (BVLS); the wrench it
  achieves is unique, and if ``Lambda`` has a null space (redundant thrusters) a second stage picks the
  minimum-norm thrust achieving that wrench within the limits (SLSQP).
* :func:`allocate_pinv` -- compiled fast path for the closed loop: a precomputed pseudo-inverse and a clip.
  Exact when nothing saturates; **not optimal under saturation** (clipping one thruster does not
  redistribute the load over the others, so the residual can be larger than :func:`allocate`'s).

The part of a wrench that no thrust can produce is its projection onto the orthogonal complement of the
column space of ``Lambda`` (:func:`unachievable_directions`, :func:`unachievable_part`). Moments [N m] and
forces [N] are compared as plain numbers there, which is exact for the axis-aligned layouts bundled in
:mod:`uvms.thrusters.layouts` (their complement is spanned by body axes).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit


def allocation_matrix(positions: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """``Lambda`` (6, m) with column ``[r x e; e]`` for thrusters at ``positions`` (m, 3) [m] along ``directions``.

    ``directions`` (m, 3) are normalised to unit length (a zero direction is an error).
    """
    positions = np.atleast_2d(np.asarray(positions, dtype=float))
    directions = np.atleast_2d(np.asarray(directions, dtype=float))
    if positions.shape != directions.shape or positions.shape[-1] != 3:
        raise ValueError(f"positions and directions must both be (m, 3), got {positions.shape} and "
                         f"{directions.shape}")
    norms = np.linalg.norm(directions, axis=1)
    if np.any(~np.isfinite(norms)) or np.any(norms < 1e-12):
        raise ValueError("thruster directions must be finite and non-zero")
    e = directions / norms[:, None]
    return np.vstack([np.cross(positions, e).T, e.T])


@dataclass(frozen=True, eq=False)
class AllocationResult:
    """Outcome of :func:`allocate`.

    Attributes:
        thrust: (m,) thrusts [N], within ``[lower, upper]``.
        achieved: (6,) wrench ``Lambda @ thrust`` ``[moment; force]`` [N m, N].
        residual: (6,) ``wrench - achieved``: what was asked for and is not produced.
        saturated: (m,) True where a thrust sits at its lower or upper limit.
        unachievable: (6,) the part of the wrench outside the column space of ``Lambda`` (no thrust can
            produce it, whatever the limits); ``residual - unachievable`` is the loss due to saturation.
    """

    thrust: np.ndarray
    achieved: np.ndarray
    residual: np.ndarray
    saturated: np.ndarray
    unachievable: np.ndarray


def _check(Lambda: np.ndarray, wrench: np.ndarray, lower, upper):
    Lambda = np.asarray(Lambda, dtype=float)
    if Lambda.ndim != 2 or Lambda.shape[0] != 6:
        raise ValueError(f"Lambda must be (6, m), got {Lambda.shape}")
    m = Lambda.shape[1]
    wrench = np.asarray(wrench, dtype=float).reshape(-1)
    if wrench.shape != (6,):
        raise ValueError(f"wrench must be (6,), got {wrench.shape}")
    lower = np.broadcast_to(np.asarray(lower, dtype=float), (m,)).copy()
    upper = np.broadcast_to(np.asarray(upper, dtype=float), (m,)).copy()
    if np.any(lower >= upper):
        raise ValueError("thrust limits need lower < upper for every thruster")
    if not np.all(np.isfinite(wrench)):
        raise ValueError("wrench must be finite")
    return Lambda, wrench, lower, upper


def unachievable_directions(Lambda: np.ndarray, *, rtol: float = 1e-10) -> np.ndarray:
    """(6, k) orthonormal basis of the wrench directions no thrust can produce (left null space of ``Lambda``)."""
    Lambda = np.asarray(Lambda, dtype=float)
    U, s, _ = np.linalg.svd(Lambda, full_matrices=True)
    rank = int(np.sum(s > rtol * max(1.0, s.max(initial=0.0))))
    return U[:, rank:]


def unachievable_part(Lambda: np.ndarray, wrench: np.ndarray) -> np.ndarray:
    """(6,) projection of ``wrench`` onto :func:`unachievable_directions`: the part no thrust can produce."""
    N = unachievable_directions(Lambda)
    return N @ (N.T @ np.asarray(wrench, dtype=float))


def _saturation_flags(thrust, lower, upper, tol):
    return (thrust <= lower + tol * np.maximum(1.0, np.abs(lower))) | (
        thrust >= upper - tol * np.maximum(1.0, np.abs(upper)))


def allocate(Lambda: np.ndarray, wrench: np.ndarray, lower: np.ndarray | float, upper: np.ndarray | float,
             *, weights: np.ndarray | None = None, tol: float = 1e-9) -> AllocationResult:
    """Thrusts (m,) in ``[lower, upper]`` that best produce ``wrench`` (6,) ``[moment; force]``.

    Minimises ``|W (Lambda T - wrench)|``, then ``|T|`` among the minimisers (see the module docstring).
    ``lower`` and ``upper`` are (m,) or scalars [N]; ``weights`` (6,) (default all ones) sets ``W = diag(weights)``,
    the price of a unit residual per wrench component (moments in N m and forces in N are otherwise weighed
    alike); ``tol`` is the relative tolerance of the saturation flags.
    """
    Lambda, wrench, lower, upper = _check(Lambda, wrench, lower, upper)
    m = Lambda.shape[1]
    w = np.ones(6) if weights is None else np.asarray(weights, dtype=float).reshape(-1)
    if w.shape != (6,) or np.any(~np.isfinite(w)) or np.any(w <= 0):
        raise ValueError(f"weights must be 6 positive numbers, got {weights!r}")
    A, b = w[:, None] * Lambda, w * wrench
    thrust = np.linalg.pinv(A) @ b
    if np.any(thrust < lower) or np.any(thrust > upper):
        from scipy.optimize import lsq_linear

        fit = lsq_linear(A, b, bounds=(lower, upper), method="bvls", tol=1e-14)
        thrust = np.clip(fit.x, lower, upper)
        if np.linalg.matrix_rank(A) < m:  # redundant thrusters: the minimiser is not unique
            thrust = _minimum_norm_refinement(A, thrust, lower, upper)
    achieved = Lambda @ thrust
    return AllocationResult(
        thrust=thrust,
        achieved=achieved,
        residual=wrench - achieved,
        saturated=_saturation_flags(thrust, lower, upper, tol),
        unachievable=unachievable_part(Lambda, wrench),
    )


def _minimum_norm_refinement(Lambda, thrust, lower, upper):
    """Minimum ``|T|`` with ``Lambda T = Lambda thrust`` and ``lower <= T <= upper`` (QP by SLSQP).

    The equality is imposed on the ``rank`` independent combinations ``V_r^T T`` (``Lambda = U S V^T``).
    """
    from scipy.optimize import minimize

    _, s, Vt = np.linalg.svd(Lambda)
    rows = Vt[: int(np.sum(s > 1e-10 * max(1.0, s.max(initial=0.0))))]  # (rank, m)
    limits = np.concatenate([lower, upper, thrust])
    scale = max(1.0, float(np.max(np.abs(limits[np.isfinite(limits)]))))  # solve in O(1) units
    target = rows @ thrust / scale
    bounds = [(lo / scale if np.isfinite(lo) else None, hi / scale if np.isfinite(hi) else None)
              for lo, hi in zip(lower, upper)]
    result = minimize(
        lambda x: 0.5 * float(x @ x), thrust / scale, jac=lambda x: x, method="SLSQP", bounds=bounds,
        constraints=[{"type": "eq", "fun": lambda x: rows @ x - target, "jac": lambda x: rows}],
        options={"ftol": 1e-16, "maxiter": 500},
    )
    candidate = np.clip(result.x * scale, lower, upper)
    achieved = Lambda @ thrust
    # Keep the refinement only if it keeps the achieved wrench and lowers the norm.
    if (np.linalg.norm(Lambda @ candidate - achieved) <= 1e-9 * max(1.0, np.linalg.norm(achieved))
            and candidate @ candidate <= thrust @ thrust):
        return candidate
    return thrust


@njit(cache=True)
def allocate_pinv(Lambda_pinv: np.ndarray, wrench: np.ndarray, lower: np.ndarray, upper: np.ndarray,
                  out: np.ndarray) -> None:
    """Fast allocation: ``out = clip(Lambda_pinv @ wrench, lower, upper)`` (compiled, no allocation).

    ``Lambda_pinv`` (m, 6) is ``np.linalg.pinv(Lambda)``, computed once; ``out`` is (m,). Exact when nothing
    saturates; under saturation it is **not** the bounded least-squares optimum of :func:`allocate`.
    """
    m = Lambda_pinv.shape[0]
    for h in range(m):
        value = 0.0
        for k in range(6):
            value += Lambda_pinv[h, k] * wrench[k]
        out[h] = min(max(value, lower[h]), upper[h])
