"""The wave kernels' paths (:mod:`uvms.hydro.flow`): the vectorised polynomial one
(:func:`~uvms.hydro.flow.wave_terms_fast`) and a body's terms turned from its anchor
(:func:`~uvms.hydro.flow.wave_sums_near`) against the libm one (:func:`~uvms.hydro.flow.wave_terms_libm`), and
the whole evaluation of a 50-component irregular sea on either side of the polynomials' range against the Airy
closed form written here with numpy (independent of all three)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from numba import njit

from uvms.hydro.elementary import SIN_COS_LIMIT
from uvms.hydro.flow import (CH_C, CH_S, K_X, K_Y, NEAR, OMEGA, SH_C, SH_S, TERM_ROWS, WAVE_LANES, WAVENUMBER, Flow,
                             N_SUMS, bodies_waves, waves_add, wave_sums, wave_sums_near, wave_terms_fast, wave_terms_libm,
                             with_body_anchors)

G = 9.81


def irregular_sea(h: float, n: int = 50, seed: int = 5) -> SimpleNamespace:
    """``n`` components of 0.8 to 4 rad/s (the benchmark's band), random amplitudes, directions and phases."""
    rng = np.random.default_rng(seed)
    omega = np.sort(rng.uniform(0.8, 4.0, n))
    k = omega**2 / G
    if math.isfinite(h):
        for _ in range(60):                         # Newton on omega^2 = g k tanh(k h)
            k -= (G * k * np.tanh(k * h) - omega**2) / (G * np.tanh(k * h) + G * k * h / np.cosh(k * h) ** 2)
    return SimpleNamespace(amplitude=rng.uniform(0.0, 0.05, n), omega=omega, wavenumber=k,
                           direction=rng.uniform(-1.0, 1.0, n), phase=rng.uniform(0.0, 2 * math.pi, n),
                           water_depth=h)


def closed_form(sea: SimpleNamespace, t: float, x: float, y: float, zeta: float) -> np.ndarray:
    """The summed Airy velocity and local acceleration, z up, (6,), with numpy's sin, cos, cosh, sinh."""
    a, w, k, b, phi, h = sea.amplitude, sea.omega, sea.wavenumber, sea.direction, sea.phase, sea.water_depth
    theta = k * (x * np.cos(b) + y * np.sin(b)) - w * t + phi
    if math.isinf(h):
        ch = sh = np.exp(k * zeta)
    else:
        ch, sh = np.cosh(k * (zeta + h)) / np.sinh(k * h), np.sinh(k * (zeta + h)) / np.sinh(k * h)
    uh, ah = a * w * ch * np.cos(theta), a * w**2 * ch * np.sin(theta)
    return np.array([np.sum(uh * np.cos(b)), np.sum(uh * np.sin(b)), np.sum(a * w * sh * np.sin(theta)),
                     np.sum(ah * np.cos(b)), np.sum(ah * np.sin(b)), np.sum(-a * w**2 * sh * np.cos(theta))])


@pytest.mark.parametrize("h", [20.0, 6.0, math.inf])
def test_polynomial_and_libm_terms_agree(h):
    flow = Flow.constant(waves=irregular_sea(h)).compiled("enu")
    table = flow.wave_table
    assert table.shape[1] % WAVE_LANES == 0 and table.shape[1] >= 50
    fast, libm = np.zeros_like(flow.wave_work), np.zeros_like(flow.wave_work)
    terms = np.zeros((TERM_ROWS, table.shape[1]))
    rng = np.random.default_rng(7)
    for _ in range(200):
        x, y = rng.uniform(-500.0, 500.0, 2)
        zeta = -rng.uniform(0.0, min(h, 40.0))
        t = rng.uniform(0.0, 3.0e4)
        wave_terms_fast(table, fast, terms, x, y, zeta, t)
        wave_terms_libm(table, libm, terms, x, y, zeta, t)
        # each term is a depth factor (<= its surface value) times cos or sin of a phase near |theta| <= 1.3e5:
        # the phases of the two paths differ by their roundings, a few ulps of |theta|
        scale = np.maximum(np.abs(libm[CH_C]) + np.abs(libm[CH_S]), np.abs(libm[SH_C]) + np.abs(libm[SH_S]))
        theta = table[WAVENUMBER] * (abs(x) + abs(y)) + table[OMEGA] * t + 2 * math.pi
        bound = scale * (8 * np.spacing(theta) + 1e-14)
        for row in (CH_C, CH_S, SH_S, SH_C):
            assert np.all(np.abs(fast[row] - libm[row]) <= bound), row


def test_components_below_the_negligible_depth_are_dropped_on_both_paths():
    flow = Flow.constant(waves=irregular_sea(math.inf)).compiled("enu")
    fast, libm = np.ones_like(flow.wave_work), np.ones_like(flow.wave_work)
    terms = np.zeros((TERM_ROWS, flow.wave_table.shape[1]))
    zeta = -2000.0                                  # k zeta < -700 for the shortest components (k > 0.35)
    wave_terms_fast(flow.wave_table, fast, terms, 1.0, 2.0, zeta, 3.0)
    wave_terms_libm(flow.wave_table, libm, terms, 1.0, 2.0, zeta, 3.0)
    dropped = flow.wave_table[WAVENUMBER] * zeta < -700.0
    assert dropped.any()
    assert np.all(fast[:, dropped] == 0.0) and np.all(libm[:, dropped] == 0.0)


@pytest.mark.parametrize("t", [10.0, 2.0e5, 2.6e5, 4.0e5])
def test_either_path_gives_the_closed_form(t):
    # max w = 4 rad/s: up to t = 2.5e5 s every phase is within SIN_COS_LIMIT (the polynomial path), beyond it
    # the bound fails and the kinematics come from libm; both must give the closed form
    sea = irregular_sea(20.0)
    flow = Flow.constant(waves=sea)
    rng = np.random.default_rng(int(t))
    for _ in range(5):
        x, y, zeta = rng.uniform(-50, 50), rng.uniform(-50, 50), -rng.uniform(0.5, 15.0)
        v, a, _ = flow.kinematics(t, [x, y, zeta], "enu")
        expected = closed_form(sea, t, x, y, zeta)
        # the phase w t of either path and of numpy is rounded differently: a few ulps of w t
        tolerance = 50 * np.spacing(4.0 * t) * np.sum(sea.amplitude * sea.omega**2) + 1e-13
        np.testing.assert_allclose(v[0], expected[:3], rtol=0, atol=tolerance)
        local = a[0] - _convective(flow, t, [x, y, zeta])
        np.testing.assert_allclose(local, expected[3:], rtol=0, atol=tolerance * 4.0)
    assert (4.0 * 2.0e5 + 2 * math.pi + 50 * 1.7 * 2 < SIN_COS_LIMIT) and 4.0 * 2.6e5 > SIN_COS_LIMIT


def _convective(flow, t, point) -> np.ndarray:
    v, _, grad = flow.kinematics(t, point, "enu")
    return grad[0] @ v[0]


@pytest.mark.parametrize("h", [20.0, 6.0, math.inf])
def test_sums_turned_from_an_anchor_agree_with_libm_at_the_point(h):
    # the anchor's terms from the polynomial path, the nearby point's sums from the angle-addition formulas,
    # against libm's terms evaluated at the point itself and summed; the offsets span the whole NEAR box
    flow = Flow.constant(waves=irregular_sea(h)).compiled("enu")
    table, weights = flow.wave_table, flow.wave_weights
    anchor = np.zeros((TERM_ROWS, table.shape[1]))
    libm, scratch = np.zeros_like(flow.wave_work), np.zeros_like(anchor)
    near, full = np.zeros(N_SUMS), np.zeros(N_SUMS)
    rng = np.random.default_rng(11)
    k_max, w_max = table[WAVENUMBER].max(), table[OMEGA].max()
    kx, ky = np.abs(table[K_X]).max(), np.abs(table[K_Y]).max()
    largest = 0.0
    for _ in range(300):
        x, y = rng.uniform(-200.0, 200.0, 2)
        zeta = -rng.uniform(0.5, min(h, 30.0) - 0.5)
        t = rng.uniform(0.0, 2.0e3)
        wave_terms_fast(table, np.zeros_like(libm), anchor, x, y, zeta, t)
        share = rng.dirichlet(np.ones(3)) * NEAR * rng.uniform(0.5, 1.0)       # of the phase bound
        dx, dy, dt = share[0] / kx * rng.choice([-1, 1]), share[1] / ky * rng.choice([-1, 1]), share[2] / w_max
        dzeta = rng.uniform(-1.0, 1.0) * NEAR / k_max
        wave_sums_near(table, weights, anchor[None], np.array([[dx, dy, dzeta, dt]]), near[None], 1)
        wave_terms_libm(table, libm, scratch, x + dx, y + dy, zeta + dzeta, t + dt)
        wave_sums(weights, libm, full)
        largest = max(largest, np.abs(table[K_X] * dx + table[K_Y] * dy - table[OMEGA] * dt).max())
        # each term is a depth factor times a sine or cosine; the phases of the anchor and of libm at the point
        # are rounded differently, a few ulps of |theta|
        theta = table[WAVENUMBER] * (abs(x) + abs(y)) + table[OMEGA] * t + 2 * math.pi
        factor = np.abs(libm[CH_C]) + np.abs(libm[CH_S]) + np.abs(libm[SH_S]) + np.abs(libm[SH_C])   # >= ch, sh
        bound = np.abs(weights) @ (factor * (8 * np.spacing(theta) + 1e-14))
        assert np.all(np.abs(near - full) <= bound)
    assert largest > 0.5 * NEAR                     # the offsets did reach the edge of the box


@njit(cache=True)
def _along(flow, times, points, body, v, a, grad, anchored_at):
    """``waves_add`` at ``points[j]``, ``times[j]`` for body ``body`` (0, its sums from ``bodies_waves``; or -1
    or beyond the anchors: evaluated in full), counting the anchors taken (the anchor's time changed)."""
    taken = 0
    slot = body == 0 and flow.wave_anchor.shape[0] > 0
    for j in range(times.shape[0]):
        v[j] = 0.0
        a[j] = 0.0
        before = flow.wave_anchor_at[0, 3] if slot else 0.0
        if slot:
            bodies_waves(flow, points[j:j + 1], times[j], 1)
        waves_add(flow, times[j], points[j], body, v[j], a[j], grad[j])
        if slot and not flow.wave_anchor_at[0, 3] == before:
            taken += 1
    anchored_at[0] = taken


@pytest.mark.parametrize("h", [20.0, math.inf])
def test_a_body_along_a_path_sees_the_water_of_a_full_evaluation(h):
    # an RK4-like sequence of points (a drifting, heaving body, 1 ms half steps) evaluated as body 0 of a flow
    # with anchors and as no body: the same kinematics to rounding, and most evaluations turned from an anchor
    flow = with_body_anchors(Flow.constant(waves=irregular_sea(h)).compiled("ned"), 3)
    n = 4000
    times = np.arange(n) * 5e-4
    points = np.column_stack([0.3 * times + 0.05 * np.sin(2 * times), -0.2 * times, 3.0 + 0.4 * np.sin(1.3 * times)])
    out = {}
    for body in (0, -1):
        v, a, grad, taken = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3, 3)), np.zeros(1, dtype=np.int64)
        _along(flow, times, points, body, v, a, grad, taken)
        out[body] = v, a, grad, int(taken[0])
    v1, a1, g1, taken = out[0]
    v0, a0, g0, _ = out[-1]
    assert 0 < taken < n // 10                      # anchors renewed, but most points turned from one
    scale = np.abs(v0).max()
    np.testing.assert_allclose(v1, v0, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(a1, a0, rtol=0, atol=1e-13 * np.abs(a0).max())
    np.testing.assert_allclose(g1, g0, rtol=0, atol=1e-13 * np.abs(g0).max())
    assert np.all(np.isnan(flow.wave_anchor_at[[1, 2]]))      # the other bodies' anchors untouched


def test_a_body_without_an_anchor_slot_is_evaluated_in_full():
    flow = with_body_anchors(Flow.constant(waves=irregular_sea(20.0)).compiled("ned"), 2)
    times, points = np.array([1.0, 1.0001]), np.array([[0.0, 0.0, 3.0], [0.0, 0.0, 3.0]])
    v, a, grad, taken = np.zeros((2, 3)), np.zeros((2, 3)), np.zeros((2, 3, 3)), np.zeros(1, dtype=np.int64)
    _along(flow, times, points, 5, v, a, grad, taken)
    v0, a0, _ = Flow.constant(waves=irregular_sea(20.0)).kinematics(1.0001, [0.0, 0.0, 3.0], "ned")
    np.testing.assert_array_equal(v[1], v0[0])
    assert np.all(np.isnan(flow.wave_anchor_at))


@njit(cache=True)
def _bodies_then_points(flow, times, points, v, a, grad, v_full, a_full, grad_full):
    """At each time, ``bodies_waves`` for all the bodies at ``points[j]`` (B, 3), then each body's kinematics
    from its sums and the same points evaluated in full (body -1)."""
    for j in range(times.shape[0]):
        bodies_waves(flow, points[j], times[j], points.shape[1])
        for b in range(points.shape[1]):
            v[j, b] = 0.0
            a[j, b] = 0.0
            v_full[j, b] = 0.0
            a_full[j, b] = 0.0
            waves_add(flow, times[j], points[j, b], b, v[j, b], a[j, b], grad[j, b])
            waves_add(flow, times[j], points[j, b], -1, v_full[j, b], a_full[j, b], grad_full[j, b])


def test_the_bodies_of_one_call_each_see_the_water_at_their_own_point():
    # three bodies 0.4 m apart, moving differently, through one wave_sums_near call per time: each body's sums are
    # its own (not a neighbour's) and match a full evaluation at its point to rounding
    flow = with_body_anchors(Flow.constant(waves=irregular_sea(20.0)).compiled("ned"), 3)
    times = np.arange(2000) * 5e-4
    offsets = np.array([[0.0, 0.0, 3.0], [0.4, 0.0, 3.2], [0.4, 0.4, 3.5]])
    motion = np.stack([np.column_stack([0.2 * times, 0.1 * np.sin(times), 0.05 * np.sin(2 * times)]) * (b + 1)
                       for b in range(3)], axis=1)
    points = offsets[None] + motion
    shape = (times.size, 3, 3)
    v, a, v_full, a_full = (np.zeros(shape) for _ in range(4))
    grad, grad_full = np.zeros(shape + (3,)), np.zeros(shape + (3,))
    _bodies_then_points(flow, times, points, v, a, grad, v_full, a_full, grad_full)
    for mine, full in ((v, v_full), (a, a_full), (grad, grad_full)):
        np.testing.assert_allclose(mine, full, rtol=0, atol=1e-13 * np.abs(full).max())
    assert np.abs(v_full[:, 0] - v_full[:, 2]).max() > 1e-3 * np.abs(v_full).max()   # the bodies' water differs
    assert np.all(np.isfinite(flow.wave_anchor_at))
