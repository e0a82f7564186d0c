"""The structured spatial transforms of :mod:`uvms.dynamics.blocks` against the dense Plucker matrices of
:mod:`uvms.spatial` (Featherstone Eq. 2.24), and the compile options of every kernel."""

from __future__ import annotations

import numpy as np

from uvms import spatial
from uvms.dynamics import blocks
from uvms.rotations import rotation_from_euler


def test_transform_motion_is_the_plucker_product(rng):
    for _ in range(50):
        E = rotation_from_euler(rng.uniform(-3, 3, 3))
        r, m = rng.normal(size=3), rng.normal(size=6)
        out = np.full(6, np.nan)
        blocks.transform_motion(E, r, m, out)
        np.testing.assert_allclose(out, spatial.plucker(E, r) @ m, rtol=0, atol=1e-13)


def test_transform_force_add_is_the_transposed_plucker_product(rng):
    for _ in range(50):
        E = rotation_from_euler(rng.uniform(-3, 3, 3))
        r, f, out = rng.normal(size=3), rng.normal(size=6), rng.normal(size=6)
        expected = out + spatial.plucker(E, r).T @ f
        blocks.transform_force_add(E, r, f, out)
        np.testing.assert_allclose(out, expected, rtol=0, atol=1e-13)
        # power is invariant: (X m) . f == m . (X^T f)
        m = rng.normal(size=6)
        Xm, XTf = np.zeros(6), np.zeros(6)
        blocks.transform_motion(E, r, m, Xm)
        blocks.transform_force_add(E, r, f, XTf)
        assert abs(Xm @ f - m @ XTf) < 1e-12


def test_kernels_count_no_references_and_keep_nan():
    """The kernels are compiled without reference counting (no allocation inside) and without fastmath (a NaN
    input must reach the caller's finiteness check)."""
    from uvms import jit

    assert jit.OPTIONS["_nrt"] is False
    assert "fastmath" not in jit.OPTIONS
    out = np.zeros(6)
    blocks.transform_motion(np.eye(3), np.zeros(3), np.array([np.nan, 0, 0, 0, 0, 0]), out)
    assert np.isnan(out[0])


def test_cholesky_factor_and_solve_against_numpy(rng):
    """``cholesky_factor`` is numpy's lower Cholesky factor and ``cholesky_solve`` solves ``A x = b`` (LAPACK's
    answer, an independent implementation), for sizes 1 to 9; ``cholesky_solve6`` is the two together."""
    for k in range(1, 10):
        B = rng.normal(size=(k, k))
        A = B @ B.T + k * np.eye(k)
        b = rng.normal(size=k)
        L, x = np.full((k, k), np.nan), np.full(k, np.nan)
        blocks.cholesky_factor(A, L)
        np.testing.assert_allclose(np.tril(L), np.linalg.cholesky(A), rtol=0, atol=1e-12 * np.abs(A).max())
        blocks.cholesky_solve(L, b, x)
        np.testing.assert_allclose(x, np.linalg.solve(A, b), rtol=1e-12, atol=1e-12)
        x2 = b.copy()
        blocks.cholesky_solve(L, x2, x2)                       # in place
        np.testing.assert_array_equal(x2, x)
    A6 = rng.normal(size=(6, 6))
    A6 = A6 @ A6.T + np.eye(6)
    b6, x6 = rng.normal(size=6), np.zeros(6)
    blocks.cholesky_solve6(A6, b6, np.zeros((6, 6)), x6)
    np.testing.assert_allclose(A6 @ x6, b6, rtol=0, atol=1e-12)


def test_cholesky_of_a_matrix_that_is_not_positive_definite_gives_nan():
    L, x = np.zeros((2, 2)), np.zeros(2)
    blocks.cholesky_factor(np.array([[1.0, 2.0], [2.0, 1.0]]), L)        # eigenvalues 3 and -1
    blocks.cholesky_solve(L, np.ones(2), x)
    assert np.isnan(x).all()
