"""Compiled spatial-algebra blocks: scalar loops over 3- and 6-element blocks, no allocation.

Same operations and order as :mod:`uvms.spatial` (``[angular; linear]``); every function writes into an
output argument. ``X`` is a 6x6 Plucker motion transform, ``X^T`` maps forces back to the parent.
"""

from __future__ import annotations

import numpy as np

from uvms.jit import block


@block
def cross3(a, b, out):
    """``out = a x b`` for 3-vectors (``out`` must not alias ``a`` or ``b``)."""
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@block
def mat3_vec(E, x, out):
    """``out = E x`` (3x3)."""
    for i in range(3):
        out[i] = E[i, 0] * x[0] + E[i, 1] * x[1] + E[i, 2] * x[2]


@block
def mat6_vec(A, x, out):
    """``out = A x`` (6x6)."""
    for i in range(6):
        s = 0.0
        for j in range(6):
            s += A[i, j] * x[j]
        out[i] = s


@block
def mat6T_vec_add(A, x, out):
    """``out += A^T x`` (6x6): with ``A = Xup`` this carries a child's force to its parent."""
    for j in range(6):
        s = 0.0
        for i in range(6):
            s += A[i, j] * x[i]
        out[j] += s


@block
def transform_motion(E, r, m, out):
    """``out = X m`` for ``X = plucker(E, r)``, by the transform's structure (Featherstone Eq. 2.24; a rotation
    and a translation, never the dense 6x6 product)::

        X [w; v] = [E w; E (v - r x w)]
    """
    w0, w1, w2 = m[0], m[1], m[2]
    l0 = m[3] - (r[1] * w2 - r[2] * w1)
    l1 = m[4] - (r[2] * w0 - r[0] * w2)
    l2 = m[5] - (r[0] * w1 - r[1] * w0)
    for i in range(3):
        out[i] = E[i, 0] * w0 + E[i, 1] * w1 + E[i, 2] * w2
        out[3 + i] = E[i, 0] * l0 + E[i, 1] * l1 + E[i, 2] * l2


@block
def transform_force_add(E, r, f, out):
    """``out += X^T f`` for ``X = plucker(E, r)``: a force in body coordinates handed to the parent::

        X^T [n; f] = [E^T n + r x (E^T f); E^T f]
    """
    f0 = E[0, 0] * f[3] + E[1, 0] * f[4] + E[2, 0] * f[5]
    f1 = E[0, 1] * f[3] + E[1, 1] * f[4] + E[2, 1] * f[5]
    f2 = E[0, 2] * f[3] + E[1, 2] * f[4] + E[2, 2] * f[5]
    out[0] += (E[0, 0] * f[0] + E[1, 0] * f[1] + E[2, 0] * f[2]) + (r[1] * f2 - r[2] * f1)
    out[1] += (E[0, 1] * f[0] + E[1, 1] * f[1] + E[2, 1] * f[2]) + (r[2] * f0 - r[0] * f2)
    out[2] += (E[0, 2] * f[0] + E[1, 2] * f[1] + E[2, 2] * f[2]) + (r[0] * f1 - r[1] * f0)
    out[3] += f0
    out[4] += f1
    out[5] += f2


@block
def crm_mul(v, m, out):
    """``out = v x m`` (spatial motion cross product, Featherstone Eq. 2.31)."""
    out[0] = v[1] * m[2] - v[2] * m[1]
    out[1] = v[2] * m[0] - v[0] * m[2]
    out[2] = v[0] * m[1] - v[1] * m[0]
    out[3] = v[1] * m[5] - v[2] * m[4] + v[4] * m[2] - v[5] * m[1]
    out[4] = v[2] * m[3] - v[0] * m[5] + v[5] * m[0] - v[3] * m[2]
    out[5] = v[0] * m[4] - v[1] * m[3] + v[3] * m[1] - v[4] * m[0]


@block
def crf_mul_add(v, f, scale, out):
    """``out += scale * (v x* f)`` (spatial force cross product, Featherstone Eq. 2.32)."""
    out[0] += scale * (v[1] * f[2] - v[2] * f[1] + v[4] * f[5] - v[5] * f[4])
    out[1] += scale * (v[2] * f[0] - v[0] * f[2] + v[5] * f[3] - v[3] * f[5])
    out[2] += scale * (v[0] * f[1] - v[1] * f[0] + v[3] * f[4] - v[4] * f[3])
    out[3] += scale * (v[1] * f[5] - v[2] * f[4])
    out[4] += scale * (v[2] * f[3] - v[0] * f[5])
    out[5] += scale * (v[0] * f[4] - v[1] * f[3])


@block
def plucker(E, r, X):
    """``X = [[E, 0], [-E skew(r), E]]`` (Featherstone Eq. 2.24)."""
    for i in range(3):
        for j in range(3):
            X[i, j] = E[i, j]
            X[i + 3, j + 3] = E[i, j]
            X[i, j + 3] = 0.0
        # row i of -E skew(r)
        X[i + 3, 0] = -(E[i, 1] * r[2] - E[i, 2] * r[1])
        X[i + 3, 1] = -(E[i, 2] * r[0] - E[i, 0] * r[2])
        X[i + 3, 2] = -(E[i, 0] * r[1] - E[i, 1] * r[0])


