"""Compiled thrust allocation and thrust -> command: what the simulation does with a controller's body wrench.

:func:`allocate_command` turns a commanded body wrench ``[K M N X Y Z]`` into the held actuator commands of a
thruster layout (paper Eq. 11, ``f0 = Lambda T``):

1. the minimum-norm least-squares thrust ``pinv(Lambda) wrench`` (precomputed pseudo-inverse);
2. only if that violates a thrust limit, the saturation-aware bounded least squares of
   :func:`uvms.thrusters.allocation.allocate`, compiled (:func:`bounded_least_squares`): minimise
   ``|Lambda T - wrench|`` within ``lower <= T <= upper`` and, among the minimisers, ``|T|``;
3. per thruster, thrust -> command (:func:`uvms.thrusters.kinds.command_for_thrust`): Healey's steady-state
   voltage (:func:`~uvms.thrusters.healey.healey_voltage_for_thrust`), a table thruster's inverse table
   (:func:`~uvms.thrusters.table.table_command`), or the thrust itself (first-order and ideal thrusters).

With no thrusters (ideal actuation) the command is the wrench itself. The logged signals are the thrusts and
the part of the wrench not produced (``thrust_cmd_<name>``, ``unachieved_<K..Z>``; :func:`thrust_command_names`).

Bounded least squares, compiled. A primal active-set method (Lawson and Hanson, Ch. 23) on the strictly convex
``min 1/2 |Lambda T - w|^2 + 1/2 eps |T|^2`` (``eps = 1e-12 |Lambda|_F^2``) finds which thrusters sit at a
limit; on that face the free thrusts are then recomputed exactly as the minimum-norm least-squares solution
``T_F = pinv(Lambda_F) (w - Lambda_B T_B)`` (the ``eps -> 0`` limit), which is the least residual. The regularisation keeps every
subproblem's solution unique, so the active set cannot cycle on layouts with redundant thrusters. With a
null space (rank < m) the minimiser is not unique: a second active-set pass
(:func:`minimum_norm_refinement`) finds the least ``|T|`` producing that same wrench within the limits, as
:func:`uvms.thrusters.allocation.allocate` does with SLSQP.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from uvms.jit import allocating, kernel
from uvms.thrusters.kinds import command_for_thrust, kind_of

LABELS = ("K", "M", "N", "X", "Y", "Z")


class ThrustCommand(NamedTuple):
    """A layout's compiled allocation data (numba type independent of the layout)."""

    m: int                      # number of thrusters (0: ideal actuation)
    Lambda: np.ndarray          # (6, m) allocation matrix (Eq. 11)
    pinv: np.ndarray            # (m, 6) its pseudo-inverse
    lower: np.ndarray           # (m,) thrust limits [N]
    upper: np.ndarray           # (m,)
    regularisation: float       # eps of the active-set search
    kind: np.ndarray            # (m,) int64 thruster kinds (uvms.thrusters.kinds)
    params: np.ndarray          # (m, P) each thruster's kernel parameters (rows zero-padded)
    coefficients: np.ndarray    # (m, 3) Healey steady-state coefficients (zeros for others)
    redundant: bool             # rank(Lambda) < m: minimum-norm refinement among the minimisers
    thrust: np.ndarray          # (m,) scratch: the allocated thrusts
    side: np.ndarray            # (m,) int64 scratch: -1 at lower, +1 at upper, 0 free


def thrust_command(thrusters) -> ThrustCommand:
    """The :class:`ThrustCommand` of a layout (a tuple of :class:`~uvms.thrusters.layouts.Thruster`; empty:
    ideal actuation, the command is the wrench)."""
    from uvms.thrusters.healey import steady_coefficients
    from uvms.thrusters.layouts import layout_matrix, thrust_limits

    thrusters = tuple(thrusters)
    m = len(thrusters)
    Lambda = np.ascontiguousarray(layout_matrix(thrusters), dtype=float).reshape(6, m)
    pinv = np.ascontiguousarray(np.linalg.pinv(Lambda)) if m else np.zeros((0, 6))
    lower, upper = thrust_limits(thrusters) if m else (np.zeros(0), np.zeros(0))
    rows = [t.parameters.as_array() if t.model in ("healey", "table") else np.zeros(1) for t in thrusters]
    params = np.zeros((m, max([r.size for r in rows], default=1)))
    for j, r in enumerate(rows):
        params[j, :r.size] = r
    kind = np.array([kind_of(t.model) for t in thrusters], dtype=np.int64)
    coefficients = np.zeros((m, 3))
    for j, t in enumerate(thrusters):
        if t.model == "healey":
            coefficients[j] = steady_coefficients(t.parameters)
    eps = 1e-12 * max(float(np.sum(Lambda * Lambda)), 1e-300)
    return ThrustCommand(m=m, Lambda=Lambda, pinv=pinv, lower=np.array(lower, dtype=float),
                         upper=np.array(upper, dtype=float), regularisation=eps, kind=kind.reshape(m),
                         params=params, coefficients=coefficients,
                         redundant=bool(m and np.linalg.matrix_rank(Lambda) < m), thrust=np.zeros(m),
                         side=np.zeros(m, dtype=np.int64))


