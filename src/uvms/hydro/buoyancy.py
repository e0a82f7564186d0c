"""Gravity, buoyancy and fluid-acceleration (Froude-Krylov) forces, paper Eqs. 7-8.

Gravity ``m a_g`` acts at the centre of mass ``r_G``; the displaced fluid pushes with
``f_TB = m_f (a_f - a_g)`` at the centre of buoyancy ``b`` (Eq. 7), as the spatial force
``[b x f_TB; f_TB]`` (Eq. 8). All vectors in body axes: ``a_g`` and ``a_f`` are the world vectors rotated
by ``R^T``. The paper's vehicle has ``m_f = m`` and ``b`` above the CoM (z down), hence a righting moment.
"""

from __future__ import annotations

from uvms.jit import block


@block
def point_force(point, f0, f1, f2, out):
    """``out = [point x f; f]``: a force ``f`` applied at ``point`` as a spatial force about the origin."""
    out[0] = point[1] * f2 - point[2] * f1
    out[1] = point[2] * f0 - point[0] * f2
    out[2] = point[0] * f1 - point[1] * f0
    out[3] = f0
    out[4] = f1
    out[5] = f2


@block
def gravity_force(mass, com, gravity_body, out):
    """``out = [r_G x m a_g; m a_g]``: weight at the centre of mass."""
    point_force(com, mass * gravity_body[0], mass * gravity_body[1], mass * gravity_body[2], out)


@block
def buoyancy_force(fluid_mass, cob, gravity_body, a_fluid_body, out):
    """``out = [b x f_TB; f_TB]``, ``f_TB = m_f (a_f - a_g)`` (Eqs. 7-8): buoyancy plus fluid acceleration."""
    point_force(cob, fluid_mass * (a_fluid_body[0] - gravity_body[0]),
                fluid_mass * (a_fluid_body[1] - gravity_body[1]),
                fluid_mass * (a_fluid_body[2] - gravity_body[2]), out)