@block
def congruence_add_plucker(E, r, I, out, tmp):
    """``out += X^T I X`` for ``X = plucker(E, r)`` and a symmetric ``I``, by the transform's structure
    (Featherstone 2008, Sec. 2.8: a rotation then a translation, never a dense 6x6 product).

    With ``[[A, B], [B^T, C]] = diag(E, E)^T I diag(E, E)`` and ``D = B + r x C``::

        X^T I X = [[A + (r x) B^T - D (r x), D], [D^T, C]]

    ``tmp`` is a 6x6 scratch matrix (rows 0-2: A, rows 3-5: B; its right half: C and D).
    """
    # A = E^T I11 E, B = E^T I12 E, C = E^T I22 E (blocks of the rotated inertia), column b at a time: the
    # columns I11 E[:, b], I12 E[:, b], I22 E[:, b] once, then E^T times each
    for b in range(3):
        e0, e1, e2 = E[0, b], E[1, b], E[2, b]
        p0 = I[0, 0] * e0 + I[0, 1] * e1 + I[0, 2] * e2
        p1 = I[1, 0] * e0 + I[1, 1] * e1 + I[1, 2] * e2
        p2 = I[2, 0] * e0 + I[2, 1] * e1 + I[2, 2] * e2
        q0 = I[0, 3] * e0 + I[0, 4] * e1 + I[0, 5] * e2
        q1 = I[1, 3] * e0 + I[1, 4] * e1 + I[1, 5] * e2
        q2 = I[2, 3] * e0 + I[2, 4] * e1 + I[2, 5] * e2
        c0 = I[3, 3] * e0 + I[3, 4] * e1 + I[3, 5] * e2
        c1 = I[4, 3] * e0 + I[4, 4] * e1 + I[4, 5] * e2
        c2 = I[5, 3] * e0 + I[5, 4] * e1 + I[5, 5] * e2
        for a in range(3):
            f0, f1, f2 = E[0, a], E[1, a], E[2, a]
            tmp[a, b] = f0 * p0 + f1 * p1 + f2 * p2
            tmp[3 + a, b] = f0 * q0 + f1 * q1 + f2 * q2
            tmp[a, 3 + b] = f0 * c0 + f1 * c1 + f2 * c2
    # D = B + r x C, column by column: D[:, j] = B[:, j] + r x C[:, j]
    for j in range(3):
        c0, c1, c2 = tmp[0, 3 + j], tmp[1, 3 + j], tmp[2, 3 + j]
        tmp[3, 3 + j] = tmp[3, j] + r[1] * c2 - r[2] * c1
        tmp[4, 3 + j] = tmp[4, j] + r[2] * c0 - r[0] * c2
        tmp[5, 3 + j] = tmp[5, j] + r[0] * c1 - r[1] * c0
    # top-left: A + (r x) B^T - D (r x); column j of (r x) B^T is r x B[j, :], row i of -D (r x) is r x D[i, :]
    for i in range(3):
        for j in range(3):
            out[i, j] += tmp[i, j]
    for j in range(3):
        bx, by, bz = tmp[3 + j, 0], tmp[3 + j, 1], tmp[3 + j, 2]          # B[j, :]
        out[0, j] += r[1] * bz - r[2] * by
        out[1, j] += r[2] * bx - r[0] * bz
        out[2, j] += r[0] * by - r[1] * bx
    for i in range(3):
        dx, dy, dz = tmp[3 + i, 3], tmp[3 + i, 4], tmp[3 + i, 5]          # D[i, :]
        out[i, 0] += r[1] * dz - r[2] * dy
        out[i, 1] += r[2] * dx - r[0] * dz
        out[i, 2] += r[0] * dy - r[1] * dx
    for i in range(3):
        for j in range(3):
            d = tmp[3 + i, 3 + j]
            out[i, 3 + j] += d
            out[3 + j, i] += d
            out[3 + i, 3 + j] += tmp[i, 3 + j]


@block
def cholesky_factor(A, L):
    """The lower Cholesky factor ``L`` of a symmetric positive-definite ``A`` (k x k, lower triangle read;
    ``A = L L^T``, Golub & Van Loan, Algorithm 4.2.1). A pivot that is not positive is set to NaN, which
    propagates to every result (the callers' finiteness checks catch it)."""
    k = A.shape[0]
    for j in range(k):
        s = A[j, j]
        for m in range(j):
            s -= L[j, m] * L[j, m]
        if s <= 0.0:
            s = np.nan
        L[j, j] = np.sqrt(s)
        for i in range(j + 1, k):
            t = A[i, j]
            for m in range(j):
                t -= L[i, m] * L[j, m]
            L[i, j] = t / L[j, j]


@block
def cholesky_solve(L, b, out):
    """Solve ``L L^T out = b`` by forward and back substitution (``L`` from :func:`cholesky_factor`; ``out``
    may alias ``b``)."""
    k = L.shape[0]
    for i in range(k):
        t = b[i]
        for m in range(i):
            t -= L[i, m] * out[m]
        out[i] = t / L[i, i]
    for i in range(k - 1, -1, -1):
        t = out[i]
        for m in range(i + 1, k):
            t -= L[m, i] * out[m]
        out[i] = t / L[i, i]


@block
def cholesky_solve6(A, b, L, out):
    """Solve ``A out = b`` for a symmetric positive-definite 6x6 ``A`` (``L`` is 6x6 scratch)."""
    cholesky_factor(A, L)
    cholesky_solve(L, b, out)
