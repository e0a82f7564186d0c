"""Spatial (6D) vector algebra, Featherstone's notation.

Vector order, once for the whole package: motion vectors are ``[angular; linear]`` = ``[omega; v]``, force
vectors are ``[moment; force]`` = ``[n; f]`` (Featherstone, *Rigid Body Dynamics Algorithms*, 2008, ch. 2;
the paper and McMillan et al. use the same order). Fossen's linear-first order is converted only in
:func:`to_linear_first` / :func:`from_linear_first`.

A Plucker transform ``X = xlt(r) rot(E)`` maps motion vectors from frame A to frame B, where ``E`` rotates
A coordinates into B coordinates and ``r`` is B's origin expressed in A coordinates:
``X = [[E, 0], [-E skew(r), E]]``. Forces transform with ``X* = X^-T``, and ``X^T`` maps B forces to A.

These are the plain NumPy helpers for set-up, tests and inspection; the compiled kernels in
:mod:`uvms.dynamics` use scalar-loop versions of the same operations.
"""

from __future__ import annotations

import numpy as np


def skew(v: np.ndarray) -> np.ndarray:
    """3x3 cross-product matrix: ``skew(a) @ b == cross(a, b)``."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def crm(v: np.ndarray) -> np.ndarray:
    """6x6 motion cross product ``v x`` (Featherstone Eq. 2.31)."""
    w, u = skew(v[:3]), skew(v[3:])
    return np.block([[w, np.zeros((3, 3))], [u, w]])


def crf(v: np.ndarray) -> np.ndarray:
    """6x6 force cross product ``v x* = -(v x)^T`` (Featherstone Eq. 2.32)."""
    return -crm(v).T


def rotx(angle: float) -> np.ndarray:
    """3x3 rotation about x by ``angle`` (active: maps child-frame vectors into the parent frame)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def roty(angle: float) -> np.ndarray:
    """3x3 rotation about y by ``angle``."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rotz(angle: float) -> np.ndarray:
    """3x3 rotation about z by ``angle``."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def plucker(E: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Plucker motion transform ``[[E, 0], [-E skew(r), E]]`` (Featherstone Eq. 2.24)."""
    X = np.zeros((6, 6))
    X[:3, :3] = E
    X[3:, 3:] = E
    X[3:, :3] = -E @ skew(r)
    return X


def plucker_from_pose(R: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Motion transform from parent to child coordinates, given the child's pose in the parent.

    ``R`` is the child's orientation (child-to-parent rotation), ``p`` the child's origin, both in parent axes.
    """
    return plucker(R.T, p)


def force_transform(X: np.ndarray) -> np.ndarray:
    """The force transform ``X* = X^-T`` of a motion transform ``X``."""
    E = X[:3, :3]
    Xf = X.copy()
    Xf[:3, 3:] = X[3:, :3]
    Xf[3:, :3] = 0.0
    Xf[:3, :3] = E
    return Xf


def spatial_inertia(mass: float, com: np.ndarray, inertia_com: np.ndarray) -> np.ndarray:
    """6x6 rigid-body inertia about the frame origin (Featherstone Eq. 2.63, ``mcI``).

    ``inertia_com`` is the rotational inertia about the centre of mass ``com``.
    """
    C = skew(com)
    return np.block([[inertia_com + mass * C @ C.T, mass * C], [mass * C.T, mass * np.eye(3)]])


def inertia_about_com(mass: float, com: np.ndarray, inertia_origin: np.ndarray) -> np.ndarray:
    """Rotational inertia about the centre of mass from the one about the frame origin (parallel axis)."""
    C = skew(com)
    return inertia_origin - mass * C @ C.T


def shift_spatial_inertia(I_at_point: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Express a 6x6 inertia given about ``point`` (frame axes) about the frame origin.

    ``I_origin = X^T I_point X`` with ``X`` the pure translation from the origin to ``point``.
    """
    X = plucker(np.eye(3), point)
    return X.T @ I_at_point @ X


def modified_dh_pose(alpha_prev: float, a_prev: float, d: float, theta: float) -> tuple[np.ndarray, np.ndarray]:
    """Pose of frame i in frame i-1 for modified DH (Craig): ``RotX(alpha) TransX(a) RotZ(theta) TransZ(d)``.

    Returns ``(R, p)``: orientation (child-to-parent) and origin of frame i, in frame i-1 axes.
    """
    R = rotx(alpha_prev) @ rotz(theta)
    p = np.array([a_prev, 0.0, 0.0]) + rotx(alpha_prev) @ np.array([0.0, 0.0, d])
    return R, p


def homogeneous(R: np.ndarray, p: np.ndarray) -> np.ndarray:
    """4x4 homogeneous transform from a rotation and a translation."""
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


def to_linear_first(x: np.ndarray) -> np.ndarray:
    """Convert a ``[angular; linear]`` 6-vector (or 6xK array) to Fossen's ``[linear; angular]``."""
    x = np.asarray(x)
    return np.concatenate([x[3:6], x[0:3]], axis=0)


def from_linear_first(x: np.ndarray) -> np.ndarray:
    """Convert Fossen's ``[linear; angular]`` 6-vector to ``[angular; linear]``."""
    x = np.asarray(x)
    return np.concatenate([x[3:6], x[0:3]], axis=0)
