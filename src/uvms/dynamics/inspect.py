"""What pushes the vehicle: every body's hydrodynamic and gravity wrench, split by cause.

For each body (vehicle, links), in its own axes about its frame origin, ``[moment; force]``:

- ``added_mass_velocity``: ``-(nu_r x*) I_A nu_r`` (Eq. 2, velocity terms)
- ``added_mass_inertial``: ``-I_A a`` at the accelerations the ABA gives for the inputs (Eq. 2)
- ``fluid_acceleration``: ``I_A a_fluid + m_f a_f`` at the centre of buoyancy (Eqs. 2, 7)
- ``drag``: Eqs. 3-6
- ``buoyancy``: ``-m_f a_g`` at the centre of buoyancy (Eqs. 7-8)
- ``gravity``: ``m a_g`` at the centre of mass

A read-out of one evaluation of the articulated-body algorithm (:func:`uvms.dynamics.aba.aba`): its outward pass
keeps each body's named forces (``Workspace.forces``, slots of :mod:`uvms.dynamics.kernel_model`) and relative
velocity, its last pass each body's acceleration; what you see is what is integrated. The fluid-acceleration
parts (``I_A [0; a_f]`` and ``m_f a_f`` at the centre of buoyancy, ``a_f`` the world fluid acceleration in body
axes) are taken out of the added-mass and buoyancy slots.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uvms import checks
from uvms.dynamics.aba import aba
from uvms.dynamics.api import environment
from uvms.dynamics.kernel_model import ADDED_MASS, BUOYANCY, DRAG, GRAVITY, make_workspace
from uvms.dynamics.plant import fluid_table, kernel_model

CAUSES = ("added_mass_velocity", "added_mass_inertial", "fluid_acceleration", "drag", "buoyancy", "gravity")


__all__ = ["CAUSES", "HydrodynamicWrenches", "hydrodynamic_wrenches"]


@dataclass(frozen=True)
class HydrodynamicWrenches:
    """``wrenches[cause]`` is (nb, 6): each body's wrench of that cause, body axes ``[moment; force]``.

    ``relative_velocity`` (nb, 6) is each body's velocity relative to the fluid (body axes).
    """

    body_names: tuple[str, ...]
    wrenches: dict[str, np.ndarray]
    relative_velocity: np.ndarray

    def total(self) -> np.ndarray:
        """(nb, 6) sum over causes."""
        return sum(self.wrenches.values())

    def table(self):
        """A pandas DataFrame: one row per (body, cause), columns K, M, N [N m], X, Y, Z [N]."""
        import pandas as pd

        rows = []
        for cause, w in self.wrenches.items():
            for i, name in enumerate(self.body_names):
                rows.append({"body": name, "cause": cause, **dict(zip(("K", "M", "N", "X", "Y", "Z"), w[i]))})
        return pd.DataFrame(rows)


def hydrodynamic_wrenches(model, state, *, joint_torques=None, body_wrench=None, current=None,
                          fluid_acceleration=None, fixed_base=False) -> HydrodynamicWrenches:
    """Each body's wrench by cause at ``state`` in a uniform current (see the module docstring)."""
    env = environment(model, current, fluid_acceleration)
    return _wrenches(model, state, joint_torques, body_wrench,
                     fluid_table([0.0], [env.current], [env.fluid_acceleration]), 0.0, fixed_base)


def hydrodynamic_wrenches_in(model, state, flow, time: float = 0.0, *, joint_torques=None, body_wrench=None,
                             fixed_base=False) -> HydrodynamicWrenches:
    """Each body's wrench by cause at ``state`` in the water ``flow`` (a :class:`~uvms.hydro.flow.Flow`) at
    ``time`` [s]: each body sees the water at its own centre of buoyancy (:mod:`uvms.hydro.flow`)."""
    from uvms.hydro.flow import Flow, check_status

    if not isinstance(flow, Flow):
        raise checks.fail("flow", f"expected a uvms.hydro.flow.Flow, got {checks.show(flow)}")
    data = flow.compiled(model.convention)
    out = _wrenches(model, state, joint_torques, body_wrench, data, checks.number(time, "time", unit="s"), fixed_base)
    check_status(data)
    return out


def _wrenches(model, state, joint_torques, body_wrench, flow, t, fixed_base) -> HydrodynamicWrenches:
    checks.state(model, state)
    fixed_base = checks.flag(fixed_base, "fixed_base")
    n = model.n_joints
    nu = np.array(state.nu, dtype=float)
    if fixed_base and np.any(nu != 0.0):
        raise checks.fail("fixed_base", "True needs a vehicle at rest (state.nu == 0): a clamped vehicle does not "
                                        "move")
    tau = checks.optional_vector(joint_torques, n, "joint_torques", " (one per joint)")
    f_body = checks.optional_vector(body_wrench, 6, "body_wrench", " [moment; force]")
    km = kernel_model(model)
    ws = make_workspace(model.n_bodies)
    nu_dot, qdd = np.zeros(6), np.zeros(n)
    aba(km, ws, state.rotation, np.array(state.position, dtype=float), nu, np.array(state.q, dtype=float),
        np.array(state.qd, dtype=float), tau, f_body, np.zeros(6), flow, t, fixed_base, nu_dot, qdd)
    if not checks.finite(nu_dot, qdd):
        raise checks.overflow("the accelerations", {"state.nu": nu, "state.qd": state.qd, "joint_torques": tau,
                                                    "body_wrench": f_body})
    f = ws.forces
    added_mass_fluid = np.einsum("ijk,ik->ij", km.added_mass[:, :, 3:], ws.af)       # I_A [0; a_f]
    buoyancy_fluid = np.zeros((model.n_bodies, 6))                                    # m_f a_f at b
    buoyancy_fluid[:, 3:] = km.fluid_mass[:, None] * ws.af
    buoyancy_fluid[:, :3] = np.cross(km.cob, buoyancy_fluid[:, 3:])
    out = {
        "added_mass_velocity": f[:, ADDED_MASS] - added_mass_fluid,
        "added_mass_inertial": -np.einsum("ijk,ik->ij", km.added_mass, ws.a),
        "fluid_acceleration": added_mass_fluid + buoyancy_fluid,
        "drag": f[:, DRAG].copy(),
        "buoyancy": f[:, BUOYANCY] - buoyancy_fluid,
        "gravity": f[:, GRAVITY].copy(),
    }
    return HydrodynamicWrenches(body_names=model.body_names, wrenches=out, relative_velocity=ws.nu_r.copy())
