"""Flat arrays of a :class:`~uvms.model.Model` for the compiled kernels, and their preallocated workspace.

Built once per model (:func:`kernel_model_from`); the kernels never allocate (one workspace per run).
Body 0 is the vehicle, bodies 1..n the links of a kinematic tree (``parent[i] < i``); index 0 of per-joint
arrays is unused padding so that body ``i`` and its joint share an index, as in Featherstone's
``model.parent(i)``. Joint ``i``'s motion subspace is the unit 6-vector ``S_i`` (``[axis; 0]`` revolute,
``[0; axis]`` prismatic, in the body frame, which is the joint frame).

The kernels compiled with :mod:`uvms.jit` read this module's column and effect indices as compile-time
constants, so the kernel cache's fingerprint (:mod:`uvms._cache`, which keys on that module's name) covers it.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from uvms.kinematics import JOINT_PRISMATIC, JOINT_REVOLUTE, JOINT_Z
from uvms.spatial import spatial_inertia

Z_AXIS = 2
"""Index of ``e_z`` in a ``[angular; linear]`` 6-vector: a ``JOINT_Z`` joint's motion subspace is ``S = e_z``, so
``S^T x = x[Z_AXIS]``, ``I S = I[:, Z_AXIS]`` and ``v + S qd`` adds ``qd`` to ``v[Z_AXIS]``."""

DAMPING, FRICTION, INV_SPEED = 1, 2, 3
"""Columns of :attr:`KernelModel.joint` after the offset (column ``JOINT_OFFSET = 0``, defined with the joint
kinds in :mod:`uvms.kinematics`, which reads it). (The kernel model packs small per-body parameters into few
arrays: every array of the named tuple costs time on each kernel call.)"""


class KernelModel(NamedTuple):
    """Model arrays read by the kernels. Shapes use ``nb = n + 1`` bodies; units SI."""

    parent: np.ndarray          # (nb,) int64, parent body index, -1 for the vehicle
    tree_E: np.ndarray          # (nb, 3, 3) parent-to-joint-frame coordinate rotation (before the joint angle)
    tree_r: np.ndarray          # (nb, 3) joint-frame origin in parent coordinates [m]
    joint: np.ndarray           # (nb, 4) per joint: offset (modified-DH theta offset) [rad or m], viscous damping
                                #   b [N m s/rad or N s/m], Coulomb friction F_c [N m or N], the inverse 1 / v_s
                                #   of its regularisation speed [s/rad or s/m] (columns JOINT_OFFSET .. INV_SPEED)
    joint_kind: np.ndarray      # (nb,) int64: JOINT_Z (revolute about z, modified DH), JOINT_REVOLUTE, JOINT_PRISMATIC
    S: np.ndarray               # (nb, 6) motion subspace of each joint, body axes (row 0 unused): [axis; 0], [0; axis]
    inertia: np.ndarray         # (nb, 6, 6) rigid spatial inertia about the body origin
    inertia_h: np.ndarray       # (nb, 6, 6) hydrodynamic inertia I + I_A (Eq. 13's I^H)
    added_mass: np.ndarray      # (nb, 6, 6) I_A about the body origin (Eq. 2)
    mass: np.ndarray            # (nb,) the mass that weighs [kg] (Model.weight_mass; read by the gravity force only)
    com: np.ndarray             # (nb, 3) where it acts [m] (Model.weight_center; the inertias use Model.com)
    fluid_mass: np.ndarray      # (nb,) displaced-fluid mass m_f [kg] (Eq. 7)
    cob: np.ndarray             # (nb, 3) centre of buoyancy b [m] (Eq. 8)
    vehicle_drag_linear: np.ndarray     # (3,) 0.5 rho A_j Cd_j [kg/m] (Eq. 3)
    vehicle_drag_angular: np.ndarray    # (3,) rho Cd a^5 / 32 [kg m^2] (Eq. 4, closed form)
    cylinder: np.ndarray        # (nb, 5, 3) each link's drag cylinder (Eq. 6): rows 0-2 the body-to-cylinder
                                #   rotation (the cylinder along its x), row 3 its origin in the body [m], row 4
                                #   [0.5 rho Cd (2 r) per unit length [kg/m^2], length L [m], 1.0 if the cylinder is
                                #   not along the body x axis from the origin else 0.0]
    fossen: np.ndarray          # (nb, 85, 6) Fossen damping of each body: rows 0-5 D_l, rows 6-11 D_q
                                #   ([angular; linear] entries), row 12 [point (3) [m], 1.0 if the body has any
                                #   Fossen damping else 0.0, number of shape drag rows, 0] (docs/models.md)
    shapes: np.ndarray          # (nb, max(1, k), DRAG_ROW) each body's shape drag table (uvms.hydro.shapes,
                                #   coefficients 0.5 rho Cd (area) at the model's density)
    ee_body: int                # the body the end effector is fixed in
    ee_E: np.ndarray            # (3, 3) body-to-end-effector coordinate rotation
    ee_r: np.ndarray            # (3,) end-effector origin in body coordinates [m]
    gravity: np.ndarray         # (3,) world gravitational acceleration a_g [m/s^2]
    disturbance: np.ndarray     # (6,) the model's constant disturbance wrench on the vehicle, body axes
                                #   [moment; force] [N m, N] (Model.disturbance_wrench; read by stage_inputs only)


ADDED_MASS, DRAG, BUOYANCY, GRAVITY = 0, 1, 2, 3
"""Slots of :attr:`Workspace.forces`, each body's named hydrodynamic and gravity forces (paper Eqs. 2-8, body
axes, about the body origin, ``[moment; force]``): ``ADDED_MASS`` ``I_A a_f - (nu_r x*) I_A nu_r`` (Eq. 2 less
its ``-I_A a``, which is in the articulated inertia), ``DRAG`` (Eqs. 3-6, Fossen and shape drag included),
``BUOYANCY`` ``m_f (a_f - a_g)`` at the centre of buoyancy (Eqs. 7-8), ``GRAVITY`` ``m a_g`` at the centre of
mass."""
N_FORCES = 4


class Workspace(NamedTuple):
    """Scratch arrays for one kernel call, allocated once per run (never inside the loop).

    Per-body arrays (first index the body) hold what the passes compute and later passes or read-outs
    (:mod:`uvms.dynamics.inspect`, the controllers) use; the others are named scratch of one step of a pass."""

    E: np.ndarray       # (nb, 3, 3) parent-to-body coordinate rotation of Xup_i = plucker(E_i, r_i)
    r: np.ndarray       # (nb, 3) body origin in parent coordinates [m]
    v: np.ndarray       # (nb, 6) body spatial velocity
    c: np.ndarray       # (nb, 6) velocity-product acceleration v_i x S qd_i
    a: np.ndarray       # (nb, 6) body spatial acceleration
    IA: np.ndarray      # (nb, 6, 6) articulated (or composite) inertia
    pA: np.ndarray      # (nb, 6) articulated bias force
    U: np.ndarray       # (nb, 6) IA S
    d: np.ndarray       # (nb,) S^T IA S
    u: np.ndarray       # (nb,) the joint's passive torque after the outward pass; then tau + tau_p - S^T pA
    g: np.ndarray       # (nb, 3) gravity in body axes
    vc: np.ndarray      # (nb, 3) current velocity in body axes
    af: np.ndarray      # (nb, 3) fluid acceleration in body axes (world a_f rotated)
    nu_r: np.ndarray    # (nb, 6) body velocity relative to the fluid (Eq. 2's nu_r)
    forces: np.ndarray  # (nb, N_FORCES, 6) each body's named forces (slots ADDED_MASS, DRAG, BUOYANCY, GRAVITY)
    Ia: np.ndarray      # (6, 6) pass 2: IA_i less its joint's subspace, IA_i - U_i U_i^T / d_i
    rotated: np.ndarray     # (6, 6) the congruence's rotated inertia blocks (blocks.congruence_add_plucker)
    chol: np.ndarray    # (6, 6) Cholesky factor of the vehicle's articulated inertia (pass 3)
    h: np.ndarray       # (6,) I_i v_i (outward pass), I^H_i a_i (Newton-Euler)
    pa: np.ndarray      # (6,) pass 2: the bias force handed to the parent
    rhs: np.ndarray     # (6,) pass 3: -pA_0, the right-hand side of IA_0 a_0 = -pA_0
    f_ee: np.ndarray    # (6,) the end-effector wrench moved to its body, eeX_b^T f_ee (Eq. 14)
    no_wrench: np.ndarray   # (6,) zeros: the Newton-Euler algorithm's body wrench (it computes that wrench)
    sw: np.ndarray      # (6,) S_i qd_i of a joint of any axis (outward pass)
    column: np.ndarray  # (6,) CRBA: the force F = IC_i S_i of joint i's column, in the axes of the current body
    column_up: np.ndarray   # (6,) CRBA: F handed to the parent, Xup_j^T F
    a_fluid: np.ndarray     # (6,) the fluid's acceleration seen in one body's axes (hydro.current)
    nu_c: np.ndarray    # (6,) relative velocity at a link's drag cylinder; Fossen / shape drag of one body
    f_c: np.ndarray     # (6,) drag in the cylinder's axes
    shape_work: np.ndarray  # (12,) the shape drag kernel's work array (hydro.shapes.WORK_SIZE)
    R_world: np.ndarray     # (nb, 3, 3) body-to-world rotation (outward pass, non-uniform flows only)
    p_world: np.ndarray     # (nb, 3) body origin in the world [m] (outward pass, non-uniform flows only)
    points: np.ndarray      # (nb, 3) where the water is evaluated: each body's centre of buoyancy, world [m]
    fluid_v: np.ndarray     # (3,) the water's velocity there, world [m/s] (hydro.flow.fluid_at)
    fluid_a: np.ndarray     # (3,) the water's material acceleration there, world [m/s^2]
    fluid_grad: np.ndarray  # (3, 3) the water's velocity gradient there, du_r/dx_c [1/s]
    table_v: np.ndarray     # (3,) the uniform table's velocity at the pass's time, world [m/s] (non-uniform flows)
    table_a: np.ndarray     # (3,) the uniform table's acceleration then, world [m/s^2]


def kernel_model_from(model) -> KernelModel:
    """Flatten a :class:`~uvms.model.Model` into kernel arrays (spatial inertias, drag constants)."""
    nb = model.n_bodies
    n = nb - 1
    rho = model.density
    parent = np.full(nb, -1, dtype=np.int64)
    parent[1:] = model.joint_parent
    tree_E = np.zeros((nb, 3, 3))
    tree_E[0] = np.eye(3)
    tree_r = np.zeros((nb, 3))
    joint = np.zeros((nb, 4))
    joint[0, INV_SPEED] = 1.0
    S = np.zeros((nb, 6))
    joint_kind = np.zeros(nb, dtype=np.int64)
    cylinder = np.zeros((nb, 5, 3))
    cylinder[:, 0:3] = np.eye(3)
    for i in range(1, nb):
        tree_E[i] = model.joint_rotation[i - 1].T
        tree_r[i] = model.joint_position[i - 1]
        joint[i] = (model.theta_offset[i - 1], model.joint_damping[i - 1], model.joint_friction[i - 1],
                    1.0 / model.joint_friction_speed[i - 1])
        prismatic = model.joint_type[i - 1] == "prismatic"
        axis = model.joint_axis[i - 1]
        (S[i, 3:6] if prismatic else S[i, 0:3])[:] = axis
        joint_kind[i] = JOINT_PRISMATIC if prismatic else (
            JOINT_Z if np.array_equal(axis, [0.0, 0.0, 1.0]) else JOINT_REVOLUTE)
        E, o = model.link_cylinder_rotation[i - 1].T, model.link_cylinder_origin[i - 1]
        cylinder[i, 0:3], cylinder[i, 3] = E, o
        cylinder[i, 4] = (rho * model.link_drag_coefficient[i - 1] * model.link_radius[i - 1],   # 0.5 rho Cd (2 r)
                          model.link_length[i - 1], 0.0 if np.array_equal(E, np.eye(3)) and not o.any() else 1.0)
    inertia = np.stack([spatial_inertia(model.mass[i], model.com[i], model.inertia_com[i]) for i in range(nb)])
    added_mass = np.array(model.added_mass, dtype=float)
    a = model.vehicle_rotational_drag_side
    return KernelModel(
        parent=parent,
        tree_E=tree_E,
        tree_r=tree_r,
        joint=joint,
        joint_kind=joint_kind,
        S=S,
        inertia=inertia,
        inertia_h=inertia + added_mass,
        added_mass=added_mass,
        mass=np.array(model.weight_mass, dtype=float),
        com=np.array(model.weight_center, dtype=float),
        fluid_mass=np.array(model.buoyancy_mass, dtype=float),
        cob=np.array(model.cob, dtype=float),
        vehicle_drag_linear=0.5 * rho * model.vehicle_drag_area * model.vehicle_drag_coefficient,
        vehicle_drag_angular=np.full(3, rho * model.vehicle_rotational_drag_coefficient * a**5 / 32.0),
        cylinder=cylinder,
        fossen=_fossen_rows(model),
        shapes=_shape_rows(model),
        ee_body=int(model.ee_body),
        ee_E=np.array(model.ee_rotation, dtype=float).T.copy(),
        ee_r=np.array(model.ee_position, dtype=float),
        gravity=np.array(model.gravity, dtype=float),
        disturbance=np.array(model.disturbance_wrench, dtype=float),
    )


def _fossen_rows(model) -> np.ndarray:
    """:attr:`KernelModel.fossen` of a model: ``D_l``, ``D_q`` and ``[point, flag, 0, 0]`` per body."""
    nb = model.n_bodies
    from uvms.hydro.fossen import CROSS_ABS_END, CROSS_END, CROSS_ROWS

    out = np.zeros((nb, CROSS_END, 6))
    out[:, 0:6] = model.damping_linear
    out[:, 6:12] = model.damping_quadratic
    out[:, 12, 0:3] = model.damping_point
    out[:, 12, 3] = [1.0 if np.any(model.damping_linear[i]) or np.any(model.damping_quadratic[i]) else 0.0
                     for i in range(nb)]
    out[:, 12, 4] = model.shape_count
    cross = np.asarray(model.damping_cross, dtype=float)
    out[:, CROSS_ROWS:CROSS_ABS_END] = cross[:, 0].reshape(nb, 36, 6)
    out[:, CROSS_ABS_END:CROSS_END] = cross[:, 1].reshape(nb, 36, 6)
    out[:, 12, 5] = [1.0 if np.any(cross[i]) else 0.0 for i in range(nb)]
    return out


def _shape_rows(model) -> np.ndarray:
    """:attr:`KernelModel.shapes`: the model's shape drag tables with at least one (zero) row per body."""
    from uvms.hydro.shapes import COL_COEFFICIENTS

    table = np.asarray(model.shape_drag, dtype=float)
    nb, k, width = table.shape
    out = np.zeros((nb, max(1, k), width))
    out[:, :k] = table
    out[:, :k, COL_COEFFICIENTS:] *= model.density      # the model keeps them per unit density
    return out


