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
    redundant = np.linalg.matrix_rank(L) < L.shape[1]
    bounded_least_squares(np.ascontiguousarray(L), wrench, lower, upper, eps, redundant, x,
                          np.zeros(L.shape[1], np.int64))
    return x


def optimality_gap(L, wrench, lower, upper, thrust):
    """KKT of the bounded least squares: no feasible direction of descent of |L T - w|^2 (checked per thruster)."""
    g = L.T @ (L @ thrust - wrench)
    at_lower = thrust <= lower + 1e-9
    at_upper = thrust >= upper - 1e-9
    free = ~(at_lower | at_upper)
    return max(np.abs(g[free]).max(initial=0.0), (-g[at_lower]).max(initial=0.0), g[at_upper].max(initial=0.0))


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 10), st.floats(0.5, 5.0))
def test_compiled_bounded_least_squares_equals_scipy(seed, m, overdrive):
    """Random layouts (redundant with m > 6 or with two parallel thrusters, rank-deficient with m < 6), random
    asymmetric limits, wrenches beyond them. The achieved wrench (unique) equals allocate()'s to 1e-9 and is
    optimal (KKT of the bounded least squares). The thrust: with a full-rank layout (a unique minimiser) equal
    to allocate()'s to 1e-9; with a null space allocate() refines by SLSQP (ftol 1e-16), which stops within
    ~1e-7 N of the minimum-norm thrust (in 3000 random cases: 2897 equal to 1e-8, 91 with SLSQP's norm larger,
    12 differing by 1e-8 to 4e-7 N), so there the compiled thrust's norm must not exceed allocate()'s by more
    than that."""
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
    if np.linalg.matrix_rank(L) == m:
        np.testing.assert_allclose(thrust, reference.thrust, rtol=0, atol=1e-9 * max(1.0, np.abs(upper).max()))
    else:
        norm, reference_norm = np.linalg.norm(thrust), np.linalg.norm(reference.thrust)
        assert norm <= reference_norm + 1e-6 * max(1.0, reference_norm)


def thrusters_named(name):
    if name.startswith("model:"):
        import uvms

        return tuple(uvms.load_model(name[6:]).thrusters)
    if name == "first_order":
        from uvms.thrusters.layouts import Thruster

        return tuple(Thruster(f"f{j}", (0.2 * j, 0.1, -0.1 * j), d, "first_order")
                     for j, d in enumerate([(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (0, 1, 1), (1, 0, 1)]))
    return layout(name)


@pytest.mark.parametrize("name", [n for n in layout_names() if layout(n)]
                         + ["model:bluerov2_heavy_alpha5", "first_order"])
def test_allocate_command_equals_the_python_path(name):
    """pinv first, allocate() when a limit is violated, then Healey voltage / table command / thrust
    (Healey layouts, the BlueROV2's eight datasheet-table T200s, first-order thrusters)."""
    thrusters = thrusters_named(name)
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
