"""The owner of the compiled plant: Pinocchio's ``(model, data)`` and MuJoCo's ``(mjModel, mjData)`` for uvms.

Two levels, one owner:

- :class:`ModelData` couples a model's constant kernel arrays (:class:`~uvms.dynamics.kernel_model.KernelModel`,
  ``body``; built once per model object by :func:`kernel_model` and shared by every ``ModelData`` of it, which
  only read them) with the scratch they need (:class:`~uvms.dynamics.kernel_model.Workspace`, ``work``). Compiled code
  outside ``uvms.dynamics`` (controllers, arm trackers) reaches the three algorithms only through the wrappers
  :func:`forward_into` (articulated-body algorithm with hydrodynamics, paper Eqs. 13-23), :func:`inverse_into`
  (recursive Newton-Euler, Featherstone Table 5.1) and :func:`mass_matrix_into` (composite rigid body).
- :class:`Plant` is what the simulation integrates: the model data, the actuators (thruster layout), the
  water as a :class:`~uvms.hydro.flow.FlowData` (:mod:`uvms.hydro.flow`), the integrator's scratch, whether the vehicle is clamped, and the
  sane-state bounds. It is a numba *structure reference*: passed from Python to a compiled function it costs
  one pointer, not the ~50 arrays inside it, so Python may call the compiled code often (the step API, the
  checked :class:`Dynamics`). Inputs held between two updates travel beside it as :class:`Held`.

:class:`Dynamics` is the Python owner: it builds a plant once for a model, checks every argument of its
methods (types, shapes, finiteness: :class:`~uvms.errors.UvmsInputError` naming the argument), and is the one
object through which the package's Python code evaluates the dynamics. One ``ModelData``, ``Plant`` or
``Dynamics`` serves one thread at a time (their workspaces are overwritten by every call).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, types
from numba.experimental import structref

from uvms.dynamics.aba import aba, aba_inlined
from uvms.dynamics.crba import crba
from uvms.dynamics.kernel_model import KernelModel, Workspace, kernel_model_from, make_workspace
from uvms.dynamics.rnea import rnea
from uvms.hydro.flow import FlowData, uniform_flow_data, with_body_anchors
from uvms.jit import kernel
from uvms.kinematics import normalised_rotation
from uvms.state import JOINTS, NU, POSITION, QUATERNION

DEFAULT_BOUNDS = np.array([1e4, 1e3, 1e3, 1e6])
"""Sane-state limits for divergence detection: |position| [m], |nu| [rad/s, m/s], |qd| [rad/s], |actuator|."""


class ModelData(NamedTuple):
    """A model's kernel arrays and one workspace for them."""

    body: KernelModel
    work: Workspace


class Held(NamedTuple):
    """Inputs held constant between two updates (zero-order hold); written in place by the loop."""

    joint_torques: np.ndarray   # (n,) [N m or N]
    body_wrench: np.ndarray     # (6,) external wrench on the vehicle [moment; force], body axes
    ee_wrench: np.ndarray       # (6,) spatial force on the end effector, end-effector axes
    command: np.ndarray         # (max(m, 6),) actuator commands (the body wrench itself with no thrusters)


class StepScratch(NamedTuple):
    """The integrator's scratch (never allocated inside the loop)."""

    R: np.ndarray               # (3, 3) body-to-world rotation of the stage's quaternion
    vecs: np.ndarray            # (5, 6): the actuators' body wrench, (unused), (unused), nu, (unused)
    thrust: np.ndarray          # (max(m, 1),) thrusts [N]
    stages: np.ndarray          # (6, N): RK4's k1..k4, the stage state, one spare derivative


class PlantData(NamedTuple):
    """The fields of a :class:`Plant` as a named tuple (:func:`plant_data`): what kernels compiled without
    reference counting (:mod:`uvms.jit`) take, since reading a structure reference needs it."""

    body: KernelModel
    work: Workspace
    actuators: tuple
    fluid: FlowData
    scratch: StepScratch
    fixed_base: bool
    bounds: np.ndarray