def make_workspace(n_bodies: int) -> Workspace:
    """Allocate the scratch arrays for a model with ``n_bodies`` bodies."""
    from uvms.hydro.shapes import WORK_SIZE

    nb = n_bodies
    return Workspace(
        E=np.zeros((nb, 3, 3)), r=np.zeros((nb, 3)), v=np.zeros((nb, 6)), c=np.zeros((nb, 6)), a=np.zeros((nb, 6)),
        IA=np.zeros((nb, 6, 6)), pA=np.zeros((nb, 6)), U=np.zeros((nb, 6)), d=np.zeros(nb), u=np.zeros(nb),
        g=np.zeros((nb, 3)), vc=np.zeros((nb, 3)), af=np.zeros((nb, 3)), nu_r=np.zeros((nb, 6)),
        forces=np.zeros((nb, N_FORCES, 6)), Ia=np.zeros((6, 6)), rotated=np.zeros((6, 6)), chol=np.zeros((6, 6)),
        h=np.zeros(6), pa=np.zeros(6), rhs=np.zeros(6), f_ee=np.zeros(6), no_wrench=np.zeros(6), sw=np.zeros(6),
        column=np.zeros(6), column_up=np.zeros(6), a_fluid=np.zeros(6), nu_c=np.zeros(6), f_c=np.zeros(6),
        shape_work=np.zeros(WORK_SIZE), R_world=np.zeros((nb, 3, 3)), p_world=np.zeros((nb, 3)),
        points=np.zeros((nb, 3)), fluid_v=np.zeros(3), fluid_a=np.zeros(3),
        fluid_grad=np.zeros((3, 3)), table_v=np.zeros(3), table_a=np.zeros(3),
    )
