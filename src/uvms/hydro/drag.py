"""Quadratic drag: the vehicle's per-axis and strip-integrated rotational drag (Eqs. 3-5), links' cylinder
drag (Eq. 6). Every velocity is relative to the fluid, ``nu_r = [omega; v - v_c]`` in body axes.

Vehicle, translation (Eq. 3), per body axis ``j``::

    F_j = -0.5 rho A_j Cd_j v_rj |v_rj|

Vehicle, rotation (Eq. 4): the vehicle is a cube of side ``a``; strips parallel to the rotation axis at
distance ``x`` from it move at ``omega x``; each slice counted once and both perpendicular slice families
summed (``docs/conventions.md``)::

    M_j = -2 * 0.5 rho Cd a * int_{-a/2}^{a/2} x^2 |x| dx * omega_j |omega_j| = -(rho Cd a^5 / 32) omega_j |omega_j|

Link ``i`` (Eq. 6, moment arm corrected to the strip position ``l``): a cylinder of radius ``r`` along the link
x axis from the joint (``l = 0``) to ``L``; only the velocity normal to the axis counts::

    v_n(l) = [0, v_y + omega_z l, v_z - omega_y l]
    F = -0.5 rho Cd 2r int_0^L |v_n| v_n dl,    M = -0.5 rho Cd 2r int_0^L [l, 0, 0] x |v_n| v_n dl

``|v_n|`` has a kink where ``v_n`` passes through (or near) zero; the integral is split at the point of
smallest ``|v_n|`` and each piece integrated with 8-point Gauss-Legendre (within 1e-4 of an adaptive
reference, ``tests/hydro/test_added_mass_drag.py``).
"""

from __future__ import annotations

import numpy as np

from uvms.jit import block

GAUSS_POINTS = 8
_GL_X, _GL_W = np.polynomial.legendre.leggauss(GAUSS_POINTS)


def box_rotational_drag_coefficient(density: float, drag_coefficient: float, side: float) -> float:
    """Closed form of Eq. 4 for a cube of side ``a``: ``rho Cd a^5 / 32`` [N m s^2] (2.52 for the paper)."""
    from uvms.checks import number

    density = number(density, "density", nonnegative=True, unit="kg/m^3")
    drag_coefficient = number(drag_coefficient, "drag_coefficient", nonnegative=True)
    side = number(side, "side", nonnegative=True, unit="m")
    return density * drag_coefficient * side**5 / 32.0


def box_rotational_drag_by_strips(density: float, drag_coefficient: float, side: float, omega: float,
                                  n_strips: int = 2000) -> float:
    """Eq. 4 by explicit strip summation (midpoint rule), the reference for the closed form.

    Strips of width ``a / n_strips`` across the cube, for both slice families perpendicular to the
    rotation; each strip of area ``a dx`` at distance ``x`` feels Eq. 3's drag at speed ``omega x``.
    Returns the moment about the rotation axis [N m].
    """
    from uvms.checks import fail, number

    density = number(density, "density", nonnegative=True, unit="kg/m^3")
    drag_coefficient = number(drag_coefficient, "drag_coefficient", nonnegative=True)
    side = number(side, "side", nonnegative=True, unit="m")
    omega = number(omega, "omega", unit="rad/s")
    if isinstance(n_strips, bool) or not isinstance(n_strips, (int, np.integer)) or n_strips < 1:
        raise fail("n_strips", f"expected a whole number >= 1, got {n_strips!r}")
    dx = side / n_strips
    x = -side / 2 + dx * (np.arange(n_strips) + 0.5)
    speed = omega * x
    dF = -0.5 * density * drag_coefficient * (side * dx) * speed * np.abs(speed)
    return float(2 * np.sum(x * dF))


@block
def vehicle_drag_force(k_linear, k_angular, nu_r, out):
    """``out`` = Eq. 5's ``[M_1..3; F_4..6]`` with ``k_linear = 0.5 rho A Cd`` and ``k_angular = rho Cd a^5/32``."""
    for j in range(3):
        w = nu_r[j]
        v = nu_r[3 + j]
        out[j] = -k_angular[j] * w * abs(w)
        out[3 + j] = -k_linear[j] * v * abs(v)


@block
def link_drag_force(k, length, nu_r, out):
    """``out`` = Eq. 6's ``[M; F]`` about the joint, ``k = 0.5 rho Cd 2r`` per unit length."""
    for j in range(6):
        out[j] = 0.0
    if k == 0.0 or length == 0.0:
        return
    ay, az = nu_r[4], nu_r[5]          # normal velocity at the joint
    by, bz = nu_r[2], -nu_r[1]         # its rate of change along the link (omega_z, -omega_y)
    bb = by * by + bz * bz
    split = -1.0
    if bb > 0.0:
        split = -(ay * by + az * bz) / bb          # where |v_n| is smallest
    n_pieces = 2 if 0.0 < split < length else 1
    fy = fz = my = mz = 0.0
    for piece in range(n_pieces):
        lo = 0.0
        hi = length
        if n_pieces == 2:
            if piece == 0:
                hi = split
            else:
                lo = split
        half = 0.5 * (hi - lo)
        mid = 0.5 * (hi + lo)
        for g in range(GAUSS_POINTS):
            l = mid + half * _GL_X[g]
            w = half * _GL_W[g]
            vy = ay + by * l
            vz = az + bz * l
            s = np.sqrt(vy * vy + vz * vz)
            fy += w * s * vy
            fz += w * s * vz
            my += w * l * s * vz
            mz -= w * l * s * vy
    # dF = -k |v_n| v_n dl;  M = int [l,0,0] x dF = [0, -l dF_z, l dF_y]
    out[1] = k * my
    out[2] = k * mz
    out[4] = -k * fy
    out[5] = -k * fz
