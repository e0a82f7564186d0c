"""The wave kernels' two paths (:mod:`uvms.hydro.flow`): the vectorised polynomial one
(:func:`~uvms.hydro.flow.wave_terms_fast`) against the libm one (:func:`~uvms.hydro.flow.wave_terms_libm`), and
the whole evaluation of a 50-component irregular sea on either side of the polynomials' range against the Airy
closed form written here with numpy (independent of both)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from uvms.hydro.elementary import SIN_COS_LIMIT
from uvms.hydro.flow import (CH_C, CH_S, OMEGA, SH_C, SH_S, WAVE_LANES, WAVENUMBER, Flow, wave_terms_fast,
                             wave_terms_libm)

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
    rng = np.random.default_rng(7)
    for _ in range(200):
        x, y = rng.uniform(-500.0, 500.0, 2)
        zeta = -rng.uniform(0.0, min(h, 40.0))
        t = rng.uniform(0.0, 3.0e4)
        wave_terms_fast(table, fast, x, y, zeta, t)
        wave_terms_libm(table, libm, x, y, zeta, t)
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
    zeta = -2000.0                                  # k zeta < -700 for the shortest components (k > 0.35)
    wave_terms_fast(flow.wave_table, fast, 1.0, 2.0, zeta, 3.0)
    wave_terms_libm(flow.wave_table, libm, 1.0, 2.0, zeta, 3.0)
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
