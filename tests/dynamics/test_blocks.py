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
    from uvms.dynamics import jit

    assert jit.OPTIONS["_nrt"] is False
    assert "fastmath" not in jit.OPTIONS
    out = np.zeros(6)
    blocks.transform_motion(np.eye(3), np.zeros(3), np.array([np.nan, 0, 0, 0, 0, 0]), out)
    assert np.isnan(out[0])
