"""Flat arrays of a :class:`~uvms.model.Model` for the compiled kernels, and their preallocated workspace.

Built once per model (:func:`kernel_model_from`); the kernels never allocate (one workspace per run).
Body 0 is the vehicle, bodies 1..n the links of a kinematic tree (``parent[i] < i``); index 0 of per-joint
arrays is unused padding so that body ``i`` and its joint share an index, as in Featherstone's
``model.parent(i)``. Joint ``i``'s motion subspace is the unit 6-vector ``S_i`` (``[axis; 0]`` revolute,
``[0; axis]`` prismatic, in the body frame, which is the joint frame).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from uvms.spatial import spatial_inertia


class KernelModel(NamedTuple):
    """Model arrays read by the kernels. Shapes use ``nb = n + 1`` bodies; units SI."""

    parent: np.ndarray          # (nb,) int64, parent body index, -1 for the vehicle
    tree_E: np.ndarray          # (nb, 3, 3) parent-to-joint-frame coordinate rotation (before the joint angle)
    tree_r: np.ndarray          # (nb, 3) joint-frame origin in parent coordinates [m]
    theta_offset: np.ndarray    # (nb,) joint offset (modified-DH theta offset) [rad or m]
    S: np.ndarray               # (nb, 6) motion subspace of each joint, body axes (row 0 unused)
    prismatic: np.ndarray       # (nb,) bool, joint i is prismatic (translation along its axis)
    joint_damping: np.ndarray   # (nb,) viscous damping b [N m s/rad or N s/m]
    joint_friction: np.ndarray  # (nb,) Coulomb friction F_c [N m or N]
    friction_speed: np.ndarray  # (nb,) regularisation speed v_s of the Coulomb law [rad/s or m/s]
    inertia: np.ndarray         # (nb, 6, 6) rigid spatial inertia about the body origin
    inertia_h: np.ndarray       # (nb, 6, 6) hydrodynamic inertia I + I_A (Eq. 13's I^H)
    added_mass: np.ndarray      # (nb, 6, 6) I_A about the body origin (Eq. 2)
    mass: np.ndarray            # (nb,) [kg]
    com: np.ndarray             # (nb, 3) [m]
    fluid_mass: np.ndarray      # (nb,) displaced-fluid mass m_f [kg] (Eq. 7)
    cob: np.ndarray             # (nb, 3) centre of buoyancy b [m] (Eq. 8)
    vehicle_drag_linear: np.ndarray     # (3,) 0.5 rho A_j Cd_j [kg/m] (Eq. 3)
    vehicle_drag_angular: np.ndarray    # (3,) rho Cd a^5 / 32 [kg m^2] (Eq. 4, closed form)
    link_drag: np.ndarray       # (nb,) 0.5 rho Cd (2 r) per unit length [kg/m^2] (Eq. 6)
    link_length: np.ndarray     # (nb,) cylinder length L [m]
    cyl_E: np.ndarray           # (nb, 3, 3) body-to-cylinder coordinate rotation (cylinder along its x)
    cyl_o: np.ndarray           # (nb, 3) cylinder origin in body coordinates [m]
    ee_body: np.ndarray         # (1,) int64, the body the end effector is fixed in
    ee_E: np.ndarray            # (3, 3) body-to-end-effector coordinate rotation
    ee_r: np.ndarray            # (3,) end-effector origin in body coordinates [m]
    gravity: np.ndarray         # (3,) world gravitational acceleration a_g [m/s^2]


class Workspace(NamedTuple):
    """Scratch arrays for one kernel call, allocated once per run (never inside the loop)."""

    Xup: np.ndarray     # (nb, 6, 6) motion transform parent -> body i
    E: np.ndarray       # (nb, 3, 3) parent-to-body coordinate rotation
    r: np.ndarray       # (nb, 3) body origin in parent coordinates [m]
    v: np.ndarray       # (nb, 6) body spatial velocity
    c: np.ndarray       # (nb, 6) velocity-product acceleration v_i x S qd_i
    a: np.ndarray       # (nb, 6) body spatial acceleration
    IA: np.ndarray      # (nb, 6, 6) articulated (or composite) inertia
    pA: np.ndarray      # (nb, 6) articulated bias force
    U: np.ndarray       # (nb, 6) IA S
    d: np.ndarray       # (nb,) S^T IA S
    u: np.ndarray       # (nb,) tau - S^T pA
    g: np.ndarray       # (nb, 3) gravity in body axes
    vc: np.ndarray      # (nb, 3) current velocity in body axes
    af: np.ndarray      # (nb, 3) fluid acceleration in body axes
    m6: np.ndarray      # (3, 6, 6) scratch matrices
    w6: np.ndarray      # (5, 6) scratch vectors
    f4: np.ndarray      # (4, 6) one body's named forces: added mass, drag, buoyancy, gravity


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
    theta_offset = np.zeros(nb)
    S = np.zeros((nb, 6))
    prismatic = np.zeros(nb, dtype=np.bool_)
    cyl_E = np.tile(np.eye(3), (nb, 1, 1))
    cyl_o = np.zeros((nb, 3))
    for i in range(1, nb):
        tree_E[i] = model.joint_rotation[i - 1].T
        tree_r[i] = model.joint_position[i - 1]
        theta_offset[i] = model.theta_offset[i - 1]
        prismatic[i] = model.joint_type[i - 1] == "prismatic"
        (S[i, 3:6] if prismatic[i] else S[i, 0:3])[:] = model.joint_axis[i - 1]
        cyl_E[i] = model.link_cylinder_rotation[i - 1].T
        cyl_o[i] = model.link_cylinder_origin[i - 1]
    joint_damping, joint_friction, friction_speed = np.zeros(nb), np.zeros(nb), np.ones(nb)
    joint_damping[1:] = model.joint_damping
    joint_friction[1:] = model.joint_friction
    friction_speed[1:] = model.joint_friction_speed
    inertia = np.stack([spatial_inertia(model.mass[i], model.com[i], model.inertia_com[i]) for i in range(nb)])
    added_mass = np.array(model.added_mass, dtype=float)
    link_drag = np.zeros(nb)
    link_length = np.zeros(nb)
    link_drag[1:] = rho * model.link_drag_coefficient * model.link_radius   # 0.5 rho Cd (2 r)
    link_length[1:] = model.link_length
    a = model.vehicle_rotational_drag_side
    return KernelModel(
        parent=parent,
        tree_E=tree_E,
        tree_r=tree_r,
        theta_offset=theta_offset,
        S=S,
        prismatic=prismatic,
        joint_damping=joint_damping,
        joint_friction=joint_friction,
        friction_speed=friction_speed,
        inertia=inertia,
        inertia_h=inertia + added_mass,
        added_mass=added_mass,
        mass=np.array(model.mass, dtype=float),
        com=np.array(model.com, dtype=float),
        fluid_mass=np.array(model.buoyancy_mass, dtype=float),
        cob=np.array(model.cob, dtype=float),
        vehicle_drag_linear=0.5 * rho * model.vehicle_drag_area * model.vehicle_drag_coefficient,
        vehicle_drag_angular=np.full(3, rho * model.vehicle_rotational_drag_coefficient * a**5 / 32.0),
        link_drag=link_drag,
        link_length=link_length,
        cyl_E=cyl_E,
        cyl_o=cyl_o,
        ee_body=np.array([model.ee_body], dtype=np.int64),
        ee_E=np.array(model.ee_rotation, dtype=float).T.copy(),
        ee_r=np.array(model.ee_position, dtype=float),
        gravity=np.array(model.gravity, dtype=float),
    )


def make_workspace(n_bodies: int) -> Workspace:
    """Allocate the scratch arrays for a model with ``n_bodies`` bodies."""
    nb = n_bodies
    return Workspace(
        Xup=np.zeros((nb, 6, 6)), E=np.zeros((nb, 3, 3)), r=np.zeros((nb, 3)), v=np.zeros((nb, 6)), c=np.zeros((nb, 6)),
        a=np.zeros((nb, 6)), IA=np.zeros((nb, 6, 6)), pA=np.zeros((nb, 6)), U=np.zeros((nb, 6)),
        d=np.zeros(nb), u=np.zeros(nb), g=np.zeros((nb, 3)), vc=np.zeros((nb, 3)), af=np.zeros((nb, 3)),
        m6=np.zeros((3, 6, 6)), w6=np.zeros((5, 6)), f4=np.zeros((4, 6)),
    )
