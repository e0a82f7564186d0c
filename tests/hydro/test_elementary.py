"""The branch-free sine-cosine and exponential pair (:mod:`uvms.hydro.elementary`) against libm (``math.sin``,
``math.cos``, ``math.exp``), in ulps of libm's result, over the whole range the wave kernels use: random
arguments (uniform and log-uniform in magnitude), the reduction's boundaries (odd multiples of pi/4, ln 2 / 2),
the quadrant boundaries, zero and tiny arguments, and both sides of the polynomials' limits (where
:func:`sin_cos` and :func:`exp_pair` hand over to libm)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uvms.hydro.elementary import (EXP_LIMIT, SIN_COS_LIMIT, SMALL_LIMIT, exp_pair_array, exp_pair_reduced_array,
                                   power_of_two, sin_cos_array, sin_cos_reduced_array, sin_cos_small_array,
                                   sinh_cosh_scaled, sinh_cosh_small_array, small_hyperbolic_coefficients)
from uvms.jit import fused_kernel

MAX_ULPS = 2.0
"""The error bound pinned here: Taylor truncation below 0.4 ulp plus the Horner and final roundings (a round
to nearest each, and the reduction's last step) stays within two ulps of the correctly rounded value; libm is
itself within one ulp or better."""


def ulps(value: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """``|value - reference|`` in units of the last place of ``reference`` (its spacing; of the smallest
    normal number for results below it)."""
    spacing = np.spacing(np.maximum(np.abs(reference), np.finfo(float).tiny))
    return np.abs(value - reference) / spacing


def _libm(function, x: np.ndarray) -> np.ndarray:
    return np.array([function(v) for v in x])


def _sin_cos_arguments(limit: float) -> np.ndarray:
    rng = np.random.default_rng(2027)
    uniform = rng.uniform(-limit, limit, 40_000)
    log_uniform = np.exp(rng.uniform(math.log(1e-12), math.log(limit), 40_000)) * rng.choice([-1.0, 1.0], 40_000)
    m = np.arange(-2000, 2001)
    boundaries = np.concatenate([(2 * m + 1) * math.pi / 4, m * math.pi / 2])           # reduction, quadrants
    near = np.concatenate([np.nextafter(boundaries, np.inf), np.nextafter(boundaries, -np.inf), boundaries])
    far = np.array([limit, -limit, 2.0**23, 1.2345678e5, 999_999.5])
    far = far[np.abs(far) <= limit]
    return np.concatenate([uniform, log_uniform, near, far, [0.0, -0.0, 5e-324, 1e-300, -1e-300]])


def test_sin_cos_reduced_is_within_two_ulps_of_libm_over_its_whole_range():
    x = _sin_cos_arguments(SIN_COS_LIMIT)
    s, c = np.empty_like(x), np.empty_like(x)
    sin_cos_reduced_array(x, s, c)
    sin_ulps = ulps(s, _libm(math.sin, x))
    cos_ulps = ulps(c, _libm(math.cos, x))
    assert sin_ulps.max() <= MAX_ULPS, x[np.argmax(sin_ulps)]
    assert cos_ulps.max() <= MAX_ULPS, x[np.argmax(cos_ulps)]
    assert np.mean(sin_ulps == 0.0) > 0.5 and np.mean(cos_ulps == 0.0) > 0.5     # most results exact


def test_sin_cos_hands_over_to_libm_at_its_limit_and_agrees_across_it():
    inside = np.array([SIN_COS_LIMIT, -SIN_COS_LIMIT, np.nextafter(SIN_COS_LIMIT, 0.0)])
    outside = np.array([np.nextafter(SIN_COS_LIMIT, np.inf), -np.nextafter(SIN_COS_LIMIT, np.inf), 1e7, 1e300,
                        np.inf, -np.inf, np.nan])
    x = np.concatenate([inside, outside])
    s, c = np.empty_like(x), np.empty_like(x)
    sin_cos_array(x, s, c)
    s_poly, c_poly = np.empty(3), np.empty(3)
    sin_cos_reduced_array(inside, s_poly, c_poly)
    assert np.array_equal(s[:3], s_poly) and np.array_equal(c[:3], c_poly)         # the polynomial inside
    with np.errstate(invalid="ignore"):
        libm_s, libm_c = np.sin(outside), np.cos(outside)
    assert np.array_equal(s[3:], libm_s, equal_nan=True) and np.array_equal(c[3:], libm_c, equal_nan=True)
    assert ulps(s[:3], np.sin(inside)).max() <= MAX_ULPS and ulps(c[:3], np.cos(inside)).max() <= MAX_ULPS


def _exp_arguments(limit: float) -> np.ndarray:
    rng = np.random.default_rng(2028)
    uniform = rng.uniform(-limit, limit, 40_000)
    small = rng.uniform(-2.0, 2.0, 20_000)
    m = np.arange(-2050, 2051)
    boundaries = (m + 0.5) * math.log(2.0)                     # where rint(x / ln 2) changes
    near = np.concatenate([np.nextafter(boundaries, np.inf), np.nextafter(boundaries, -np.inf)])
    near = near[np.abs(near) <= limit]
    return np.concatenate([uniform, small, near, [limit, -limit, 0.0, -0.0, 1e-300, -1e-17, 700.0, -700.0]])


def test_exp_pair_reduced_is_within_two_ulps_of_libm_over_its_whole_range():
    x = _exp_arguments(EXP_LIMIT)
    e_up, e_down = np.empty_like(x), np.empty_like(x)
    exp_pair_reduced_array(x, e_up, e_down)
    up_ulps = ulps(e_up, _libm(math.exp, x))
    down_ulps = ulps(e_down, _libm(math.exp, -x))
    assert up_ulps.max() <= MAX_ULPS, x[np.argmax(up_ulps)]
    assert down_ulps.max() <= MAX_ULPS, x[np.argmax(down_ulps)]


def test_exp_pair_hands_over_to_libm_at_its_limit():
    inside = np.array([EXP_LIMIT, -EXP_LIMIT])
    outside = np.array([np.nextafter(EXP_LIMIT, np.inf), -np.nextafter(EXP_LIMIT, np.inf), 709.5, -745.0, -800.0,
                        800.0, np.inf, -np.inf, np.nan])
    x = np.concatenate([inside, outside])
    e_up, e_down = np.empty_like(x), np.empty_like(x)
    exp_pair_array(x, e_up, e_down)
    with np.errstate(over="ignore"):
        libm_up, libm_down = np.exp(outside), np.exp(-outside)
    assert np.array_equal(e_up[2:], libm_up, equal_nan=True) and np.array_equal(e_down[2:], libm_down, equal_nan=True)
    assert ulps(e_up[:2], np.exp(inside)).max() <= MAX_ULPS and ulps(e_down[:2], np.exp(-inside)).max() <= MAX_ULPS


@pytest.mark.parametrize("n", [-1022, -1, 0, 1, 52, 1023])
def test_power_of_two_is_exact(n):
    assert power_of_two(n) == math.ldexp(1.0, n)


def _small_arguments() -> np.ndarray:
    rng = np.random.default_rng(2028)
    log_uniform = np.exp(rng.uniform(math.log(1e-12), math.log(SMALL_LIMIT), 20_000)) * rng.choice([-1.0, 1.0], 20_000)
    return np.concatenate([rng.uniform(-SMALL_LIMIT, SMALL_LIMIT, 40_000), log_uniform,
                           [SMALL_LIMIT, -SMALL_LIMIT, 0.0, -0.0, 1e-300]])


def test_small_argument_series_are_within_two_ulps_of_libm():
    # the series without range reduction the wave anchors turn with (truncation below 0.1 ulp of 1)
    d = _small_arguments()
    s, c, sh, ch = (np.empty_like(d) for _ in range(4))
    sin_cos_small_array(d, s, c)
    sinh_cosh_small_array(d, sh, ch)
    for value, function in ((s, math.sin), (c, math.cos), (sh, math.sinh), (ch, math.cosh)):
        error = ulps(value, _libm(function, d))
        assert error.max() <= MAX_ULPS, (function.__name__, d[np.argmax(error)])


@fused_kernel
def _scaled(k, dz, sinh_out, cosh_out):
    for i in range(k.shape[0]):
        sinh_out[i], cosh_out[i] = sinh_cosh_scaled(k[i], k[i] * k[i], small_hyperbolic_coefficients(dz[i]))


def test_hyperbolic_pair_in_powers_of_k_squared_is_the_series_of_k_dz():
    # the wave kernel's form (coefficients from dz, Horner in k^2) against libm at the rounded product k dz: the
    # product's own rounding (half an ulp) comes on top of the series'
    rng = np.random.default_rng(2029)
    k = np.exp(rng.uniform(math.log(1e-3), math.log(10.0), 50_000))
    dz = rng.uniform(-1.0, 1.0, k.size) * SMALL_LIMIT / k
    sh, ch = np.empty_like(k), np.empty_like(k)
    _scaled(k, dz, sh, ch)
    x = k * dz
    assert ulps(sh, np.sinh(x)).max() <= MAX_ULPS + 1.0
    assert ulps(ch, np.cosh(x)).max() <= MAX_ULPS
