"""The compiled allocation and thrust -> command (:mod:`uvms.thrusters.command`) against the Python
reference: :func:`uvms.thrusters.allocation.allocate` (scipy's BVLS and SLSQP) and the per-thruster inverses
called one by one, as ``simulate`` did before it was compiled."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uvms.thrusters.allocation import allocate, allocation_matrix
from uvms.thrusters.command import (
    allocate_command,
    bounded_least_squares,
    thrust_command,
    thrust_command_names,
)
from uvms.thrusters.healey import healey_voltage_for_thrust, steady_coefficients
from uvms.thrusters.layouts import layout, layout_matrix, layout_names, thrust_limits
from uvms.thrusters.table import table_command


def compiled_allocation(L, wrench, lower, upper):
    x = np.linalg.pinv(L) @ wrench
    if np.all(x >= lower) and np.all(x <= upper):
        return x
    eps = 1e-12 * float(np.sum(L * L))
    bounded_least_squares(np.ascontiguousarray(L), wrench, lower, upper, eps, x, np.zeros(L.shape[1], np.int64))
    return x


def optimality_gap(L, wrench, lower, upper, thrust):
    """KKT of the bounded least squares: no feasible direction of descent of |L T - w|^2 (checked per thruster)."""
    g = L.T @ (L @ thrust - wrench)
    at_lower = thrust <= lower + 1e-9
    at_upper = thrust >= upper - 1e-9
    free = ~(at_lower | at_upper)
    return max(np.abs(g[free]).max(initial=0.0), (-g[at_lower]).max(initial=0.0), g[at_upper].max(initial=0.0))


@settings(max_examples=150, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 10), st.floats(0.5, 5.0))
def test_compiled_bounded_least_squares_equals_scipy(seed, m, overdrive):
    """Random layouts (redundant with m > 6, rank-deficient with m < 6), random asymmetric limits, wrenches
    beyond them: same achieved wrench and same thrust as allocate() to ~1e-9."""
    rng = np.random.default_rng(seed)
    positions = rng.uniform(-0.3, 0.3, (m, 3))
    directions = rng.normal(size=(m, 3))
    if m > 2 and rng.random() < 0.3:
        directions[1] = directions[0]                  # two parallel thrusters: a null space even for m <= 6
        positions[1] = positions[0] + 0.1 * directions[0]
    L = allocation_matrix(positions, directions)
    lower, upper = -rng.uniform(5, 50, m), rng.uniform(5, 50, m)
    wrench = L @ (overdrive * rng.uniform(lower, upper)) + rng.normal(0.0, 2.0, 6)
    reference = allocate(L, wrench, lower, upper)
    thrust = compiled_allocation(L, wrench, lower, upper)
    assert np.all(thrust >= lower) and np.all(thrust <= upper)
    scale = max(1.0, np.abs(wrench).max())
    np.testing.assert_allclose(L @ thrust, reference.achieved, rtol=0, atol=1e-9 * scale)
    assert optimality_gap(L, wrench, lower, upper, thrust) < 1e-8 * scale
    if np.linalg.matrix_rank(L) == m or thrust @ thrust >= reference.thrust @ reference.thrust - 1e-9:
        np.testing.assert_allclose(thrust, reference.thrust, rtol=0, atol=1e-9 * max(1.0, np.abs(upper).max()))
    # else: SLSQP stopped short of the minimum norm; ours is at least as small with the same wrench (checked above)


@pytest.mark.parametrize("name", [n for n in layout_names() if layout(n)])
def test_allocate_command_equals_the_python_path(name):
    """pinv first, allocate() when a limit is violated, then Healey voltage / table command / thrust."""
    thrusters = layout(name)
    data = thrust_command(thrusters)
    m = len(thrusters)
    L = layout_matrix(thrusters)
    lower, upper = thrust_limits(thrusters)
    names = thrust_command_names(thrusters)
    assert names == (tuple(f"thrust_cmd_{t.name}" for t in thrusters) + tuple(f"unachieved_{a}" for a in "KMNXYZ")
                     if m else ())
    rng = np.random.default_rng(4)
    for scale in (1.0, 20.0, 200.0):                    # within limits, then saturating
        for _ in range(20):
            wrench = rng.normal(0.0, scale, 6)
            command = np.zeros(max(m, 6))
            signals = np.zeros(m + 6)
            allocate_command(data, wrench, command, signals)
            thrust = np.linalg.pinv(L) @ wrench
            if np.any(thrust < lower) or np.any(thrust > upper):
                thrust = allocate(L, wrench, lower, upper).thrust
            np.testing.assert_allclose(signals[:m], thrust, rtol=0, atol=1e-9 * max(1.0, scale))
            np.testing.assert_allclose(signals[m:], wrench - L @ signals[:m], rtol=0, atol=1e-12 * scale)
            for j, t in enumerate(thrusters):
                if t.model == "healey":
                    expected = healey_voltage_for_thrust(t.parameters.as_array(), steady_coefficients(t.parameters),
                                                         signals[j])
                elif t.model == "table":
                    expected = table_command(t.parameters.as_array(), signals[j])
                else:
                    expected = signals[j]
                assert command[j] == expected
            assert np.all(command[m:] == 0.0)


def test_ideal_actuation_passes_the_wrench():
    data = thrust_command(())
    wrench = np.arange(6.0)
    command = np.full(6, np.nan)
    allocate_command(data, wrench, command, np.zeros(0))
    np.testing.assert_array_equal(command, wrench)
    assert thrust_command_names(()) == ()
