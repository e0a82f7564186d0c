"""Branch-free sine-cosine and exponential pair for the wave kernels (:mod:`uvms.hydro.flow`).

libm's ``sin``, ``cos`` and ``exp`` are calls the compiler cannot vectorise; the wave kinematics need one of
each per component and per body in every RK4 stage (``docs/flow.md``, "Cost"). These functions are straight
arithmetic (no table, no branch on the argument), so a loop over wave components that calls them compiles
to vector instructions.

**Sine and cosine** (:func:`sin_cos_reduced`): Cody-Waite range reduction (Muller, *Elementary Functions*,
ch. 11): ``n = rint(x 2/pi)``, ``r = x - n pi/2`` with ``pi/2 = P1 + P2 + P3``, where ``P1`` and ``P2`` carry 30
significant bits each, so that ``n P1`` and ``n P2`` are exact for ``|n| < 2^23`` and ``x - n P1`` is exact
(Sterbenz); then ``|r| <= pi/4`` and the Taylor series::

    sin r = r - r^3/3! + ... + r^17/17!       (next term below 0.4 ulp of sin r at r = pi/4)
    cos r = 1 - r^2/2! + ... + r^16/16!       (next term below 0.02 ulp)

and the quadrant ``n mod 4`` picks ``(sin x, cos x) = (s, c), (c, -s), (-s, -c), (-c, s)``. Valid for
``|x| <= SIN_COS_LIMIT``; :func:`sin_cos` falls back to libm beyond.

**Exponential pair** (:func:`exp_pair_reduced`): ``e^x`` and ``e^-x`` from one reduction: ``n = rint(x / ln 2)``,
``r = x - n ln 2`` (``ln 2 = L1 + L2``, ``L1`` with 32 significant bits), ``|r| <= ln 2 / 2``, the even and odd
parts of the Taylor series::

    C = cosh r = 1 + r^2/2! + ... + r^12/12!        S = sinh r = r + r^3/3! + ... + r^13/13!
    e^x = 2^n (C + S)                                e^-x = 2^-n (C - S)

(next terms below 0.05 ulp), the powers of two built from their exponent bits. Valid for
``|x| <= EXP_LIMIT`` (both results normal); :func:`exp_pair` falls back to libm beyond.

**Small arguments** (:func:`sin_cos_small`, :func:`sinh_cosh_small`), ``|d| <= SMALL_LIMIT = 1/32``: no
reduction, the Taylor series to ``d^7`` (odd) and ``d^6`` (even)::

    sin d = d - d^3/3! + d^5/5! - d^7/7!      (next term below d^9/9! = 7.8e-20)
    cos d = 1 - d^2/2! + d^4/4! - d^6/6!      (next term below d^8/8! = 2.2e-17, 0.1 ulp of 1)

and ``sinh``, ``cosh`` with every sign ``+``: absolute errors below an ulp of 1. The wave kernels turn a body's
terms at its last full evaluation into its terms at a nearby point and time with them (the angle-addition
formulas, :func:`uvms.hydro.flow.wave_sums_near`). There the hyperbolic pair's argument is ``k dz`` for every
component's wave number ``k`` and one height change ``dz``, so the series are written as polynomials in ``k^2``
whose coefficients depend on ``dz`` alone (:func:`small_hyperbolic_coefficients`, once per call;
:func:`sinh_cosh_scaled`, per component)::

    cosh(k dz) = 1 + k^2 (A1 + k^2 (A2 + k^2 A3))               A_j = dz^(2j) / (2j)!
    sinh(k dz) = k (B0 + k^2 (B1 + k^2 (B2 + k^2 B3)))          B_j = dz^(2j+1) / (2j+1)!

the same terms as the series in ``d = k dz``, three operations fewer per component.

Errors, measured against libm (``tests/hydro/test_elementary.py``): at most a few ulps (the tests pin the
bound). The kernels are compiled with floating-point contraction only (:data:`uvms.jit.fused_block`): an FMA
keeps every step above exact or better rounded; reassociation would undo the reductions, so it is never allowed
here.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from uvms.jit import fused_block, fused_kernel

SIN_COS_LIMIT = 1.0e6
"""``|x|`` [rad] up to which :func:`sin_cos_reduced` holds (``|n| < 2^23``: the reduction's products exact)."""
EXP_LIMIT = 708.0
"""``|x|`` up to which :func:`exp_pair_reduced` holds (``2^n`` and ``2^-n`` normal numbers)."""
SMALL_LIMIT = 1.0 / 32.0
"""``|d|`` up to which :func:`sin_cos_small` and :func:`sinh_cosh_small` hold (their truncation errors below
2.2e-17, a tenth of an ulp of 1)."""

_TWO_OVER_PI = 2.0 / math.pi
_P1 = float.fromhex("0x1.921fb54800000p+0")      # pi/2 to 30 bits
_P2 = float.fromhex("-0x1.de973dc800000p-31")    # the next 30 bits of pi/2 (negative: rounded to nearest)
_P3 = float.fromhex("-0x1.9d9cceba3f91fp-62")    # the rest, rounded to 53 bits
_INV_LN2 = 1.0 / math.log(2.0)
_L1 = 0.6931471806019545                        # ln 2 to 32 bits
_L2 = -4.2009150726810846e-11                   # ln 2 - L1, rounded
_EXPONENT_BIAS = 1023
_MANTISSA_BITS = 52

_F = [1.0 / math.factorial(n) for n in range(18)]   # 1/n!, each correctly rounded (n! < 2^53 exactly)
_S3, _S5, _S7, _S9, _S11, _S13, _S15, _S17 = (-_F[3], _F[5], -_F[7], _F[9], -_F[11], _F[13], -_F[15], _F[17])
_C2, _C4, _C6, _C8, _C10, _C12, _C14, _C16 = (-_F[2], _F[4], -_F[6], _F[8], -_F[10], _F[12], -_F[14], _F[16])
_E2, _E4, _E6, _E8, _E10, _E12 = (_F[2], _F[4], _F[6], _F[8], _F[10], _F[12])
_E3, _E5, _E7, _E9, _E11, _E13 = (_F[3], _F[5], _F[7], _F[9], _F[11], _F[13])


@intrinsic
def _float_from_bits(typingctx, bits):
    """The float64 whose IEEE 754 bit pattern is the int64 ``bits`` (a reinterpretation, no conversion)."""
    if not isinstance(bits, types.Integer):
        return None
    signature = types.float64(types.int64)

    def codegen(context, builder, sig, args):
        return builder.bitcast(args[0], ir.DoubleType())

    return signature, codegen


@fused_block
def power_of_two(n):
    """``2^n`` for an integer ``n`` in [-1022, 1023] (its exponent field ``n + 1023``, mantissa zero)."""
    return _float_from_bits((n + _EXPONENT_BIAS) << _MANTISSA_BITS)


@fused_block
def sin_cos_reduced(x):
    """``(sin x, cos x)`` for ``|x| <= SIN_COS_LIMIT`` (module docstring), branch-free."""
    n = np.rint(x * _TWO_OVER_PI)
    r = x - n * _P1
    r = r - n * _P2
    r = r - n * _P3
    r2 = r * r
    s = r + r * r2 * (_S3 + r2 * (_S5 + r2 * (_S7 + r2 * (_S9 + r2 * (_S11 + r2 * (_S13 + r2 * (
        _S15 + r2 * _S17)))))))
    c = 1.0 + r2 * (_C2 + r2 * (_C4 + r2 * (_C6 + r2 * (_C8 + r2 * (_C10 + r2 * (_C12 + r2 * (
        _C14 + r2 * _C16)))))))
    quadrant = np.int64(n) & 3
    odd = (quadrant & 1) == 1
    sin_x = c if odd else s
    cos_x = s if odd else c
    sin_sign = 1.0 - 2.0 * ((quadrant >> 1) & 1)                 # quadrants 2, 3: -sin
    cos_sign = 1.0 - 2.0 * (((quadrant + 1) >> 1) & 1)           # quadrants 1, 2: -cos
    return sin_x * sin_sign, cos_x * cos_sign


@fused_block
def exp_pair_reduced(x):
    """``(e^x, e^-x)`` for ``|x| <= EXP_LIMIT`` (module docstring), branch-free."""
    n = np.rint(x * _INV_LN2)
    r = x - n * _L1
    r = r - n * _L2
    r2 = r * r
    even = 1.0 + r2 * (_E2 + r2 * (_E4 + r2 * (_E6 + r2 * (_E8 + r2 * (_E10 + r2 * _E12)))))
    odd = r + r * r2 * (_E3 + r2 * (_E5 + r2 * (_E7 + r2 * (_E9 + r2 * (_E11 + r2 * _E13)))))
    m = np.int64(n)
    return (even + odd) * power_of_two(m), (even - odd) * power_of_two(-m)


@fused_block
def sin_cos_small(d):
    """``(sin d, cos d)`` for ``|d| <= SMALL_LIMIT`` (module docstring: Taylor to ``d^7``, ``d^6``)."""
    d2 = d * d
    return d + d * d2 * (_S3 + d2 * (_S5 + d2 * _S7)), 1.0 + d2 * (_C2 + d2 * (_C4 + d2 * _C6))


@fused_block
def small_hyperbolic_coefficients(dz):
    """``(A1, A2, A3, B0, B1, B2, B3)``: the coefficients of :func:`sinh_cosh_scaled` for the height change
    ``dz`` (module docstring), ``A_j = dz^(2j) / (2j)!``, ``B_j = dz^(2j+1) / (2j+1)!``; the powers taken side
    by side (a short dependency chain before the loop that uses them)."""
    z2 = dz * dz
    z4 = z2 * z2
    z6 = z4 * z2
    return z2 * _E2, z4 * _E4, z6 * _E6, dz, (dz * _E3) * z2, (dz * _E5) * z4, (dz * _E7) * z6


@fused_block
def sinh_cosh_scaled(k, k2, coefficients):
    """``(sinh(k dz), cosh(k dz))`` for ``|k dz| <= SMALL_LIMIT`` from ``k``, ``k2 = k^2`` and the
    :func:`small_hyperbolic_coefficients` of ``dz`` (module docstring: Taylor to ``(k dz)^7``, ``(k dz)^6``)."""
    a1, a2, a3, b0, b1, b2, b3 = coefficients
    return k * (b0 + k2 * (b1 + k2 * (b2 + k2 * b3))), 1.0 + k2 * (a1 + k2 * (a2 + k2 * a3))


@fused_block
def sinh_cosh_small(d):
    """``(sinh d, cosh d)`` for ``|d| <= SMALL_LIMIT``: :func:`sinh_cosh_scaled` with ``k = 1``, ``dz = d``."""
    return sinh_cosh_scaled(1.0, 1.0, small_hyperbolic_coefficients(d))


@fused_block
def sin_cos(x):
    """``(sin x, cos x)``: :func:`sin_cos_reduced` within ``SIN_COS_LIMIT``, libm beyond (and for NaN, inf)."""
    if abs(x) <= SIN_COS_LIMIT:
        return sin_cos_reduced(x)
    return math.sin(x), math.cos(x)


@fused_block
def exp_pair(x):
    """``(e^x, e^-x)``: :func:`exp_pair_reduced` within ``EXP_LIMIT``, libm beyond (and for NaN, inf)."""
    if abs(x) <= EXP_LIMIT:
        return exp_pair_reduced(x)
    return math.exp(x), math.exp(-x)


@fused_kernel
def sin_cos_array(x, sin_out, cos_out):
    """:func:`sin_cos` of every element of ``x`` (for tests and microbenchmarks)."""
    for i in range(x.shape[0]):
        sin_out[i], cos_out[i] = sin_cos(x[i])


@fused_kernel
def exp_pair_array(x, exp_out, exp_neg_out):
    """:func:`exp_pair` of every element of ``x`` (for tests and microbenchmarks)."""
    for i in range(x.shape[0]):
        exp_out[i], exp_neg_out[i] = exp_pair(x[i])


@fused_kernel
def sin_cos_small_array(x, sin_out, cos_out):
    """:func:`sin_cos_small` of every element of ``x`` (for tests)."""
    for i in range(x.shape[0]):
        sin_out[i], cos_out[i] = sin_cos_small(x[i])


@fused_kernel
def sinh_cosh_small_array(x, sinh_out, cosh_out):
    """:func:`sinh_cosh_small` of every element of ``x`` (for tests)."""
    for i in range(x.shape[0]):
        sinh_out[i], cosh_out[i] = sinh_cosh_small(x[i])


@fused_kernel
def sin_cos_reduced_array(x, sin_out, cos_out):
    """:func:`sin_cos_reduced` of every element of ``x`` (no fallback: the vectorised loop)."""
    for i in range(x.shape[0]):
        sin_out[i], cos_out[i] = sin_cos_reduced(x[i])


@fused_kernel
def exp_pair_reduced_array(x, exp_out, exp_neg_out):
    """:func:`exp_pair_reduced` of every element of ``x`` (no fallback: the vectorised loop)."""
    for i in range(x.shape[0]):
        exp_out[i], exp_neg_out[i] = exp_pair_reduced(x[i])
