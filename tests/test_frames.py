"""The half-turn map between the ``ned`` and ``enu`` conventions (uvms.frames), against rotation matrices built
independently (``R' = H R H``, ``H = Rx(pi)``)."""

import numpy as np
import pytest

from uvms import frames
from uvms.errors import UvmsInputError
from uvms.rotations import euler_from_rotation, quaternion_from_rotation, rotation_from_euler, rotation_from_quaternion
from uvms.spatial import rotx


def test_the_map_is_a_half_turn_about_x_for_points_rotations_and_euler_angles():
    H = rotx(np.pi)
    rng = np.random.default_rng(3)
    for _ in range(20):
        euler = rng.uniform([-3, -1.4, -3], [3, 1.4, 3])
        R = rotation_from_euler(euler)
        R_enu = H @ R @ H.T
        q = quaternion_from_rotation(R)
        q_enu = frames.convert_quaternions(q, "ned", "enu")
        np.testing.assert_allclose(rotation_from_quaternion(q_enu), R_enu, atol=1e-14)
        np.testing.assert_allclose(frames.convert_euler(euler, "ned", "enu"), euler_from_rotation(R_enu), atol=1e-12)
        p = rng.normal(size=3)
        np.testing.assert_allclose(frames.convert_vectors(p, "ned", "enu"), H @ p, atol=1e-15)
        np.testing.assert_allclose(frames.convert_vectors(frames.convert_vectors(p, "ned", "enu"), "enu", "ned"), p)


def test_spatial_matrices_and_twists_transform_together():
    rng = np.random.default_rng(4)
    M = rng.normal(size=(6, 6))
    nu = rng.normal(size=6)
    H6 = np.kron(np.eye(2), rotx(np.pi))
    np.testing.assert_allclose(frames.convert_spatial_matrix(M, "ned", "enu"), H6 @ M @ H6.T, atol=1e-14)
    np.testing.assert_allclose(frames.convert_twists(nu, "enu", "ned"), H6 @ nu, atol=1e-15)
    np.testing.assert_allclose(frames.convert_twists(nu, "ned", "ned"), nu)


def test_ros_quaternion_order_and_gravity_direction():
    np.testing.assert_array_equal(frames.quaternion_wxyz([0.1, 0.2, 0.3, 0.9]), [0.9, 0.1, 0.2, 0.3])
    np.testing.assert_array_equal(frames.GRAVITY_DIRECTION["enu"], -frames.UP["enu"])
    np.testing.assert_array_equal(frames.convert_vectors(frames.UP["ned"], "ned", "enu"), frames.UP["enu"])


def test_an_unknown_frame_is_one_line():
    with pytest.raises(UvmsInputError, match="expected one of ned, enu"):
        frames.check_frame("nwu")
