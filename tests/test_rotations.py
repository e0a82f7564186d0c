"""Issue 17: ZYX Euler angles at and near +/-90 deg of pitch (gimbal lock).

Only ``psi -/+ phi`` is defined at ``theta = +/-pi/2``; the convention (``docs/conventions.md``) is roll = 0 and
the whole rotation about z in yaw. Every conversion must return angles that rebuild the same rotation matrix:
``R(euler(R)) == R`` to 1e-12, for random, exactly singular and nearly singular rotations, in the scalar and
the vectorised form. The reference rotation is always built independently, as the product of the three
elementary rotations (paper Eq. 1's ``T1``).
"""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.rotations import (
    GIMBAL_LOCK_COS,
    euler_from_quaternion,
    euler_from_rotation,
    euler_from_rotations,
    quaternion_from_euler,
    rotation_from_euler,
    rotation_from_quaternion,
    rotations_from_quaternions,
)
from uvms.spatial import rotx, roty, rotz


def _R(phi, theta, psi):
    return rotz(psi) @ roty(theta) @ rotx(phi)


def _rotations(rng, count=400):
    """Random rotations, exactly singular ones (theta = +/-pi/2 in floating point), and nearly singular ones
    (theta = +/-(pi/2 - delta), delta from 1e-16 to 1e-3), each built from Euler angles or from a quaternion."""
    out = []
    for k in range(count):
        e = rng.uniform(-np.pi, np.pi, 3)
        kind = k % 3
        if kind == 1:
            e[1] = rng.choice([-1.0, 1.0]) * np.pi / 2
        elif kind == 2:
            e[1] = rng.choice([-1.0, 1.0]) * (np.pi / 2 - 10.0 ** rng.uniform(-16, -3))
        out.append(_R(*e) if k % 2 else rotation_from_quaternion(quaternion_from_euler(e)))
    for delta in (0.0, 1e-15, 1e-13, 1e-12, 1e-9, 1e-6):
        for sign in (-1.0, 1.0):
            out.append(_R(0.3, sign * (np.pi / 2 - delta), 0.2))
    return np.array(out)


def test_angles_rebuild_the_rotation_everywhere_including_gimbal_lock():
    R = _rotations(np.random.default_rng(17))
    E = euler_from_rotations(R)
    for k in range(len(R)):
        e = euler_from_rotation(R[k])
        np.testing.assert_allclose(_R(*e), R[k], rtol=0, atol=1e-12)
        np.testing.assert_allclose(E[k], e, rtol=0, atol=1e-15)       # one formula, two forms
        assert -np.pi / 2 <= e[1] <= np.pi / 2 and -np.pi <= e[0] <= np.pi and -np.pi <= e[2] <= np.pi


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_at_exactly_90_degrees_roll_is_zero_and_yaw_holds_the_rotation_about_z(sign):
    """``Rz(psi) Ry(+pi/2) Rx(phi) = Rz(psi - phi) Ry(pi/2)`` and ``Rz(psi) Ry(-pi/2) Rx(phi) = Rz(psi + phi)
    Ry(-pi/2)``: with roll 0, yaw is ``psi - phi`` (pitch up) or ``psi + phi`` (pitch down)."""
    phi, psi = 0.3, 0.2
    e0 = [phi, sign * np.pi / 2, psi]
    for R in (_R(*e0), rotation_from_quaternion(quaternion_from_euler(e0))):
        e = euler_from_rotation(R)
        np.testing.assert_allclose(e, [0.0, sign * np.pi / 2, psi - sign * phi], rtol=0, atol=1e-12)
        assert e[0] == 0.0


def test_the_issue_example_state_reports_the_same_orientation(tmp_path):
    """``State.from_euler(m, euler=[0.3, pi/2, 0.2]).euler`` was ``(pi/2, pi/2, pi/2)``: another orientation."""
    model = uvms.load_model("paper")
    s = uvms.State.from_euler(model, euler=[0.3, np.pi / 2, 0.2])
    np.testing.assert_allclose(s.euler, [0.0, np.pi / 2, -0.1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(_R(*s.euler), s.rotation, rtol=0, atol=1e-12)
    np.testing.assert_allclose(_R(*s.euler), _R(0.3, np.pi / 2, 0.2), rtol=0, atol=1e-12)


def test_near_singular_pitch_keeps_roll_and_yaw_to_round_off():
    """At pitch pi/2 - 1e-9 the angles are still defined; roll and yaw come back to ~1e-16 / cos(theta)."""
    e0 = np.array([0.3, np.pi / 2 - 1e-9, 0.2])
    e = euler_from_quaternion(quaternion_from_euler(e0))
    np.testing.assert_allclose(e, e0, rtol=0, atol=1e-6)
    np.testing.assert_allclose(_R(*e), _R(*e0), rtol=0, atol=1e-12)


def test_recorded_runs_report_no_spurious_roll_or_yaw_at_gimbal_lock():
    """A run's rows at exactly 90 deg of pitch: roll 0 and yaw the rotation about z, not round-off angles."""
    e0 = [0.0, np.pi / 2, 0.0]
    q = np.array([quaternion_from_euler(e0)] * 5)
    E = euler_from_rotations(rotations_from_quaternions(q))
    np.testing.assert_allclose(E, [e0] * 5, rtol=0, atol=1e-12)


def test_the_threshold_is_below_the_test_tolerance_and_above_round_off():
    """Roll is dropped only when ``cos(theta)`` is below the threshold, which bounds the rebuild error."""
    assert 1e-15 < GIMBAL_LOCK_COS <= 1e-13
    R = _R(1.0, np.pi / 2 - 0.5 * GIMBAL_LOCK_COS, -0.4)
    np.testing.assert_allclose(_R(*euler_from_rotation(R)), R, rtol=0, atol=1e-12)
    assert euler_from_rotation(R)[0] == 0.0
    assert euler_from_rotation(_R(1.0, np.pi / 2 - 4 * GIMBAL_LOCK_COS, -0.4))[0] != 0.0


def test_rotation_from_euler_is_the_product_of_elementary_rotations(rng):
    for _ in range(20):
        e = rng.uniform(-np.pi, np.pi, 3)
        np.testing.assert_allclose(rotation_from_euler(e), _R(*e), rtol=0, atol=1e-15)


@pytest.mark.parametrize("euler", [[0.3, np.pi / 2, 0.2], [0.3, -np.pi / 2, 0.2], [0.3, np.pi / 2 - 1e-9, 0.2],
                                   [-2.0, 0.4, 3.0]])
def test_the_controllers_see_the_euler_angles_the_state_reports(euler):
    """The sliding-mode kernels extract the angles with the same compiled function: at gimbal lock a controller
    holding ``State.euler``'s yaw sees no yaw error (it saw 1.67 rad of round-off yaw with a second formula)."""
    from uvms.control.smc import axis_kinematics

    model = uvms.load_model("paper")
    s = uvms.State.from_euler(model, euler=euler)
    kin = axis_kinematics(s, s.position, float(s.euler[2]))
    np.testing.assert_allclose(kin.euler, s.euler, rtol=0, atol=1e-12)
    assert abs(kin.error[2]) < 1e-12
