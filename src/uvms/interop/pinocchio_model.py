"""The rigid part of a :class:`~uvms.model.Model` as a Pinocchio model (tests and benchmarks only).

Pinocchio has no hydrodynamics: added mass, drag, buoyancy and currents are ignored, so compare against
``model.with_effects(added_mass=False, drag=False, buoyancy=False)``. ``pinocchio`` is imported inside the
functions: it is a test/benchmark dependency, not a runtime one.

Conventions that differ between the two libraries, converted here and nowhere else:

==================  =====================================  ==========================================
quantity            uvms                                   Pinocchio (free-flyer root)
==================  =====================================  ==========================================
configuration       ``position, quaternion [w,x,y,z], q``  ``[x, y, z, qx, qy, qz, qw, q...]``
velocity            ``[omega; v]`` body axes, ``qd``       ``[v; omega]`` local frame, ``qd``
acceleration        ``nu_dot = [alpha; a]`` (spatial)      ``ddq[:6] = [a; alpha]`` (spatial, local)
wrench on vehicle   ``[moment; force]`` body axes          ``Force(linear, angular)`` on joint 1
==================  =====================================  ==========================================

Joint ``i`` (revolute about, or prismatic along, ``joint_axis[i]``; ``RZ`` for the z axis of modified DH) is
placed at ``SE3(joint_rotation[i] @ Rot(axis, theta_offset[i]), joint_position[i])`` (prismatic: shifted by
``offset * axis``) on the Pinocchio joint of its parent body ``joint_parent[i]``, so that the link frame is
``placement * Rot(axis, q_i)`` as in :func:`uvms.dynamics.passes.joint_transform`. The end effector is an
operational frame named ``"end_effector"`` on the joint of body ``ee_body``. Gravity is ``model.gravity`` in
the world frame. :class:`JointMap` maps a model to Pinocchio's own URDF parser instead.
"""

from __future__ import annotations

import numpy as np

from uvms.spatial import rotz

END_EFFECTOR_FRAME = "end_effector"


def pinocchio_model_from(model, *, fixed_base: bool = False, base_rotation=None, base_position=None):
    """A ``pinocchio.Model`` of the rigid bodies of ``model``.

    Args:
        model: a uvms :class:`~uvms.model.Model`.
        fixed_base: ``False``: a free-flyer root joint carries the vehicle (``nq = 7 + n``, ``nv = 6 + n``).
            ``True``: the vehicle is welded to the world at ``(base_rotation, base_position)`` and only the
            arm joints remain (``nq = nv = n``), as ``forward_dynamics(..., fixed_base=True)``.
        base_rotation: (3, 3) vehicle orientation (body to world) for ``fixed_base``; identity by default.
        base_position: (3,) vehicle position in the world for ``fixed_base`` [m]; zero by default.
    """
    import pinocchio as pin

    pm = pin.Model()
    pm.name = model.name
    pm.gravity.linear = np.array(model.gravity, dtype=float)
    vehicle_inertia = pin.Inertia(float(model.mass[0]), np.array(model.com[0], dtype=float),
                                  np.array(model.inertia_com[0], dtype=float))
    if fixed_base:
        R0 = np.eye(3) if base_rotation is None else np.array(base_rotation, dtype=float)
        p0 = np.zeros(3) if base_position is None else np.array(base_position, dtype=float)
        base = pin.SE3(R0, p0)
        parent = 0
    else:
        parent = pm.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), model.body_names[0])
        pm.appendBodyToJoint(parent, vehicle_inertia, pin.SE3.Identity())
        base = pin.SE3.Identity()
    ids = [parent]                    # Pinocchio joint id carrying each uvms body
    for i in range(model.n_joints):
        axis = np.array(model.joint_axis[i], dtype=float)
        offset = float(model.theta_offset[i])
        R = np.array(model.joint_rotation[i], dtype=float)
        p = np.array(model.joint_position[i], dtype=float)
        if model.joint_type[i] == "prismatic":
            placement = pin.SE3(R, p + R @ axis * offset)
            joint = pin.JointModelPrismaticUnaligned(*axis)
        else:
            placement = pin.SE3(R @ _axis_rotation(axis, offset), p)
            joint = pin.JointModelRZ() if np.array_equal(axis, [0.0, 0.0, 1.0]) else \
                pin.JointModelRevoluteUnaligned(*axis)
        body_parent = int(model.joint_parent[i])
        if body_parent == 0:
            placement = base * placement
        jid = pm.addJoint(ids[body_parent], joint, placement, model.joint_names[i])
        pm.appendBodyToJoint(jid, pin.Inertia(float(model.mass[i + 1]), np.array(model.com[i + 1], dtype=float),
                                              np.array(model.inertia_com[i + 1], dtype=float)), pin.SE3.Identity())
        ids.append(jid)
    parent = ids[model.ee_body]
    ee = pin.SE3(np.array(model.ee_rotation, dtype=float), np.array(model.ee_position, dtype=float))
    if model.ee_body == 0:
        ee = base * ee
    pm.addFrame(pin.Frame(END_EFFECTOR_FRAME, parent, ee, pin.FrameType.OP_FRAME))
    return pm