@structref.register
class PlantType(types.StructRef):
    """numba type of :class:`Plant`."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class Plant(structref.StructRefProxy):
    """The compiled data of a simulation (module docstring). Build with :func:`build_plant`; Python reads its
    parts from the :class:`Dynamics` that made it (attribute access on the proxy is compiled code)."""


structref.define_proxy(Plant, PlantType, ["body", "work", "actuators", "fluid", "scratch", "fixed_base", "bounds"])


@njit(cache=True)
def _new_plant(body, work, actuators, fluid, scratch, fixed_base, bounds):
    return Plant(body, work, actuators, fluid, scratch, fixed_base, bounds)


@njit(cache=True, nogil=True)
def plant_data(plant):
    """The :class:`PlantData` of a :class:`Plant` (the same arrays)."""
    return PlantData(plant.body, plant.work, plant.actuators, plant.fluid, plant.scratch, plant.fixed_base,
                     plant.bounds)


_KERNEL_SLOT = "_uvms_kernel_model"
"""The model attribute holding the model's :class:`KernelModel` (built by :func:`kernel_model` at the first
call)."""


def kernel_model(model) -> KernelModel:
    """The kernel arrays of a :class:`~uvms.model.Model` (:func:`~uvms.dynamics.kernel_model.kernel_model_from`),
    built at the first call and kept in a slot of the model object, so they go with the model (as
    :func:`uvms.dynamics.api.dynamics_of` keeps its ``Dynamics``). The arrays are writeable (numba types read-only
    arrays differently: one compiled type for all) and shared by every user of the model: nothing writes them."""
    try:
        return model.__dict__[_KERNEL_SLOT]
    except KeyError:
        pass
    return model.__dict__.setdefault(_KERNEL_SLOT, kernel_model_from(model))     # atomic: one per model


def model_data(model) -> ModelData:
    """A :class:`ModelData` of a :class:`~uvms.model.Model`: its kernel arrays (:func:`kernel_model`, shared)
    with a fresh workspace."""
    return ModelData(body=kernel_model(model), work=make_workspace(model.n_bodies))


def empty_model_data() -> ModelData:
    """A :class:`ModelData` of no bodies (zero-size arrays of the kernel arrays' dtypes and dimensions): the
    placeholder of an unused model slot (a controller's or an arm tracker's), of the same numba type as every
    model's."""
    def none(ndim: int, dtype=np.float64) -> np.ndarray:
        return np.zeros((0,) * ndim, dtype=dtype)

    body = KernelModel(parent=none(1, np.int64), tree_E=none(3), tree_r=none(2), joint=none(2),
                       joint_kind=none(1, np.int64), S=none(2), inertia=none(3), inertia_h=none(3), added_mass=none(3),
                       mass=none(1), com=none(2), fluid_mass=none(1), cob=none(2), vehicle_drag_linear=none(1),
                       vehicle_drag_angular=none(1), cylinder=none(3), fossen=none(3), shapes=none(3), ee_body=0,
                       ee_E=none(2), ee_r=none(1), gravity=none(1),
                       disturbance=none(1))
    work = Workspace(*[none(a.ndim, a.dtype) for a in make_workspace(0)])
    return ModelData(body=body, work=work)


def fluid_table(times, velocity, acceleration) -> FlowData:
    """The compiled water of a uniform current table alone (:func:`uvms.hydro.flow.uniform_flow_data`): world
    velocity [m/s] and fluid acceleration [m/s^2] at ``times`` [s], linear between, held outside."""
    return uniform_flow_data(np.array(times, dtype=float).reshape(-1), np.array(velocity, dtype=float).reshape(-1, 3),
                             np.array(acceleration, dtype=float).reshape(-1, 3))


def build_plant(model, *, thrusters: tuple = (), fluid: FlowData | None = None, fixed_base: bool = False,
                bounds: np.ndarray = DEFAULT_BOUNDS) -> tuple[Plant, ModelData]:
    """The :class:`Plant` of ``model`` with a thruster layout (empty: ideal body-wrench actuation), the water
    (a :class:`~uvms.hydro.flow.FlowData`; default: the model's constant environment) and a clamped or free
    vehicle; also returns its :class:`ModelData` (the same arrays, for Python-side reading)."""
    from uvms.thrusters.actuation import actuator_kernel, n_actuator_states

    md = model_data(model)
    actuators = actuator_kernel(tuple(thrusters))
    if fluid is None:
        fluid = fluid_table([0.0], [model.current], [model.fluid_acceleration])
    fluid = with_body_anchors(fluid, model.n_bodies)
    size = JOINTS + 2 * model.n_joints + n_actuator_states(actuators)
    scratch = StepScratch(R=np.zeros((3, 3)), vecs=np.zeros((5, 6)), thrust=np.zeros(max(len(thrusters), 1)),
                          stages=np.zeros((6, size)))
    plant = _new_plant(md.body, md.work, actuators, fluid, scratch, bool(fixed_base),
                       np.array(bounds, dtype=float))
    return plant, md


def held_inputs(n_joints: int, n_thrusters: int) -> Held:
    """Zero :class:`Held` inputs for ``n_joints`` joints and ``n_thrusters`` thrusters."""
    return Held(np.zeros(n_joints), np.zeros(6), np.zeros(6), np.zeros(max(n_thrusters, 6)))


# ------------------------------------------------------------------------------------- compiled entry points


@kernel
def forward_into(md, R, p, nu, q, qd, tau, f_body, f_ee, flow, t, fixed_base, nu_dot, qdd):
    """``nu_dot`` (6) and ``qdd`` (n) by the articulated-body algorithm (:func:`uvms.dynamics.aba.aba`), the
    vehicle at rotation ``R`` and world position ``p`` in the water ``flow`` (:class:`FlowData`) at ``t``."""
    aba(md.body, md.work, R, p, nu, q, qd, tau, f_body, f_ee, flow, t, fixed_base, nu_dot, qdd)


@kernel
def inverse_into(md, R, p, nu, q, qd, nu_dot, qdd, f_ee, flow, t, f0, tau):
    """The vehicle wrench ``f0`` (6) and joint torques ``tau`` (n) producing ``nu_dot``, ``qdd``
    (:func:`uvms.dynamics.rnea.rnea`; pose and water as :func:`forward_into`)."""
    rnea(md.body, md.work, R, p, nu, q, qd, nu_dot, qdd, f_ee, flow, t, f0, tau)


@kernel
def mass_matrix_into(md, q, M):
    """The joint-space inertia ``M`` (6+n, 6+n) at joint angles ``q`` (:func:`uvms.dynamics.crba.crba`)."""
    crba(md.body, md.work, q, M)


@njit(cache=True, inline="always")
def _rotation(plant, quaternion):
    """The plant's scratch rotation, set to the body-to-world rotation of ``quaternion`` (normalised)."""
    R = plant.scratch.R
    normalised_rotation(quaternion, R)
    return R


@njit(cache=True)
def plant_forward(plant, t, x, tau, wrenches, fixed_base, out):
    """:func:`forward_into` for a state vector ``x`` (layout of :mod:`uvms.state`: ``[p | quaternion | nu |
    q | qd | ...]``) in the plant's water at ``t`` [s], into ``out = [nu_dot (6) | qdd (n)]``; ``wrenches =
    [body wrench (6) | end-effector wrench (6)]``. Returns whether every acceleration is finite. The ABA is
    inlined (``aba_inlined``): the call from Python is the hot path of :func:`uvms.forward_dynamics`."""
    n = out.shape[0] - 6
    R = _rotation(plant, x[QUATERNION:NU])
    aba_inlined(plant.body, plant.work, R, x[POSITION:QUATERNION], x[NU:JOINTS], x[JOINTS:JOINTS + n],
                x[JOINTS + n:JOINTS + 2 * n], tau, wrenches[0:6], wrenches[6:12], plant.fluid, t, fixed_base, out[0:6],
                out[6:])
    for k in range(out.shape[0]):
        if not np.isfinite(out[k]):
            return False
    return True


@njit(cache=True)
def plant_inverse(plant, t, x, u, out):
    """``out = [f_0 (6) | tau (n)]`` by :func:`inverse_into` for a state vector ``x`` (as :func:`plant_forward`)
    and ``u = [nu_dot (6) | qdd (n) | end-effector wrench (6)]``, in the plant's water at ``t`` [s]."""
    n = out.shape[0] - 6
    R = _rotation(plant, x[QUATERNION:NU])
    rnea(plant.body, plant.work, R, x[POSITION:QUATERNION], x[NU:JOINTS], x[JOINTS:JOINTS + n],
         x[JOINTS + n:JOINTS + 2 * n], u[0:6], u[6:6 + n], u[6 + n:12 + n], plant.fluid, t, out[0:6], out[6:6 + n])


@njit(cache=True)
def plant_mass_matrix(plant, q, M):
    """:func:`mass_matrix_into` on the plant's model."""
    crba(plant.body, plant.work, q, M)
