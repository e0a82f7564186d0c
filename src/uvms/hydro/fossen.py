"""Fossen's coefficient form of hydrodynamic damping: linear and quadratic, from SNAME-named coefficients.

Fossen (*Handbook of Marine Craft Hydrodynamics and Motion Control*, 2nd ed., 2021, the chapters on
hydrodynamic damping) writes the damping of an underwater vehicle as ``tau_D = -D(nu_r) nu_r`` with
``D(nu_r) = D_l + D_n(nu_r)``; in the common diagonal form ``D_l = -diag(X_u, Y_v, Z_w, K_p, M_q, N_r)`` and
``D_n = -diag(X_u|u| |u|, Y_v|v| |v|, ..., N_r|r| |r|)``. The SNAME (1950) names are the derivatives of a force
or moment (capital letter) with respect to a velocity (subscript), so a dissipative coefficient is negative
(``X_u < 0``). Identification papers print them either way; :func:`damping_matrices` takes a ``convention``.

uvms keeps its own order ``[angular; linear]`` = ``[p q r u v w]`` for velocities and ``[K M N X Y Z]`` for
forces (``docs/conventions.md``), so Fossen's linear-first index ``i`` becomes ``(i + 3) % 6``:

=================== ======= =============== ====================== =====================
SNAME name          row     column          linear ``D_l[row,col]`` quadratic ``D_q[row,col]``
=================== ======= =============== ====================== =====================
``K_p``, ``K_p|p|`` 0 (K)   0 (p)           ``-K_p``               ``-K_p|p|``
``M_q``, ``M_q|q|`` 1 (M)   1 (q)           ``-M_q``               ``-M_q|q|``
``N_r``, ``N_r|r|`` 2 (N)   2 (r)           ``-N_r``               ``-N_r|r|``
``X_u``, ``X_u|u|`` 3 (X)   3 (u)           ``-X_u``               ``-X_u|u|``
``Y_v``, ``Y_v|v|`` 4 (Y)   4 (v)           ``-Y_v``               ``-Y_v|v|``
``Z_w``, ``Z_w|w|`` 5 (Z)   5 (w)           ``-Z_w``               ``-Z_w|w|``
``F_a``, ``F_a|a|`` of F    of a            ``-F_a`` (coupling)    ``-F_a|a|`` (coupling)
=================== ======= =============== ====================== =====================

(signs for ``convention="derivative"``; with ``"magnitude"`` the printed value is the matrix entry). A
quadratic name ``F_a|a|`` is the coefficient of ``a |a|`` in force ``F``; ``F_|a|a`` is accepted as the same.
Mixed products such as ``Y_|v|r`` (coefficient of ``|v| r``) are not part of this form and are refused.

The force (:func:`fossen_damping_force`) is ``f = -(D_l + D_q diag|nu_p|) nu_p`` where ``nu_p`` is the
velocity relative to the fluid of the point the coefficients were identified about (``point``, body
coordinates; usually the centre of origin or of gravity), then moved to the body origin as a spatial force.
With a symmetric positive semi-definite ``D_l`` and a diagonal non-negative ``D_q`` the power
``f . nu_r`` is never positive (tested); a general 6x6 ``D_q`` carries no such guarantee.
"""

from __future__ import annotations

import math
import re
from typing import Mapping

import numpy as np

from uvms.errors import UvmsInputError, show
from uvms.jit import block

FORCE_INDEX = {"K": 0, "M": 1, "N": 2, "X": 3, "Y": 4, "Z": 5}
VELOCITY_INDEX = {"p": 0, "q": 1, "r": 2, "u": 3, "v": 4, "w": 5}

_LINEAR = re.compile(r"^([KMNXYZ])_?([pqruvw])$")
_QUADRATIC = re.compile(r"^([KMNXYZ])_?(?:([pqruvw])\|([pqruvw])\||\|([pqruvw])\|([pqruvw]))$")


