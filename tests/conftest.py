"""Shared test fixtures: random chains (random DH rows, inertias, hydrodynamics) built directly as Models."""

from __future__ import annotations

import os

import numpy as np
import pytest

from uvms.model.model import Model
from uvms.rotations import rotation_from_euler
from uvms.spatial import modified_dh_pose


MAX_AUTO_WORKERS = 4
"""Most test processes ``-n auto`` starts (pyproject.toml's ``addopts``): each one imports the whole stack and
loads the compiled kernels it uses, and the longest test files bound the wall time anyway, so a machine of many
cores gains nothing from more (``-n N`` or ``PYTEST_XDIST_AUTO_NUM_WORKERS`` chooses another number)."""


@pytest.hookimpl(optionalhook=True, tryfirst=True)
def pytest_xdist_auto_num_workers(config):
    """``-n auto``: one test process per core this process may run on, at most :data:`MAX_AUTO_WORKERS`."""
    if os.environ.get("PYTEST_XDIST_AUTO_NUM_WORKERS"):
        return None                      # pytest-xdist's own hook reads it
    return max(1, min(len(os.sched_getaffinity(0)), MAX_AUTO_WORKERS))


def random_inertia(rng: np.random.Generator, mass: float, size: float) -> np.ndarray:
    """A physically valid rotational inertia (about the CoM) of a random box, randomly rotated."""
    dims = rng.uniform(0.2, 1.0, 3) * size
    Ixx = mass / 12 * (dims[1] ** 2 + dims[2] ** 2)
    Iyy = mass / 12 * (dims[0] ** 2 + dims[2] ** 2)
    Izz = mass / 12 * (dims[0] ** 2 + dims[1] ** 2)
    R = rotation_from_euler(rng.uniform(-np.pi, np.pi, 3))
    return R @ np.diag([Ixx, Iyy, Izz]) @ R.T


def random_spd6(rng: np.random.Generator, scale_ang: float, scale_lin: float) -> np.ndarray:
    A = rng.normal(size=(6, 6))
    D = np.diag([scale_ang] * 3 + [scale_lin] * 3) ** 0.5
    return D @ (A @ A.T / 6 + 0.1 * np.eye(6)) @ D


def random_model(rng: np.random.Generator, n: int, *, hydro: bool = True, gravity: bool = True,
                 current=None) -> Model:
    """A random vehicle with an n-link chain of random modified-DH rows and random inertias."""
    nb = n + 1
    mass = np.concatenate([[rng.uniform(20, 60)], rng.uniform(0.3, 3.0, n)])
    com = np.vstack([rng.normal(scale=0.03, size=3), rng.normal(scale=0.1, size=(n, 3))])
    inertia = np.stack([random_inertia(rng, mass[0], 0.8)] + [random_inertia(rng, m, 0.3) for m in mass[1:]])
    added = np.stack([random_spd6(rng, 2.0, 20.0)] + [random_spd6(rng, 0.002, 0.1) for _ in range(n)])
    joint_R = np.zeros((n, 3, 3))
    joint_p = np.zeros((n, 3))
    for i in range(n):
        R, p = modified_dh_pose(rng.uniform(-np.pi, np.pi), rng.uniform(-0.3, 0.3), rng.uniform(-0.2, 0.2), 0.0)
        joint_R[i], joint_p[i] = R, p
    ee_R, ee_p = modified_dh_pose(rng.uniform(-1, 1), rng.uniform(0, 0.3), rng.uniform(-0.1, 0.1), 0.0)
    h = 1.0 if hydro else 0.0
    return Model(
        name=f"random{n}", source=None, body_names=tuple(f"b{i}" for i in range(nb)),
        mass=mass, com=com, inertia_com=inertia, added_mass=added * h,
        buoyancy_mass=mass * rng.uniform(0.8, 1.2, nb) * h, cob=com + rng.normal(scale=0.05, size=(nb, 3)),
        vehicle_drag_area=rng.uniform(0.05, 0.3, 3), vehicle_drag_coefficient=rng.uniform(0.5, 1.5, 3) * h,
        vehicle_rotational_drag_side=rng.uniform(0.3, 0.8), vehicle_rotational_drag_coefficient=1.0 * h,
        vehicle_box=np.array([0.6, 0.6, 0.6]), link_radius=rng.uniform(0.01, 0.05, n),
        link_length=rng.uniform(0.05, 0.4, n), link_drag_coefficient=rng.uniform(0.5, 1.5, n) * h,
        joint_rotation=joint_R, joint_position=joint_p, theta_offset=rng.uniform(-1, 1, n),
        ee_rotation=ee_R, ee_position=ee_p, density=1000.0,
        gravity=np.array([0.0, 0.0, 9.81]) if gravity else np.zeros(3),
        current=np.zeros(3) if current is None else np.asarray(current, dtype=float),
        fluid_acceleration=np.zeros(3),
    )


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261121)
