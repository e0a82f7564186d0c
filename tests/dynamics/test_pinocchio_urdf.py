"""URDF robot descriptions that nobody here wrote (the ``example-robot-data`` package) against Pinocchio's own
URDF parser: forward dynamics, inverse dynamics, the mass matrix and every frame placement, free-flying base,
hydrodynamics off (a bare URDF has none) and joint friction off (Pinocchio's algorithms have none).

Pinocchio reads the same files with ``buildModelFromUrdf(path, JointModelFreeFlyer())``; the conventions that
differ (quaternion order, ``[linear; angular]``, ``(cos, sin)`` for continuous joints, joint order) are
converted by :class:`uvms.interop.pinocchio_model.JointMap`, joints matched by name.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import uvms
from uvms.interop.pinocchio_model import JointMap
from uvms.model.model import END_EFFECTOR

pin = pytest.importorskip("pinocchio")

N_STATES = 100
TOLERANCE = 1e-9


def robots_dir() -> Path:
    """The ``robots`` folder of example-robot-data (installed by cmeel next to pinocchio)."""
    for base in [Path(pin.__file__).parents[i] for i in range(2, 6)]:
        candidate = base / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
        if candidate.is_dir():
            return candidate
        candidate = base / "share" / "example-robot-data" / "robots"
        if candidate.is_dir():
            return candidate
    pytest.skip("example-robot-data is not installed")


# name: (file, joints frozen through the YAML additions, what it covers)
ROBOTS = {
    "ur5": ("ur_description/urdf/ur5_robot.urdf", (), "arm with fixed joints (world, base, tool frames)"),
    "kinova": ("kinova_description/robots/kinova.urdf", (), "continuous and revolute joints, fixed joints"),
    "panda": ("panda_description/urdf/panda.urdf", ("panda_finger_joint2",), "prismatic finger joint; the "
              "mimic finger frozen (and locked in Pinocchio's reduced model)"),
    "centauro": ("centauro_description/urdf/centauro.urdf", (), "branching tree: a wheeled mobile manipulator "
                 "(four legs, two arms, 39 joints)"),
    "z1": ("z1_description/urdf/z1.urdf", (), "arm with off-axis revolute joints"),
    "double_pendulum_continuous": ("double_pendulum_description/urdf/double_pendulum_continuous.urdf", (),
                                   "continuous joints only"),
}


def load(tmp_path: Path, name: str) -> tuple[uvms.Model, object]:
    """The uvms model (through a model YAML naming the URDF when joints are frozen) and Pinocchio's model."""
    file, frozen, _ = ROBOTS[name]
    path = robots_dir() / file
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")           # meshes behind package:// are not needed
        if frozen:
            yaml_path = tmp_path / f"{name}.yaml"
            yaml_path.write_text(f"urdf: {path}\nfixed_joints: [{', '.join(frozen)}]\n")
            model = uvms.load_model(yaml_path)
        else:
            model = uvms.load_model(path)
    model = model.with_effects(joint_friction=False)
    pm = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
    if frozen:
        pm = pin.buildReducedModel(pm, [pm.getJointId(j) for j in frozen], pin.neutral(pm))
    pm.gravity.linear = np.array(model.gravity, dtype=float)
    return model, pm


def random_state(rng, model) -> uvms.State:
    n = model.n_joints
    return uvms.State.from_euler(
        model, position=rng.normal(size=3), euler=rng.uniform([-np.pi, -np.pi / 2, -np.pi], [np.pi, np.pi / 2, np.pi]),
        nu=rng.normal(size=6), q=rng.uniform(-np.pi, np.pi, n), qd=rng.normal(scale=2.0, size=n))


def close(actual, expected, tol: float = TOLERANCE) -> bool:
    """Equal to ``tol`` relative to the norm of ``expected``, or absolutely where that norm is below 1."""
    return bool(np.linalg.norm(actual - expected) <= tol * max(1.0, np.linalg.norm(expected)))


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_urdf_dynamics_and_frames_match_pinocchio(tmp_path, name):
    model, pm = load(tmp_path, name)
    pd = pm.createData()
    jm = JointMap(model, pm)
    rng = np.random.default_rng(sum(map(ord, name)))
    frames = [f for f in model.frame_names if f != END_EFFECTOR]
    frame_ids = {f: pm.getFrameId(f, pin.FrameType.BODY) for f in frames}
    assert all(i < pm.nframes for i in frame_ids.values())
    for _ in range(N_STATES):
        state = random_state(rng, model)
        q, v = jm.configuration(state), jm.velocity(state)
        tau = rng.normal(scale=2.0, size=model.n_joints)
        wrench = rng.normal(size=6) * 5.0
        # forward dynamics (a body wrench on the vehicle and joint torques)
        acc = uvms.forward_dynamics(model, state, joint_torques=tau, body_wrench=wrench)
        fext = pin.StdVec_Force()
        for _ in range(pm.njoints):
            fext.append(pin.Force.Zero())
        fext[1] = pin.Force(wrench[3:6].copy(), wrench[0:3].copy())
        ddq = pin.aba(pm, pd, q, v, jm.to_pinocchio(np.concatenate([np.zeros(6), tau])), fext)
        assert close(acc.generalized, jm.from_pinocchio(ddq)), name
        # inverse dynamics
        a = rng.normal(size=model.n_dof)
        f0, tau_id = uvms.inverse_dynamics(model, state, nu_dot=a[:6], qdd=a[6:])
        expected = jm.from_pinocchio(pin.rnea(pm, pd, q, v, jm.to_pinocchio(a)))
        assert close(np.concatenate([f0, tau_id]), expected), name
        # mass matrix (Pinocchio fills the upper triangle)
        M = pin.crba(pm, pd, q)
        M = np.triu(M) + np.triu(M, 1).T
        assert close(uvms.mass_matrix(model, state), jm.matrix_from_pinocchio(M)), name
        # every frame: links, links merged by fixed joints, the vehicle (root link)
        pin.framesForwardKinematics(pm, pd, q)
        poses = uvms.frame_poses(model, state)
        for f in frames:
            oMf = pd.oMf[frame_ids[f]]
            assert np.abs(poses[f].position - oMf.translation).max() <= TOLERANCE, (name, f)
            assert np.abs(poses[f].rotation - oMf.rotation).max() <= TOLERANCE, (name, f)