def sname_index(name: str) -> tuple[str, int, int]:
    """``("linear" | "quadratic", row, column)`` of a SNAME coefficient name in uvms's ``[angular; linear]`` order.

    ``X_u`` -> ``("linear", 3, 3)``; ``N_r|r|`` (or ``N_|r|r``) -> ``("quadratic", 2, 2)``; ``K_v`` ->
    ``("linear", 0, 4)``. Raises ``ValueError`` for anything else (including mixed ``Y_|v|r``).
    """
    text = name.replace(" ", "")
    m = _LINEAR.match(text)
    if m:
        return "linear", FORCE_INDEX[m.group(1)], VELOCITY_INDEX[m.group(2)]
    m = _QUADRATIC.match(text)
    if m:
        a, b = (m.group(2), m.group(3)) if m.group(2) else (m.group(4), m.group(5))
        if a != b:
            raise ValueError(f"{name!r}: mixed quadratic terms (coefficient of |{b}| {a}) are not supported")
        return "quadratic", FORCE_INDEX[m.group(1)], VELOCITY_INDEX[a]
    raise ValueError(f"{name!r} is not a SNAME damping coefficient such as X_u, N_r or X_u|u|")


def damping_matrices(coefficients: Mapping[str, float], *, convention: str = "derivative",
                     source: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``(D_l, D_q)``, both 6x6 in ``[angular; linear]`` order, from SNAME-named coefficients.

    Args:
        coefficients: e.g. ``{"X_u": -4.03, "X_u|u|": -18.18, "N_r": -0.07}``; names not given are zero.
        convention: ``"derivative"`` (SNAME: the value is the derivative, so dissipative values are negative
            and ``D = -value``) or ``"magnitude"`` (the value is the matrix entry, dissipative values positive).
        source: the file the coefficients came from, for error messages.

    Raises:
        UvmsInputError: an unknown name, a non-finite value, a name given twice, or an unknown convention
            (one line naming ``source`` and the key).
    """
    if convention not in ("derivative", "magnitude"):
        raise UvmsInputError(f"expected 'derivative' or 'magnitude', got {show(convention)}", source,
                             "convention")
    sign = -1.0 if convention == "derivative" else 1.0
    D_l = np.zeros((6, 6))
    D_q = np.zeros((6, 6))
    seen: dict[tuple[str, int, int], str] = {}
    for name, value in coefficients.items():
        try:
            kind, row, col = sname_index(str(name))
        except ValueError as exc:
            raise UvmsInputError(str(exc), source, str(name)) from None
        try:
            x = float(value)
        except (TypeError, ValueError):
            raise UvmsInputError(f"expected a number, got {show(value)}", source, str(name)) from None
        if not math.isfinite(x):
            raise UvmsInputError(f"expected a finite number, got {show(value)}", source, str(name))
        key = (kind, row, col)
        if key in seen:
            raise UvmsInputError(f"the same coefficient as {seen[key]!r}", source, str(name))
        seen[key] = str(name)
        (D_l if kind == "linear" else D_q)[row, col] = sign * x
    return D_l, D_q


def diagonal_damping(linear=None, quadratic=None) -> tuple[np.ndarray, np.ndarray]:
    """``(D_l, D_q)`` from 6 diagonal values each (already in ``[angular; linear]`` order, as matrix entries),
    or from 6x6 arrays; ``None`` gives zeros."""
    out = []
    for name, x in (("linear", linear), ("quadratic", quadratic)):
        if x is None:
            out.append(np.zeros((6, 6)))
            continue
        a = np.asarray(x, dtype=float)
        if a.shape == (6,):
            a = np.diag(a)
        if a.shape != (6, 6) or not np.all(np.isfinite(a)):
            raise ValueError(f"{name} damping must be 6 finite values or a finite 6x6 array, got shape {a.shape}")
        out.append(a.copy())
    return out[0], out[1]


@block
def fossen_damping_force(D_l, D_q, point, nu_r, out):
    """``out`` = ``[m; f]`` about the body origin, body axes, of ``f_p = -(D_l + D_q diag|nu_p|) nu_p``.

    ``nu_p = [omega; v + omega x point]`` is the velocity relative to the fluid of ``point`` (where the
    coefficients hold, body coordinates); the spatial force ``f_p = [m_p; f]`` acting there is moved to the
    origin as ``[m_p + point x f; f]``.
    """
    w0, w1, w2 = nu_r[0], nu_r[1], nu_r[2]
    px, py, pz = point[0], point[1], point[2]
    n0, n1, n2 = w0, w1, w2
    n3 = nu_r[3] + w1 * pz - w2 * py
    n4 = nu_r[4] + w2 * px - w0 * pz
    n5 = nu_r[5] + w0 * py - w1 * px
    for i in range(6):
        s = 0.0
        for j in range(6):
            if j == 0:
                nj = n0
            elif j == 1:
                nj = n1
            elif j == 2:
                nj = n2
            elif j == 3:
                nj = n3
            elif j == 4:
                nj = n4
            else:
                nj = n5
            s += (D_l[i, j] + D_q[i, j] * abs(nj)) * nj
        out[i] = -s
    fx, fy, fz = out[3], out[4], out[5]
    out[0] += py * fz - pz * fy
    out[1] += pz * fx - px * fz
    out[2] += px * fy - py * fx


CROSS_ROWS = 13
"""First row of the mixed quadratic terms in a body's kernel Fossen block (``uvms.dynamics.kernel_model``):
rows ``CROSS_ROWS + 6 i + j``, column ``k`` hold ``C[0, i, j, k]`` (the ``nu_j |nu_k|`` terms), the 36 rows after
them ``C[1, i, j, k]`` (the ``nu_j nu_k`` terms)."""
CROSS_ABS_END = CROSS_ROWS + 36
CROSS_END = CROSS_ROWS + 72


@block
def fossen_cross_damping_force(C_abs, C_plain, point, nu_r, out):
    """``out`` = ``[m; f]`` about the body origin of the mixed quadratic damping
    ``f_i = -sum_jk (C_abs[6 i + j, k] nu_j |nu_k| + C_plain[6 i + j, k] nu_j nu_k)`` acting at ``point``.

    This is the quadratic part of gz-sim's Hydrodynamics system (``D(i, j) -= xUabsV |V| + xUV V``, force
    ``D nu``; gz-sim ``HydrodynamicsUtils.hh``, ``buildDampingMatrix``) and UUV Simulator's damping
    proportional to the forward speed (``-u D_lfs nu``, ``HydrodynamicModel.cc``, ``HMFossen``), in
    ``[angular; linear]`` indices and matrix-entry signs. ``nu_p`` (the velocity of ``point``) as in
    :func:`fossen_damping_force`; the diagonal ``F_a|a|`` terms stay in ``D_q``.
    """
    w0, w1, w2 = nu_r[0], nu_r[1], nu_r[2]
    px, py, pz = point[0], point[1], point[2]
    n0, n1, n2 = w0, w1, w2
    n3 = nu_r[3] + w1 * pz - w2 * py
    n4 = nu_r[4] + w2 * px - w0 * pz
    n5 = nu_r[5] + w0 * py - w1 * px
    for i in range(6):
        s = 0.0
        for j in range(6):
            nj = n0 if j == 0 else n1 if j == 1 else n2 if j == 2 else n3 if j == 3 else n4 if j == 4 else n5
            for k in range(6):
                nk = n0 if k == 0 else n1 if k == 1 else n2 if k == 2 else n3 if k == 3 else n4 if k == 4 else n5
                s += (C_abs[6 * i + j, k] * abs(nk) + C_plain[6 * i + j, k] * nk) * nj
        out[i] = -s
    fx, fy, fz = out[3], out[4], out[5]
    out[0] += py * fz - pz * fy
    out[1] += pz * fx - px * fz
    out[2] += px * fy - py * fx
