"""What pushes the vehicle: every body's hydrodynamic and gravity wrench, split by cause.

For each body (vehicle, links), in its own axes about its frame origin, ``[moment; force]``:

- ``added_mass_velocity``: ``-(nu_r x*) I_A nu_r`` (Eq. 2, velocity terms)
- ``added_mass_inertial``: ``-I_A a`` at the accelerations the ABA gives for the inputs (Eq. 2)
- ``fluid_acceleration``: ``I_A a_fluid + m_f a_f`` at the centre of buoyancy (Eqs. 2, 7)
- ``drag``: Eqs. 3-6
- ``buoyancy``: ``-m_f a_g`` at the centre of buoyancy (Eqs. 7-8)
- ``gravity``: ``m a_g`` at the centre of mass

Uses the same compiled per-effect functions as the dynamics, so what you see is what is integrated.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uvms import checks
from uvms.dynamics.api import environment, forward_dynamics
from uvms.dynamics.kernel_model import make_workspace
from uvms.dynamics.passes import body_hydro_forces, outward_pass

CAUSES = ("added_mass_velocity", "added_mass_inertial", "fluid_acceleration", "drag", "buoyancy", "gravity")


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
    """Each body's wrench by cause at ``state`` (see the module docstring)."""
    checks.state(model, state)
    fixed_base = checks.flag(fixed_base, "fixed_base")
    nb = model.n_bodies
    km = model.kernel
    ws = make_workspace(nb)
    env = environment(model, current, fluid_acceleration)
    nu = np.zeros(6) if fixed_base else np.array(state.nu, dtype=float)
    outward_pass(km, ws, state.rotation, nu, np.array(state.q, dtype=float), np.array(state.qd, dtype=float),
                 env.current, env.fluid_acceleration)
    acc = forward_dynamics(model, state, joint_torques=joint_torques, body_wrench=body_wrench, current=current,
                           fluid_acceleration=fluid_acceleration, fixed_base=fixed_base)
    # body accelerations from the ABA's joint accelerations (outward, as in the RNEA)
    a = np.zeros((nb, 6))
    a[0] = acc.nu_dot
    for i in range(1, nb):
        a[i] = ws.Xup[i] @ a[km.parent[i]] + ws.c[i]
        a[i] += km.S[i] * acc.qdd[i - 1]
    out = {c: np.zeros((nb, 6)) for c in CAUSES}
    rel = np.zeros((nb, 6))
    f = np.zeros((4, 6))
    scratch = np.zeros((6, 6))
    zero3 = np.zeros(3)

    def forces(i, af):
        body_hydro_forces(km.added_mass[i], km.vehicle_drag_linear, km.vehicle_drag_angular, km.cylinder[i],
                          km.fossen[i], km.shapes[i], i == 0, km.mass[i], km.com[i], km.fluid_mass[i], km.cob[i],
                          ws.v[i], ws.vc[i], af, ws.g[i], f, scratch)

    for i in range(nb):
        # velocity terms alone (no fluid acceleration), then the fluid-acceleration part as the difference
        forces(i, zero3)
        out["added_mass_velocity"][i] = f[0]
        out["drag"][i] = f[1]
        out["buoyancy"][i] = f[2]
        out["gravity"][i] = f[3]
        rel[i] = scratch[0]
        forces(i, ws.af[i])
        out["fluid_acceleration"][i] = (f[0] - out["added_mass_velocity"][i]) + (f[2] - out["buoyancy"][i])
        out["added_mass_inertial"][i] = -km.added_mass[i] @ a[i]
    return HydrodynamicWrenches(body_names=model.body_names, wrenches=out, relative_velocity=rel)
