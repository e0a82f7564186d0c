"""Added mass (paper Eq. 2; Newman 1977; McMillan et al. 1995).

A body accelerating through fluid at rest feels ``f_A = -I_A nu_dot_r - (nu_r x*) I_A nu_r`` with ``I_A`` a
constant symmetric 6x6 matrix (body axes, about the body-frame origin, ``[angular; linear]``) and ``nu_r`` the
body velocity relative to the fluid. In :mod:`uvms.dynamics` the acceleration part ``-I_A nu_dot`` goes into
the articulated inertia ``I_H = I + I_A`` (Eq. 13); the rest is the bias
``-I_A a_fluid - (nu_r x*) I_A nu_r``, with ``a_fluid`` the rate of change of the fluid velocity seen in body
axes (see :mod:`uvms.hydro.current`).
"""

from __future__ import annotations

import numpy as np

from uvms.jit import block


def cylinder_added_mass(density: float, radius: float, length: float) -> np.ndarray:
    """Strip-theory added mass of a cylinder along x from 0 to ``length``, about its end (the joint).

    Each strip ``dl`` at ``l`` has 2D added mass ``m_a' = rho pi r^2`` for motion normal to the axis and none
    along it (Patel 1989; ``docs/conventions.md``). Integrating the strip kinetic energy
    ``0.5 m_a' |v_n(l)|^2``, ``v_n(l) = [0, v_y + w_z l, v_z - w_y l]``, gives ``[angular; linear]``::

        I_A[wy,wy] = I_A[wz,wz] = m_a' L^3 / 3      I_A[vy,vy] = I_A[vz,vz] = m_a' L
        I_A[wz,vy] = +m_a' L^2 / 2                   I_A[wy,vz] = -m_a' L^2 / 2

    For the paper's links (r = 0.0125 m, L = 0.22 m, rho = 1000 kg/m^3): 0.1080 kg, 0.00174 kg m^2 and
    +/-0.0119 kg m, the appendix's diagonal (0.1078, 0.0017) up to rounding.
    """
    from uvms.checks import number

    density = number(density, "density", nonnegative=True, unit="kg/m^3")
    radius = number(radius, "radius", nonnegative=True, unit="m")
    length = number(length, "length", nonnegative=True, unit="m")
    ma = density * np.pi * radius**2
    I_A = np.zeros((6, 6))
    I_A[1, 1] = I_A[2, 2] = ma * length**3 / 3.0
    I_A[4, 4] = I_A[5, 5] = ma * length
    I_A[2, 4] = I_A[4, 2] = ma * length**2 / 2.0
    I_A[1, 5] = I_A[5, 1] = -ma * length**2 / 2.0
    return I_A


@block
def added_mass_force(I_A, nu_r, a_fluid, out):
    """``out = I_A a_fluid - (nu_r x*) I_A nu_r``: the added-mass force of Eq. 2 less its ``-I_A a`` part.

    ``nu_r`` is the body velocity relative to the fluid and ``a_fluid`` the fluid's acceleration seen in body
    axes (:func:`uvms.hydro.current.fluid_acceleration_in_body`), both ``[angular; linear]`` in body axes.
    With that ``a_fluid``, ``-I_A (a - a_fluid) = -I_A d(nu_r)/dt``: Eq. 2's ``+ omega x v_r`` term is the
    classical-acceleration form of the same thing and is not added again.
    """
    for i in range(6):
        s = 0.0
        for j in range(6):
            s += I_A[i, j] * a_fluid[j]
        out[i] = s
    h0 = h1 = h2 = h3 = h4 = h5 = 0.0
    for j in range(6):
        h0 += I_A[0, j] * nu_r[j]
        h1 += I_A[1, j] * nu_r[j]
        h2 += I_A[2, j] * nu_r[j]
        h3 += I_A[3, j] * nu_r[j]
        h4 += I_A[4, j] * nu_r[j]
        h5 += I_A[5, j] * nu_r[j]
    w0, w1, w2, v0, v1, v2 = nu_r[0], nu_r[1], nu_r[2], nu_r[3], nu_r[4], nu_r[5]
    # (nu_r x*) h = [w x h_ang + v x h_lin; w x h_lin]
    out[0] -= w1 * h2 - w2 * h1 + v1 * h5 - v2 * h4
    out[1] -= w2 * h0 - w0 * h2 + v2 * h3 - v0 * h5
    out[2] -= w0 * h1 - w1 * h0 + v0 * h4 - v1 * h3
    out[3] -= w1 * h5 - w2 * h4
    out[4] -= w2 * h3 - w0 * h5
    out[5] -= w0 * h4 - w1 * h3