def thrust_command_names(thrusters) -> tuple[str, ...]:
    """Names of :func:`allocate_command`'s signals: ``thrust_cmd_<name>`` per thruster, ``unachieved_<K..Z>``
    (none without thrusters)."""
    thrusters = tuple(thrusters)
    if not thrusters:
        return ()
    return tuple(f"thrust_cmd_{t.name}" for t in thrusters) + tuple(f"unachieved_{a}" for a in LABELS)


# --------------------------------------------------------------------------------- bounded least squares

@allocating
def _face_solve(A, w, x, side, eps):
    """The free thrusts (``side == 0``) minimising ``|A x - w|^2 + eps |x_F|^2`` with the others held
    (``eps = 0``: the minimum-norm least-squares solution); returns them (k,) in free order."""
    m = A.shape[1]
    k = 0
    for i in range(m):
        if side[i] == 0:
            k += 1
    rows = 6 + k if eps > 0.0 else 6
    M = np.zeros((rows, k))
    rhs = np.zeros(rows)
    for r in range(6):
        value = w[r]
        for i in range(m):
            if side[i] != 0:
                value -= A[r, i] * x[i]
        rhs[r] = value
    c = 0
    for i in range(m):
        if side[i] == 0:
            for r in range(6):
                M[r, c] = A[r, i]
            if eps > 0.0:
                M[6 + c, c] = np.sqrt(eps)
            c += 1
    if k == 0:
        return np.zeros(0)
    return np.linalg.lstsq(M, rhs, rcond=1e-10)[0]


@njit(cache=True, nogil=True, inline="always")
def _ratio_test(z, x, side, lower, upper):
    """The active-set step from ``x`` towards the face solution ``z`` (free thrusters, in order): the largest
    fraction ``alpha <= 1`` that keeps every free thrust within its limits, the thruster that blocks it (-1:
    none) and the limit it meets (-1 lower, +1 upper)."""
    alpha, block, block_side = 1.0, -1, 0
    c = 0
    for i in range(x.shape[0]):
        if side[i] == 0:
            d = z[c] - x[i]
            if d < 0.0 and z[c] < lower[i]:
                step = (lower[i] - x[i]) / d
                if step < alpha:
                    alpha, block, block_side = step, i, -1
            elif d > 0.0 and z[c] > upper[i]:
                step = (upper[i] - x[i]) / d
                if step < alpha:
                    alpha, block, block_side = step, i, 1
            c += 1
    return alpha, block, block_side


@allocating
def bounded_least_squares(A, w, lower, upper, eps, redundant, x, side):
    """``x`` (m,): within ``[lower, upper]``, minimising ``|A x - w|`` and then ``|x|`` (module docstring).
    ``x`` holds a starting guess on entry (clipped here); ``side`` (m,) is scratch (the final active set);
    ``redundant``: ``A`` has a null space (rank < m), so the minimiser is not unique and the minimum-norm one
    is sought among them (:func:`minimum_norm_refinement`)."""
    m = A.shape[1]
    for i in range(m):
        if x[i] <= lower[i]:
            x[i] = lower[i]
            side[i] = -1
        elif x[i] >= upper[i]:
            x[i] = upper[i]
            side[i] = 1
        else:
            side[i] = 0
    for _ in range(10 * m + 20):
        z = _face_solve(A, w, x, side, eps)
        alpha, block, block_side = _ratio_test(z, x, side, lower, upper)
        c = 0
        for i in range(m):
            if side[i] == 0:
                x[i] = x[i] + max(alpha, 0.0) * (z[c] - x[i])
                c += 1
        if block >= 0:
            side[block] = block_side
            x[block] = lower[block] if block_side < 0 else upper[block]
            continue
        # optimal on this face: release the bound whose multiplier has the wrong sign
        worst, release = 0.0, -1
        for i in range(m):
            if side[i] != 0:
                g = eps * x[i]
                for r in range(6):
                    residual = -w[r]
                    for j in range(m):
                        residual += A[r, j] * x[j]
                    g += A[r, i] * residual
                violation = -g if side[i] < 0 else g          # descent points into the box
                if violation > worst:
                    worst, release = violation, i
        scale = 1e-13 * (1.0 + np.abs(w).max()) * (1.0 + np.abs(A).max())
        if release < 0 or worst <= scale:
            break
        side[release] = 0
    # exact (eps -> 0) free thrusts on the final face: minimum-norm least squares
    z = _face_solve(A, w, x, side, 0.0)
    c = 0
    inside = True
    for i in range(m):
        if side[i] == 0:
            tol = 1e-12 * (1.0 + max(abs(lower[i]), abs(upper[i])))
            if z[c] < lower[i] - tol or z[c] > upper[i] + tol:
                inside = False
            c += 1
    if inside:
        c = 0
        for i in range(m):
            if side[i] == 0:
                x[i] = min(max(z[c], lower[i]), upper[i])
                c += 1
    if redundant:
        minimum_norm_refinement(A, lower, upper, x, side)


