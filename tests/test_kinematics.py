"""Forward kinematics of the paper's arm against hand-computed poses (issue 2 acceptance)."""

from __future__ import annotations

import numpy as np
import pytest

import uvms


@pytest.fixture(scope="module")
def paper():
    return uvms.load_model("paper")


@pytest.mark.parametrize("q, expected", [
    ([0.0, 0.0, 0.0], [0.66, 0.0, 0.0]),                        # stretched along the vehicle's x axis
    ([np.pi / 2, 0.0, 0.0], [0.0, 0.66, 0.0]),                  # joint 1 (about z) swings it to +y
    ([0.0, np.pi / 2, 0.0], [0.22, 0.0, -0.44]),                # Rx(-pi/2) Rz(pi/2): links 2-3 point up (-z)
    ([0.0, np.pi / 2, -np.pi / 2], [0.44, 0.0, -0.22]),         # link 3 back to +x, one link up
])
def test_end_effector_hand_computed(paper, q, expected):
    s = uvms.State.from_euler(paper, q=q)
    np.testing.assert_allclose(uvms.end_effector_position(paper, s), expected, atol=1e-12)


def test_end_effector_follows_the_vehicle_pose(paper):
    s = uvms.State.from_euler(paper, position=[1.0, 2.0, 3.0], euler=[0.0, 0.0, np.pi / 2])
    np.testing.assert_allclose(uvms.end_effector_position(paper, s), [1.0, 2.66, 3.0], atol=1e-12)
    s = uvms.State.from_euler(paper, euler=[0.0, np.pi / 2, 0.0])        # pitch +90 deg: nose up, x axis to -z
    np.testing.assert_allclose(uvms.end_effector_position(paper, s), [0.0, 0.0, -0.66], atol=1e-12)


def test_link_frames(paper):
    poses = uvms.forward_kinematics(paper, uvms.State.from_euler(paper, q=[0.3, 0.0, 0.0]))
    np.testing.assert_allclose(poses.position[2], [0.22 * np.cos(0.3), 0.22 * np.sin(0.3), 0.0], atol=1e-12)
    for R in poses.rotation:
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