def _axis_rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation by ``angle`` about the unit ``axis`` (Rodrigues); exactly ``rotz`` for the z axis."""
    if np.array_equal(axis, [0.0, 0.0, 1.0]):
        return rotz(angle)
    K = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * K @ K


def pinocchio_configuration(state, *, fixed_base: bool = False) -> np.ndarray:
    """Pinocchio ``q``: ``[x, y, z, qx, qy, qz, qw, q...]`` (free flyer) or the joint angles (fixed base)."""
    q = np.array(state.q, dtype=float)
    if fixed_base:
        return q
    w, x, y, z = state.quaternion
    return np.concatenate([state.position, [x, y, z, w], q])


def pinocchio_velocity(state, *, fixed_base: bool = False) -> np.ndarray:
    """Pinocchio ``v``: ``[v; omega; qd]`` (free flyer, local frame) or the joint rates (fixed base)."""
    qd = np.array(state.qd, dtype=float)
    if fixed_base:
        return qd
    return np.concatenate([state.nu[3:6], state.nu[0:3], qd])


def generalized_from_pinocchio(x: np.ndarray, *, fixed_base: bool = False) -> np.ndarray:
    """A Pinocchio velocity-space vector (``v``, ``ddq``, ``tau``) reordered to uvms ``[angular; linear; joints]``."""
    x = np.asarray(x, dtype=float)
    if fixed_base:
        return x.copy()
    return np.concatenate([x[3:6], x[0:3], x[6:]])


def matrix_from_pinocchio(M: np.ndarray) -> np.ndarray:
    """A free-flyer ``nv x nv`` matrix (e.g. ``crba``) reordered to uvms ``[angular; linear; joints]``."""
    M = np.asarray(M, dtype=float)
    perm = np.concatenate([[3, 4, 5, 0, 1, 2], np.arange(6, M.shape[0])])
    return M[np.ix_(perm, perm)]


def body_wrench_force(body_wrench):
    """uvms ``[moment; force]`` on the vehicle (body axes) as a local-frame ``pinocchio.Force``."""
    import pinocchio as pin

    f = np.asarray(body_wrench, dtype=float)
    return pin.Force(f[3:6].copy(), f[0:3].copy())


class JointMap:
    """Index maps between a uvms model and a Pinocchio free-flyer model of the same robot, joints matched by
    name (for models built by ``pinocchio.buildModelFromUrdf(path, pinocchio.JointModelFreeFlyer())``).

    Pinocchio orders joints its own way and stores a continuous joint as ``(cos q, sin q)`` in its
    configuration; uvms keeps ``q`` in its tree order (``model.joint_names``) with one angle per joint.
    ``perm`` lists, for each uvms velocity index ``[angular; linear; joints]``, the Pinocchio velocity index.
    """

    def __init__(self, model, pin_model) -> None:
        n = model.n_joints
        self.idx_q = np.zeros(n, dtype=int)
        self.nq = np.zeros(n, dtype=int)
        idx_v = np.zeros(n, dtype=int)
        for k, name in enumerate(model.joint_names):
            if not pin_model.existJointName(name):
                raise KeyError(f"the Pinocchio model has no joint {name!r}")
            joint = pin_model.joints[pin_model.getJointId(name)]
            if joint.nv != 1:
                raise ValueError(f"joint {name!r} has {joint.nv} velocity coordinates in Pinocchio, expected 1")
            self.idx_q[k], self.nq[k], idx_v[k] = joint.idx_q, joint.nq, joint.idx_v
        if pin_model.nv != 6 + n:
            raise ValueError(f"the Pinocchio model has nv = {pin_model.nv}, expected 6 + {n}")
        self.nq_total = pin_model.nq
        self.perm = np.concatenate([[3, 4, 5, 0, 1, 2], idx_v])

    def configuration(self, state) -> np.ndarray:
        """Pinocchio ``q``: ``[x, y, z, qx, qy, qz, qw]`` then each joint (``cos, sin`` for continuous)."""
        x = np.zeros(self.nq_total)
        w, qx, qy, qz = state.quaternion
        x[:7] = np.concatenate([state.position, [qx, qy, qz, w]])
        for k, value in enumerate(np.asarray(state.q, dtype=float)):
            if self.nq[k] == 2:
                x[self.idx_q[k]], x[self.idx_q[k] + 1] = np.cos(value), np.sin(value)
            else:
                x[self.idx_q[k]] = value
        return x

    def to_pinocchio(self, generalized) -> np.ndarray:
        """A uvms ``[angular; linear; joints]`` vector in Pinocchio's velocity order."""
        out = np.zeros(self.perm.size)
        out[self.perm] = np.asarray(generalized, dtype=float)
        return out

    def velocity(self, state) -> np.ndarray:
        """Pinocchio ``v`` (``[v; omega]`` local frame, then the joint rates in Pinocchio's order)."""
        return self.to_pinocchio(state.generalized_velocity)

    def from_pinocchio(self, x) -> np.ndarray:
        """A Pinocchio velocity-space vector (``v``, ``ddq``, ``tau``) in uvms order."""
        return np.asarray(x, dtype=float)[self.perm]

    def matrix_from_pinocchio(self, M) -> np.ndarray:
        """An ``nv x nv`` Pinocchio matrix (e.g. ``crba``) in uvms order."""
        return np.asarray(M, dtype=float)[np.ix_(self.perm, self.perm)]