@allocating
def minimum_norm_refinement(A, lower, upper, x, side):
    """Among the thrusts producing the same wrench ``a = A x`` within the limits, the one of least ``|x|``
    (``x`` in, out): a primal active-set method on ``min 1/2 |x|^2`` subject to ``A x = a`` and the bounds.
    On a face (bounded thrusters held) the free ones are the minimum-norm solution ``pinv(A_F) (a - A_B x_B)``;
    at a face's optimum ``lambda`` solves ``A_F^T lambda = -x_F`` and a held thruster is released when its KKT
    multiplier ``x_i + A_i^T lambda`` has the wrong sign (negative at a lower limit, positive at an upper)."""
    m = A.shape[1]
    a = np.zeros(6)
    for r in range(6):
        for i in range(m):
            a[r] += A[r, i] * x[i]
    for i in range(m):
        side[i] = -1 if x[i] <= lower[i] else (1 if x[i] >= upper[i] else 0)
    tol = 1e-10 * (1.0 + np.abs(x).max())
    frozen = np.zeros(m, dtype=np.bool_)          # released without progress: not released again until a step
    for _ in range(10 * m + 20):
        z = _face_solve(A, a, x, side, 0.0)
        alpha, block, block_side = _ratio_test(z, x, side, lower, upper)
        alpha = max(alpha, 0.0)
        moved = False
        c = 0
        for i in range(m):
            if side[i] == 0:
                new = x[i] + alpha * (z[c] - x[i])
                moved = moved or abs(new - x[i]) > tol
                x[i] = new
                c += 1
        if moved:
            frozen[:] = False
        if block >= 0:
            side[block] = block_side
            x[block] = lower[block] if block_side < 0 else upper[block]
            if not moved:
                frozen[block] = True
            continue
        k = 0
        for i in range(m):
            if side[i] == 0:
                k += 1
        lam = np.zeros(6)
        if k > 0:
            At = np.zeros((k, 6))
            rhs = np.zeros(k)
            c = 0
            for i in range(m):
                if side[i] == 0:
                    for r in range(6):
                        At[c, r] = A[r, i]
                    rhs[c] = -x[i]
                    c += 1
            lam = np.linalg.lstsq(At, rhs, rcond=1e-10)[0]
        worst, release = tol, -1
        for i in range(m):
            if side[i] != 0 and not frozen[i]:
                mu = x[i]
                for r in range(6):
                    mu += A[r, i] * lam[r]
                violation = -mu if side[i] < 0 else mu
                if violation > worst:
                    worst, release = violation, i
        if release < 0:
            break
        side[release] = 0


# ----------------------------------------------------------------------------------------- the command


@kernel
def allocate_command(alloc, wrench, command, signals):
    """Held actuator commands ``command`` (max(m, 6),) for the body ``wrench`` (6,), and ``signals``
    (m + 6,): the thrusts and the unachieved ``wrench - Lambda T`` (module docstring). Without thrusters
    ``command[:6] = wrench`` and no signals."""
    m = alloc.m
    for j in range(command.shape[0]):
        command[j] = 0.0
    if m == 0:
        for j in range(6):
            command[j] = wrench[j]
        return
    T = alloc.thrust
    violated = False
    for h in range(m):
        value = 0.0
        for k in range(6):
            value += alloc.pinv[h, k] * wrench[k]
        T[h] = value
        if value < alloc.lower[h] or value > alloc.upper[h]:
            violated = True
    if violated:
        bounded_least_squares(alloc.Lambda, wrench, alloc.lower, alloc.upper, alloc.regularisation, alloc.redundant,
                              T, alloc.side)
    for k in range(6):
        achieved = 0.0
        for h in range(m):
            achieved += alloc.Lambda[k, h] * T[h]
        signals[m + k] = wrench[k] - achieved
    for h in range(m):
        signals[h] = T[h]
        command[h] = command_for_thrust(alloc.kind[h], alloc.params[h], alloc.coefficients[h], T[h])
