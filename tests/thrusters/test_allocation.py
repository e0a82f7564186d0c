"""Thrust allocation and layouts: Eq. 11 columns, exact reproduction, saturation (bounds, residual, optimality),
minimum norm with redundant thrusters, the paper layout's missing sway force."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uvms.errors import UvmsInputError
from uvms.thrusters.allocation import (
    allocate,
    allocate_pinv,
    allocation_matrix,
    unachievable_directions,
    unachievable_part,
)
from uvms.thrusters.layouts import Thruster, layout, layout_matrix, layout_names, thrust_limits


def random_layout(rng, m):
    positions = rng.uniform(-0.3, 0.3, (m, 3))
    directions = rng.normal(size=(m, 3))
    return allocation_matrix(positions, directions)


def test_columns_are_moment_then_force():
    L = allocation_matrix([[0.0, -0.15, 0.0], [0.2, 0.0, 0.1]], [[2.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    np.testing.assert_allclose(L[:, 0], [0, 0, 0.15, 1, 0, 0])  # port surge thruster yaws to starboard
    np.testing.assert_allclose(L[:, 1], [-0.1, 0, 0.2, 0, 1, 0])  # r x e with r = (0.2, 0, 0.1), e = y
    with pytest.raises(ValueError):
        allocation_matrix([[0.0, 0.0, 0.0]], [[0.0, 0.0, 0.0]])


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 8))
def test_reachable_wrench_is_reproduced(seed, m):
    rng = np.random.default_rng(seed)
    L = random_layout(rng, m)
    lower, upper = -rng.uniform(5, 50, m), rng.uniform(5, 50, m)
    wrench = L @ rng.uniform(lower, upper)  # in the column space, produced within the limits
    result = allocate(L, wrench, lower, upper)
    assert np.all(result.thrust >= lower) and np.all(result.thrust <= upper)
    np.testing.assert_allclose(result.achieved, wrench, rtol=0, atol=1e-9 * max(1.0, np.abs(wrench).max()))
    np.testing.assert_allclose(result.unachievable, 0.0, atol=1e-9 * max(1.0, np.abs(wrench).max()))


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 6))
def test_saturated_allocation_is_bounded_and_optimal(seed, m):
    rng = np.random.default_rng(seed)
    L = random_layout(rng, m)  # full column rank: the unbounded least-squares thrust is unique
    lower, upper = -np.full(m, 10.0), np.full(m, 10.0)
    wanted = rng.uniform(-10, 10, m)
    wanted[rng.integers(m)] = rng.choice([-1, 1]) * rng.uniform(20, 100)  # beyond a limit
    wrench = L @ wanted + rng.normal(size=6)  # plus a part outside the column space
    result = allocate(L, wrench, lower, upper)
    T = result.thrust
    assert np.all(T >= lower) and np.all(T <= upper)
    np.testing.assert_allclose(result.achieved, L @ T, atol=1e-12)
    np.testing.assert_allclose(result.residual, wrench - L @ T, atol=1e-12)
    assert result.saturated.any()
    # KKT of the bounded least squares: the gradient vanishes on free thrusters and points outwards at limits
    gradient = L.T @ (L @ T - wrench)
    g_tol = 1e-7 * np.abs(L).sum(axis=0) * np.linalg.norm(wrench)
    free = ~result.saturated
    assert np.all(np.abs(gradient[free]) <= g_tol[free])
    assert np.all(gradient[T <= lower + 1e-9] >= -g_tol[T <= lower + 1e-9])
    assert np.all(gradient[T >= upper - 1e-9] <= g_tol[T >= upper - 1e-9])
    # never worse than the clipped pseudo-inverse
    fast = np.empty(m)
    allocate_pinv(np.linalg.pinv(L), wrench, lower, upper, fast)
    assert np.linalg.norm(result.residual) <= np.linalg.norm(wrench - L @ fast) + 1e-9


def test_redundant_thrusters_get_minimum_norm():
    L = allocation_matrix(np.zeros((3, 3)), np.tile([1.0, 0.0, 0.0], (3, 1)))  # three coincident surge units
    wrench = np.array([0, 0, 0, 30.0, 0, 0])
    np.testing.assert_allclose(allocate(L, wrench, -100, 100).thrust, [10, 10, 10], atol=1e-9)
    result = allocate(L, wrench, [-5, -5, -100], [5, 5, 100])  # pseudo-inverse violates the limits
    np.testing.assert_allclose(result.thrust, [5, 5, 20], atol=1e-6)
    result = allocate(L, 10 * wrench, [-5, -5, -100], [5, 5, 100])
    np.testing.assert_allclose(result.thrust, [5, 5, 100], atol=1e-9)
    np.testing.assert_allclose(result.residual, [0, 0, 0, 190, 0, 0], atol=1e-9)
    assert result.saturated.all()


def test_weights_trade_components():
    thrusters = layout("paper")
    L, (lower, upper) = layout_matrix(thrusters), thrust_limits(thrusters)
    wrench = np.array([0, 0, 20.0, 100.0, 0, 0])  # needs 150 N of differential thrust for N = 20 N m
    yaw_first = allocate(L, wrench, lower, upper, weights=[1, 1, 100, 1, 1, 1])
    surge_first = allocate(L, wrench, lower, upper, weights=[1, 1, 0.01, 1, 1, 1])
    assert abs(yaw_first.residual[2]) < abs(surge_first.residual[2])
    assert abs(surge_first.residual[3]) < abs(yaw_first.residual[3])


def test_fast_path_is_clipped_pseudo_inverse():
    rng = np.random.default_rng(1)
    L = random_layout(rng, 5)
    wrench = rng.normal(size=6) * 50
    lower, upper = -np.full(5, 20.0), np.full(5, 20.0)
    out = np.empty(5)
    allocate_pinv(np.linalg.pinv(L), wrench, lower, upper, out)
    np.testing.assert_allclose(out, np.clip(np.linalg.pinv(L) @ wrench, lower, upper), atol=1e-12)


def test_paper_layout_cannot_sway_and_paper_sway_can():
    sway = np.array([0, 0, 0, 0, 10.0, 0])
    paper = layout("paper")
    result = allocate(layout_matrix(paper), sway, *thrust_limits(paper))
    np.testing.assert_allclose(result.unachievable, sway, atol=1e-12)
    np.testing.assert_allclose(result.residual, sway, atol=1e-12)
    np.testing.assert_allclose(result.thrust, 0.0, atol=1e-12)
    with_sway = layout("paper-sway")
    result = allocate(layout_matrix(with_sway), sway, *thrust_limits(with_sway))
    np.testing.assert_allclose(result.achieved, sway, atol=1e-9)
    np.testing.assert_allclose(result.unachievable, 0.0, atol=1e-12)
    assert result.thrust[-1] == pytest.approx(10.0)


def test_unachievable_directions_of_bundled_layouts():
    def spanned_axes(name):
        N = unachievable_directions(layout_matrix(layout(name)))
        return sorted(int(i) for i in np.nonzero(np.linalg.norm(N, axis=1) > 1e-9)[0]), N.shape[1]

    assert spanned_axes("paper") == ([0, 1, 4], 3)  # K, M, Y
    assert spanned_axes("paper-sway") == ([0, 1], 2)  # K, M
    assert spanned_axes("ideal") == (list(range(6)), 6)  # no thrusters: the wrench is applied directly
    wrench = np.arange(1.0, 7.0)
    np.testing.assert_allclose(unachievable_part(layout_matrix(layout("paper-sway")), wrench), [1, 2, 0, 0, 0, 0],
                               atol=1e-12)


def test_layouts():
    assert set(layout_names()) == {"ideal", "paper", "paper-sway"}
    assert layout("ideal") == ()
    assert [t.name for t in layout()] == ["surge_port", "surge_starboard", "heave", "sway"]
    lower, upper = thrust_limits(layout("paper"))
    np.testing.assert_allclose(upper, 51.8, rtol=5e-3)          # conventions: about 51.8 N at 24 V
    np.testing.assert_allclose(lower, -upper)
    with pytest.raises(UvmsInputError):
        layout("nope")
    assert Thruster("t", (0, 0, 0), (0, 3, 4)).direction == pytest.approx((0, 0.6, 0.8))
    with pytest.raises(UvmsInputError):
        Thruster("t", (0, 0, 0), (0, 0, 0))
    with pytest.raises(UvmsInputError):
        Thruster("t", (0, 0, 0), (1, 0, 0), model="first_order", parameters=layout()[0].parameters)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(7, 10))
def test_redundant_saturated_allocation_keeps_wrench_and_lowers_norm(seed, m):
    from scipy.optimize import lsq_linear

    rng = np.random.default_rng(seed)
    L = random_layout(rng, m)
    lower, upper = -rng.uniform(1, 20, m), rng.uniform(1, 20, m)
    wrench = L @ rng.uniform(-30, 30, m) + rng.normal(size=6)
    result = allocate(L, wrench, lower, upper)
    bvls = lsq_linear(L, wrench, bounds=(lower, upper), method="bvls", tol=1e-14).x
    assert np.all(result.thrust >= lower) and np.all(result.thrust <= upper)
    np.testing.assert_allclose(result.achieved, L @ bvls, atol=1e-7 * max(1.0, np.linalg.norm(wrench)))
    assert np.linalg.norm(result.thrust) <= np.linalg.norm(bvls) + 1e-9
