"""The owner of the compiled model data: Pinocchio's ``(model, data)`` pair for compiled code.

A :class:`ModelData` couples a model's constant kernel arrays (:class:`~uvms.dynamics.kernel_model.KernelModel`,
``body``) with the scratch it needs (:class:`~uvms.dynamics.kernel_model.Workspace`, ``work``). Compiled code
outside ``uvms.dynamics`` (controllers, arm trackers, the simulation loop) reaches the three algorithms only
through the wrappers below, each taking one ``ModelData``:

- :func:`forward_into`: the articulated-body algorithm with hydrodynamics (paper Eqs. 13-23),
- :func:`inverse_into`: the recursive Newton-Euler algorithm (the inverse dynamics, Featherstone Table 5.1),
- :func:`mass_matrix_into`: the composite-rigid-body algorithm (``M`` of ``[nu; qd]``, added mass included).

One ``ModelData`` serves one thread at a time (its workspace is overwritten by every call).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from uvms.dynamics.aba import aba
from uvms.dynamics.crba import crba
from uvms.dynamics.kernel_model import KernelModel, Workspace, make_workspace
from uvms.dynamics.rnea import rnea


class ModelData(NamedTuple):
    """A model's kernel arrays and one workspace for them."""

    body: KernelModel
    work: Workspace


def model_data(model) -> ModelData:
    """A :class:`ModelData` of a :class:`~uvms.model.Model` with a fresh workspace. The kernel arrays are
    copied so that they are writeable (numba types read-only arrays differently: one compiled type for all)."""
    km = model.kernel
    body = KernelModel(*[np.array(a) if isinstance(a, np.ndarray) else a for a in km])
    return ModelData(body=body, work=make_workspace(model.n_bodies))


@njit(cache=True, nogil=True)
def forward_into(md, R, nu, q, qd, tau, f_body, f_ee, v_current, a_fluid, fixed_base, nu_dot, qdd):
    """``nu_dot`` (6) and ``qdd`` (n) by the articulated-body algorithm (:func:`uvms.dynamics.aba.aba`)."""
    aba(md.body, md.work, R, nu, q, qd, tau, f_body, f_ee, v_current, a_fluid, fixed_base, nu_dot, qdd)


@njit(cache=True, nogil=True)
def inverse_into(md, R, nu, q, qd, nu_dot, qdd, f_ee, v_current, a_fluid, f0, tau):
    """The vehicle wrench ``f0`` (6) and joint torques ``tau`` (n) producing ``nu_dot``, ``qdd``
    (:func:`uvms.dynamics.rnea.rnea`)."""
    rnea(md.body, md.work, R, nu, q, qd, nu_dot, qdd, f_ee, v_current, a_fluid, f0, tau)


@njit(cache=True, nogil=True)
def mass_matrix_into(md, q, M):
    """The joint-space inertia ``M`` (6+n, 6+n) at joint angles ``q`` (:func:`uvms.dynamics.crba.crba`)."""
    crba(md.body, md.work, q, M)
