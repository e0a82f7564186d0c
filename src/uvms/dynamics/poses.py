"""World poses of a model's bodies, named frames and end effector at a state (the model-level face of
:func:`uvms.kinematics.link_poses`, which walks the tree on the model's compiled arrays,
:func:`uvms.dynamics.plant.kernel_model`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from uvms import checks
from uvms.dynamics.plant import kernel_model
from uvms.kinematics import link_poses


@dataclass(frozen=True)
class Poses:
    """World poses: ``rotation[i]`` (body to world) and ``position[i]`` for bodies 0..n, then the end effector."""

    rotation: np.ndarray    # (n + 2, 3, 3)
    position: np.ndarray    # (n + 2, 3) [m]

    @property
    def end_effector_position(self) -> np.ndarray:
        return self.position[-1]

    @property
    def end_effector_rotation(self) -> np.ndarray:
        return self.rotation[-1]


def forward_kinematics(model, state) -> Poses:
    """World pose of the vehicle, every link frame and the end effector."""
    checks.state(model, state)
    nb = model.n_bodies
    R = np.zeros((nb + 1, 3, 3))
    p = np.zeros((nb + 1, 3))
    link_poses(kernel_model(model), state.rotation, np.array(state.position, dtype=float),
               np.array(state.q, dtype=float), R, p, np.zeros((3, 3)), np.zeros(3))
    return Poses(rotation=R, position=p)


def end_effector_position(model, state) -> np.ndarray:
    """End-effector position in the world frame (3,) [m]."""
    return forward_kinematics(model, state).end_effector_position


class FramePose(NamedTuple):
    """World pose of a named frame: ``position`` (3,) [m] and ``rotation`` (3, 3), frame to world."""

    position: np.ndarray
    rotation: np.ndarray


def frame_pose(model, state, name: str) -> FramePose:
    """World position and rotation of the named frame (a link, a link merged by a fixed joint, or
    ``"end_effector"``; ``model.frame_names`` lists them): ``R = R_b R_f``, ``p = p_b + R_b p_f`` for a frame
    with pose ``(R_f, p_f)`` in body ``b``.

    Raises:
        UvmsInputError: no frame of that name (the message lists the names).
    """
    from uvms.errors import UvmsInputError

    try:
        frame = model.frame(name)
    except KeyError as exc:
        raise UvmsInputError(str(exc.args[0])) from None
    poses = forward_kinematics(model, state)
    R_b, p_b = poses.rotation[frame.body], poses.position[frame.body]
    return FramePose(position=p_b + R_b @ frame.position, rotation=R_b @ frame.rotation)


def frame_poses(model, state) -> dict[str, FramePose]:
    """World pose of every named frame, by name (one forward-kinematics pass)."""
    poses = forward_kinematics(model, state)
    return {f.name: FramePose(poses.position[f.body] + poses.rotation[f.body] @ f.position,
                              poses.rotation[f.body] @ f.rotation) for f in model.frames}
