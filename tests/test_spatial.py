"""Identities of the spatial-algebra helpers and the compiled blocks that mirror them."""

from __future__ import annotations

import numpy as np

from uvms import spatial
from uvms.dynamics import blocks
from uvms.rotations import (euler_from_quaternion, euler_from_rotation, quaternion_from_euler,
                            quaternion_from_rotation, quaternion_rate, rotation_from_euler, rotation_from_quaternion)


def test_cross_products(rng):
    for _ in range(50):
        v, m, f = rng.normal(size=(3, 6))
        np.testing.assert_allclose(spatial.crf(v), -spatial.crm(v).T)
        np.testing.assert_allclose(spatial.skew(v[:3]) @ m[:3], np.cross(v[:3], m[:3]))
        out = np.zeros(6)
        blocks.crm_mul(v, m, out)
        np.testing.assert_allclose(out, spatial.crm(v) @ m, atol=1e-14)
        out = np.zeros(6)
        blocks.crf_mul_add(v, f, 2.0, out)
        np.testing.assert_allclose(out, 2.0 * spatial.crf(v) @ f, atol=1e-14)
        # power: (v x* f) . v == 0 ... and m . (v x* f) == -(v x m) . f
        assert abs(m @ (spatial.crf(v) @ f) + (spatial.crm(v) @ m) @ f) < 1e-12


def test_plucker_transform(rng):
    for _ in range(20):
        E = rotation_from_euler(rng.uniform(-3, 3, 3))
        r = rng.normal(size=3)
        X = np.zeros((6, 6))
        blocks.plucker(E, r, X)
        np.testing.assert_allclose(X, spatial.plucker(E, r), atol=1e-14)
        # a point's velocity: v_B(origin B) = E (v_A + omega x r)
        v = rng.normal(size=6)
        np.testing.assert_allclose((X @ v)[3:], E @ (v[3:] + np.cross(v[:3], r)), atol=1e-12)
        np.testing.assert_allclose(spatial.force_transform(X), np.linalg.inv(X).T, atol=1e-12)


def test_spatial_inertia_kinetic_energy(rng):
    """0.5 v^T I v equals the rigid body's kinetic energy computed at its centre of mass."""
    m = 2.5
    c = rng.normal(size=3)
    Ic = np.diag([0.3, 0.4, 0.5])
    I = spatial.spatial_inertia(m, c, Ic)
    w, v0 = rng.normal(size=(2, 3))
    vc = v0 + np.cross(w, c)
    T = 0.5 * m * vc @ vc + 0.5 * w @ Ic @ w
    assert abs(0.5 * np.concatenate([w, v0]) @ I @ np.concatenate([w, v0]) - T) < 1e-12
    np.testing.assert_allclose(spatial.inertia_about_com(m, c, I[:3, :3]), Ic, atol=1e-12)


def test_modified_dh_matches_the_product_of_elementary_transforms(rng):
    for _ in range(20):
        alpha, a, d, theta = rng.normal(size=4)
        R, p = spatial.modified_dh_pose(alpha, a, d, theta)
        T = (spatial.homogeneous(spatial.rotx(alpha), np.zeros(3)) @ spatial.homogeneous(np.eye(3), [a, 0, 0])
             @ spatial.homogeneous(spatial.rotz(theta), np.zeros(3)) @ spatial.homogeneous(np.eye(3), [0, 0, d]))
        np.testing.assert_allclose(T[:3, :3], R, atol=1e-14)
        np.testing.assert_allclose(T[:3, 3], p, atol=1e-14)


def test_euler_rotation_quaternion_round_trips(rng):
    for _ in range(100):
        e = rng.uniform(-np.pi, np.pi, 3) * [1, 0.49, 1]
        R = rotation_from_euler(e)
        np.testing.assert_allclose(euler_from_rotation(R), e, atol=1e-12)
        qt = quaternion_from_euler(e)
        np.testing.assert_allclose(rotation_from_quaternion(qt), R, atol=1e-12)
        np.testing.assert_allclose(euler_from_quaternion(qt), e, atol=1e-12)
        np.testing.assert_allclose(rotation_from_quaternion(quaternion_from_rotation(R)), R, atol=1e-12)
    # the paper's T1 (Eq. 1), written out
    phi, theta, psi = 0.3, -0.4, 1.1
    s, c = np.sin, np.cos
    T1 = np.array([
        [c(psi) * c(theta), -s(psi) * c(phi) + c(psi) * s(theta) * s(phi), s(psi) * s(phi) + c(psi) * s(theta) * c(phi)],
        [s(psi) * c(theta), c(psi) * c(phi) + s(psi) * s(theta) * s(phi), -c(psi) * s(phi) + s(psi) * s(theta) * c(phi)],
        [-s(theta), c(theta) * s(phi), c(theta) * c(phi)]])
    np.testing.assert_allclose(rotation_from_euler([phi, theta, psi]), T1, atol=1e-14)


def test_quaternion_rate_matches_rotation_rate(rng):
    """d/dt R(q) == R skew(omega) for body-frame omega."""
    q = quaternion_from_euler(rng.uniform(-1, 1, 3))
    w = rng.normal(size=3)
    h = 1e-6
    dR = (rotation_from_quaternion(q + h * quaternion_rate(q, w)) - rotation_from_quaternion(q - h * quaternion_rate(q, w))) / (2 * h)
    np.testing.assert_allclose(dR, rotation_from_quaternion(q) @ spatial.skew(w), atol=1e-8)


def test_structured_congruence_equals_dense(rng):
    """The articulated-inertia hand-over X^T I X by the transform's structure equals the dense product."""
    for _ in range(50):
        E = rotation_from_euler(rng.uniform(-3, 3, 3))
        r = rng.normal(size=3)
        A = rng.normal(size=(6, 6))
        I = A @ A.T
        out = rng.normal(size=(6, 6))
        expected = out + spatial.plucker(E, r).T @ I @ spatial.plucker(E, r)
        blocks.congruence_add_plucker(E, r, I, out, np.zeros((6, 6)))
        np.testing.assert_allclose(out, expected, atol=1e-12)


def test_vectorised_rotations_and_euler_match_the_single_sample_forms():
    """``rotations_from_quaternions``/``euler_from_rotations`` (whole runs) against the per-sample functions,
    on random unnormalised quaternions including pitch near +/-90 deg."""
    from uvms.rotations import (
        euler_from_rotation,
        euler_from_rotations,
        quaternion_from_euler,
        rotation_from_quaternion,
        rotations_from_quaternions,
    )

    rng = np.random.default_rng(11)
    q = rng.normal(size=(200, 4)) * rng.uniform(0.5, 2.0, size=(200, 1))
    q[:3] = [quaternion_from_euler(np.array([0.3, s * (np.pi / 2 - 1e-9), -1.0])) for s in (-1, 1, 1)]
    R = rotations_from_quaternions(q)
    E = euler_from_rotations(R)
    for k in range(len(q)):
        np.testing.assert_allclose(R[k], rotation_from_quaternion(q[k]), atol=1e-15)
        np.testing.assert_allclose(E[k], euler_from_rotation(R[k]), atol=1e-12)
