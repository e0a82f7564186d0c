"""Energy and momentum of the whole system, for conservation checks and diagnostics.

- kinetic energy ``T = 0.5 [nu; qd]^T M [nu; qd]`` with ``M`` from the CRBA (added mass included: the fluid's
  kinetic energy in the strip/independent-body added-mass model);
- potential energy of gravity and buoyancy (z down): ``V = sum_i (-m_i a_g . r_G,i + m_f,i a_g . r_B,i)``
  with world positions of the centres of mass and buoyancy (valid in still fluid: ``a_f = 0``); ``m_i`` and
  ``r_G,i`` are the weight's (``Model.weight_mass``, ``Model.weight_center``: the dry mass of a model whose
  inertia includes added mass);
- spatial momentum about the world origin, world axes, ``sum_i X_i^* (I_i [+ I_A,i]) v_i``: conserved with no
  gravity, drag, current or external forces (with added mass included, it is the body-plus-fluid impulse).
"""

from __future__ import annotations

import numpy as np

from uvms import checks
from uvms.dynamics.api import mass_matrix
from uvms.dynamics.kernel_model import make_workspace
from uvms.dynamics.passes import outward_pass
from uvms.dynamics.plant import fluid_table, kernel_model
from uvms.dynamics.poses import forward_kinematics


def kinetic_energy(model, state) -> float:
    """``0.5 zeta^T M zeta`` [J], ``zeta = [nu; qd]``, added mass included."""
    checks.state(model, state)
    z = state.generalized_velocity
    return float(0.5 * z @ mass_matrix(model, state) @ z)


def potential_energy(model, state) -> float:
    """Gravity and buoyancy potential [J] (zero at the world origin)."""
    poses = forward_kinematics(model, state)
    g = model.gravity
    V = 0.0
    for i in range(model.n_bodies):
        R, p = poses.rotation[i], poses.position[i]
        V -= model.weight_mass[i] * g @ (p + R @ model.weight_center[i])
        V += model.buoyancy_mass[i] * g @ (p + R @ model.cob[i])
    return float(V)


def spatial_momentum(model, state, *, include_added_mass: bool = False) -> np.ndarray:
    """``[angular; linear]`` momentum about the world origin in world axes (6,)."""
    checks.state(model, state)
    include_added_mass = checks.flag(include_added_mass, "include_added_mass")
    km = kernel_model(model)
    ws = make_workspace(model.n_bodies)
    outward_pass(km, ws, state.rotation, np.array(state.position, dtype=float), np.array(state.nu, dtype=float),
                 np.array(state.q, dtype=float), np.array(state.qd, dtype=float), fluid_table([0.0], [np.zeros(3)],
                 [np.zeros(3)]), 0.0)
    poses = forward_kinematics(model, state)
    total = np.zeros(6)
    for i in range(model.n_bodies):
        I = km.inertia_h[i] if include_added_mass else km.inertia[i]
        h = I @ ws.v[i]                        # body axes, about the body origin
        R, p = poses.rotation[i], poses.position[i]
        f = R @ h[3:]
        total[:3] += R @ h[:3] + np.cross(p, f)
        total[3:] += f
    return total
