"""The water: what the fluid does at a world point and time (velocity and acceleration), paper Eqs. 2, 7.

One object, :class:`Flow`, describes the water of a run; its compiled form :class:`FlowData` travels in the
plant, and :func:`fluid_at` evaluates it for every body at its own world position inside every RK4 stage
(:func:`uvms.dynamics.passes.outward_pass`). The parts add up (superposition)::

    u_f(p, t) = u_table(t) + u_profile(depth(p)) + u_field(p, t) + u_waves(p, t)
    a_f(p, t) = du_f/dt + (u_f . grad) u_f          (the material acceleration of the water at p)

``du_f/dt`` is the local acceleration at the fixed point (the table's acceleration column, a field's slope in
time, the waves' ``du/dt``; a steady profile has none) and ``grad u_f`` the sum of the parts' velocity
gradients. The convective part is of second order in the wave steepness, so to first order ``a_f`` is linear
theory's ``du/dt``; it is kept because the pressure gradient of the water is ``rho (a_f - g)``, and without it a
neutrally buoyant body drifts down secularly (``k a^2 w^2 e^{2 k z} t^2 / 2``) instead of following the water
particle (``docs/flow.md``). A uniform table has no gradient: its ``a_f`` is its acceleration column.

- **uniform table** (today's current): ``u_table``, ``a_table`` given at ``times``, linear in between, held
  outside (one row: constant). Only this part: every body gets the same world vectors, and the algorithms
  take the pre-wave path bit for bit (``FlowData.uniform_only``).
- **depth profile**: ``velocity`` (K, 3) at ``depth`` (K,) [m, positive down from the mean surface], linear in
  depth, held beyond the ends.
- **gridded field**: ``velocity`` (nt, nz, ny, nx, 3) on world axes ``x, y, z`` and times ``t``: trilinear in
  space, linear in time, held at the time ends (there ``a = 0``). Outside the spatial box ``outside`` decides:
  ``"hold"`` (the nearest face's value: each coordinate clamped), ``"zero"`` (no field contribution) or
  ``"error"`` (the evaluation gives NaN and sets ``FlowData.status[0] = OUTSIDE``; the run stops and
  :func:`check_status` names the field). An axis of length 1 is constant along it.
- **linear (Airy) waves** (DNV-RP-C205 ch. 3; Faltinsen 1990, ch. 2), components ``i`` of amplitude ``a``,
  frequency ``w``, wave number ``k`` (finite depth: ``w^2 = g k tanh(k h)``), direction ``b`` and phase ``phi``,
  ``theta = k (x cos b + y sin b) - w t + phi``, ``zeta`` the height above the mean surface (world z up in
  ``enu``, down in ``ned``: the vertical world components change sign)::

      u_h  =  a w   cosh(k (zeta + h)) / sinh(k h) cos(theta)     (along b)
      u_z  =  a w   sinh(k (zeta + h)) / sinh(k h) sin(theta)     (up)
      du_h/dt = a w^2 cosh(k (zeta + h)) / sinh(k h) sin(theta)
      du_z/dt = -a w^2 sinh(k (zeta + h)) / sinh(k h) cos(theta)

  and their gradients (``d theta/dx = k cos b``, ``d theta/dy = k sin b``, ``d cosh(k (zeta + h))/d zeta =
  k sinh(k (zeta + h))``, zero along ``zeta`` where it is held),

  computed as ``cosh(k (zeta + h)) / sinh(k h) = (e^{k zeta} + e^{-2 k h} e^{-k zeta}) / (1 - e^{-2 k h})``
  (and the ``sinh`` ratio with a minus), one exponential pair per component, finite for every ``k h`` and
  ``e^{k zeta}`` in deep water (``h = inf``). The sums over the components are eleven dot products of fixed
  weights (:data:`UX` ...) with four terms per component (:func:`wave_terms_fast`: vectorised sine, cosine and
  exponential of :mod:`uvms.hydro.elementary`, when every phase is within their range; else
  :func:`wave_terms_libm`), ``docs/flow.md``, "Cost". Above the mean surface (``zeta > 0``, inside a crest) the
  kinematics are held at their ``zeta = 0`` values (constant extrapolation; linear theory says nothing there);
  below the seabed (``zeta < -h``) at the bed's.

  **Anchors**: a plant's bodies (:func:`with_body_anchors`) keep the terms (``ch cos theta``, ``ch sin theta``,
  ``sh / ch`` of every component) of their last full evaluation. While a body's point and time stay within
  :data:`NEAR` (1/32 rad) of that anchor in every phase and in ``k dzeta``, its sums come from the anchor's
  terms turned by the angle-addition formulas (:func:`wave_sums_near`: short series, no range reduction, sums
  in the same loop); otherwise a full evaluation at its point, placed :data:`LEAD` of the reach ahead in time,
  becomes the new anchor, and the body's sums are turned from it too. Both are exact formulas and agree to a few
  ulps (``tests/hydro/test_wave_kernels.py``); a point that is no body's is always evaluated in full.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from uvms.hydro.elementary import (SIN_COS_LIMIT, SMALL_LIMIT, exp_pair_reduced, sin_cos_reduced, sin_cos_small,
                                   sinh_cosh_scaled, small_hyperbolic_coefficients)
from uvms.jit import block, fused_kernel, kernel, sum_kernel
from uvms.lookup import last_at_or_before

HOLD, ZERO, ERROR = 0, 1, 2
"""A gridded field's outside policies (:attr:`FlowData.field_outside`)."""
OUTSIDE_NAMES = {"hold": HOLD, "zero": ZERO, "error": ERROR}
OUTSIDE = 1
""":attr:`FlowData.status` code: a point lay outside a field whose ``outside`` is ``"error"``."""
_NEGLIGIBLE = -700.0
"""``k zeta`` below which a wave component's kinematics (``<= e^{k zeta}``) are dropped (exp underflows)."""

WAVE_LANES = 8
"""The wave arrays' length is padded to a multiple of this (eight float64 lanes of an AVX-512 register)."""
WAVENUMBER, K_X, K_Y, OMEGA, PHASE, COS_B, SIN_B, AW, AW2, BED, NORM, K_SQUARED = range(12)
"""Rows of :attr:`FlowData.wave_table`: ``k``, ``k cos b``, ``k sin b``, ``w``, ``phi``, ``cos b``, ``sin b``,
``a w``, ``a w^2``, ``e^{-2 k h}`` (0 in deep water), ``1 / (1 - e^{-2 k h})``, ``k^2``."""
WAVE_ROWS = 12
CH_C, CH_S, SH_S, SH_C = range(4)
"""Rows of :attr:`FlowData.wave_work`: ``ch cos(theta)``, ``ch sin(theta)``, ``sh sin(theta)``, ``sh cos(theta)``
with ``ch = cosh(k (zeta + h)) / sinh(k h)``, ``sh = sinh(k (zeta + h)) / sinh(k h)``."""
WORK_ROWS = 4
ANCHOR_C, ANCHOR_S, RATIO = range(3)
"""Rows of a body's anchor terms (:attr:`FlowData.wave_anchor` ``[i]``) and of :attr:`FlowData.wave_point`:
each component's ``ch cos(theta)``, ``ch sin(theta)`` and ``sh / ch`` at one point and time (the ratio 0 for a
component dropped below the negligible depth, whose ``ch`` is 0)."""
TERM_ROWS = 3
X, Y, ZETA, T = range(4)
"""Columns of :attr:`FlowData.wave_anchor_at`: the anchor's world ``x``, ``y``, height ``zeta`` (held within
``[-h, 0]``) and time ``t``."""
NEAR = SMALL_LIMIT
"""How far (in phase and in ``k`` times height) a body's point may lie from its anchor for its terms to be the
anchor's turned by the angle-addition formulas (:func:`wave_sums_near`), in rad."""
LEAD = 0.75
"""A new anchor is placed this fraction of :data:`NEAR` ahead in time (``LEAD NEAR / max w`` seconds after the
point that asked for it, :func:`anchor_delta`): time runs forward, so it serves the body on both sides of its
own time, about twice as long as one placed at the point."""
UX, UY, AX, AY, UZ, AZ, PCC, PCS, PSS, QC, QS = range(11)
"""The wave sums (:attr:`FlowData.wave_sums`; ``P = a w k ch sin(theta)``, ``Q = a w k sh cos(theta)``)::

    UX = sum a w cos b ch cos    UY = sum a w sin b ch cos    UZ = sum a w sh sin      AZ = -sum a w^2 sh cos
    AX = sum a w^2 cos b ch sin  AY = sum a w^2 sin b ch sin
    PCC = sum P cos^2 b   PCS = sum P cos b sin b   PSS = sum P sin^2 b
    QC = sum Q cos b      QS = sum Q sin b

each ``sum_i weight_i work_i``: the weight a row of :attr:`FlowData.wave_weights`, the work row ``CH_S`` for
the ``sin`` sums of ``ch``, and so on (:func:`wave_sums`). ``du_z/dzeta = sum P = PCC + PSS`` (the flow is
incompressible: ``cos^2 b + sin^2 b = 1``) is not a sum of its own."""
N_SUMS = 11
REACH_KX, REACH_KY, REACH_PHASE, REACH_OMEGA, REACH_K = range(5)
"""Entries of :attr:`FlowData.wave_reach`: max ``|k cos b|``, max ``|k sin b|``, max ``|phi|``, max ``w``, max
``k`` over the components (bounds on the phases and their changes)."""
REACH_SIZE = 5


class FlowData(NamedTuple):
    """The compiled form of a :class:`Flow` (one numba type for every kind: absent parts are empty arrays).
    World frame of the model's convention, SI units."""

    uniform_only: bool          # no profile, field or waves: the algorithms' uniform path
    times: np.ndarray           # (T,) [s] uniform table
    velocity: np.ndarray        # (T, 3) [m/s]
    acceleration: np.ndarray    # (T, 3) [m/s^2]
    profile_depth: np.ndarray   # (K,) [m] positive down from the mean surface, increasing (K = 0: none)
    profile_velocity: np.ndarray  # (K, 3) [m/s]
    profile_slope: np.ndarray   # (K, 3) [1/s] d velocity / d depth of the segment below each depth (last row 0)
    field_x: np.ndarray         # (nx,) [m] world (nx = 0: no field)
    field_y: np.ndarray         # (ny,)
    field_z: np.ndarray         # (nz,)
    field_t: np.ndarray         # (nt,) [s]
    field_velocity: np.ndarray  # (nt, nz, ny, nx, 3) [m/s]
    field_outside: int          # HOLD, ZERO, ERROR
    wave_table: np.ndarray      # (WAVE_ROWS, M) each component's constants (rows WAVENUMBER ... NORM below; M = 0: no
                                #   waves; M a multiple of WAVE_LANES, the padding components of zero amplitude)
    wave_weights: np.ndarray    # (N_SUMS, M) the weights of the wave sums (rows UX ... QS below)
    wave_reach: np.ndarray      # (REACH_SIZE,) max |k cos b|, max |k sin b|, max |phi|, max w, max k: bounds
    wave_work: np.ndarray       # (WORK_ROWS, M) scratch: each component's depth factor times cos, sin theta
    wave_point: np.ndarray      # (TERM_ROWS, M) scratch: the terms at a point that is no body's
    wave_anchor: np.ndarray     # (B, TERM_ROWS, M) each body's terms at its anchor (B = 0: no anchors)
    wave_anchor_at: np.ndarray  # (B, 4) each anchor's x, y, zeta, t (NaN: none yet)
    wave_deltas: np.ndarray     # (B, 4) scratch: each body's point and time less its anchor's (columns X ... T)
    wave_body_sums: np.ndarray  # (B, N_SUMS) each body's wave sums at its point (bodies_waves)
    wave_sums: np.ndarray       # (N_SUMS,) scratch: the wave sums at a point that is no body's
    water_depth: float          # h [m] (inf: deep)
    surface: float              # world z of the mean free surface [m]
    up: float                   # +1: world z up (enu), -1: down (ned)
    status: np.ndarray          # (1,) int64: 0, or OUTSIDE once a point lay outside an "error" field

    # status, wave_work, wave_point, wave_sums and the anchors are written during an evaluation: one FlowData
    # per thread (Flow.compiled makes a fresh one; every run compiles its own, and every plant gets fresh
    # scratch and anchors for its bodies, with_body_anchors).


# ------------------------------------------------------------------------------------------- kernels


@kernel
def interpolate(table_t, table_v, t, out):
    """Linear interpolation of a (K, 3) table at ``t``, held constant outside its range."""
    K = table_t.shape[0]
    if K == 1 or t <= table_t[0]:
        for k in range(3):
            out[k] = table_v[0, k]
        return
    if t >= table_t[K - 1]:
        for k in range(3):
            out[k] = table_v[K - 1, k]
        return
    lo = last_at_or_before(table_t, t, K - 1)
    hi = lo + 1
    s = (t - table_t[lo]) / (table_t[hi] - table_t[lo])
    for k in range(3):
        out[k] = (1.0 - s) * table_v[lo, k] + s * table_v[hi, k]


@block
def uniform_at(flow, t, v_out, a_out):
    """The uniform table's velocity and acceleration at ``t`` into ``v_out``, ``a_out`` (world, (3,))."""
    interpolate(flow.times, flow.velocity, t, v_out)
    interpolate(flow.times, flow.acceleration, t, a_out)


@block
def bracket(axis, value):
    """``(lo, s, inside)``: ``value`` lies at ``(1 - s) axis[lo] + s axis[lo + 1]`` (``s`` in [0, 1], clamped;
    ``lo + 1`` stays in range); ``inside`` is whether it lies within ``[axis[0], axis[-1]]``. An axis of one
    value gives ``(0, 0.0, True)`` (constant along it)."""
    n = axis.shape[0]
    if n == 1:
        return 0, 0.0, True
    if value <= axis[0]:
        return 0, 0.0, value == axis[0]
    if value >= axis[n - 1]:
        return n - 2, 1.0, value == axis[n - 1]
    lo = last_at_or_before(axis, value, n - 1)
    hi = lo + 1
    return lo, (value - axis[lo]) / (axis[hi] - axis[lo]), True


@block
def profile_add(flow, point, v_out, grad):
    """``v_out += u_profile(depth)``, ``depth = up (surface - z)``: linear in depth, held beyond the ends;
    ``grad[:, 2] += du/dz`` (the segment's slope inside and at the ends themselves, zero where held).

    Inside segment ``j``: ``u = V_j + (depth - d_j) slope_j`` with ``slope_j = (V_{j+1} - V_j) / (d_{j+1} - d_j)``
    (:attr:`FlowData.profile_slope`, computed when the flow is compiled: no division per evaluation) and
    ``du/dz = -up slope_j``."""
    d = flow.profile_depth
    V = flow.profile_velocity
    n = d.shape[0]
    depth = flow.up * (flow.surface - point[2])
    if n == 1 or depth < d[0] or depth > d[n - 1]:           # held (one depth: constant)
        end = 0 if n == 1 or depth < d[0] else n - 1
        for k in range(3):
            v_out[k] += V[end, k]
        return
    lo = last_at_or_before(d, depth, n - 1)
    slope = flow.profile_slope
    delta = depth - d[lo]
    for k in range(3):
        v_out[k] += V[lo, k] + delta * slope[lo, k]
        grad[k, 2] -= flow.up * slope[lo, k]


@block
def _trilinear(V, it, ix, sx, iy, sy, iz, sz, k):
    """Trilinear interpolation of ``V[it, :, :, :, k]`` at cell ``(iz, iy, ix)`` with weights ``sz, sy, sx``
    (the upper index clamped to the axis for an axis of one value)."""
    nz, ny, nx = V.shape[1], V.shape[2], V.shape[3]
    jx = ix + 1 if nx > 1 else ix
    jy = iy + 1 if ny > 1 else iy
    jz = iz + 1 if nz > 1 else iz
    c00 = (1.0 - sx) * V[it, iz, iy, ix, k] + sx * V[it, iz, iy, jx, k]
    c10 = (1.0 - sx) * V[it, iz, jy, ix, k] + sx * V[it, iz, jy, jx, k]
    c01 = (1.0 - sx) * V[it, jz, iy, ix, k] + sx * V[it, jz, iy, jx, k]
    c11 = (1.0 - sx) * V[it, jz, jy, ix, k] + sx * V[it, jz, jy, jx, k]
    c0 = (1.0 - sy) * c00 + sy * c10
    c1 = (1.0 - sy) * c01 + sy * c11
    return (1.0 - sz) * c0 + sz * c1


@block
def _gradient(V, it, ix, sx, iy, sy, iz, sz, k, axis, h):
    """d/d(axis) of the trilinear interpolant of ``V[it, ..., k]`` in the cell (``h`` the cell's width along
    ``axis``: 0 for an axis of one value or a held coordinate, then the derivative is 0)."""
    if h == 0.0:
        return 0.0
    if axis == 0:
        return (_trilinear(V, it, ix, 1.0, iy, sy, iz, sz, k) - _trilinear(V, it, ix, 0.0, iy, sy, iz, sz, k)) / h
    if axis == 1:
        return (_trilinear(V, it, ix, sx, iy, 1.0, iz, sz, k) - _trilinear(V, it, ix, sx, iy, 0.0, iz, sz, k)) / h
    return (_trilinear(V, it, ix, sx, iy, sy, iz, 1.0, k) - _trilinear(V, it, ix, sx, iy, sy, iz, 0.0, k)) / h


@block
def _width(axis, lo, inside):
    """The cell width along an axis at ``lo`` (0 for an axis of one value, or outside it: held)."""
    if axis.shape[0] == 1 or not inside:
        return 0.0
    return axis[lo + 1] - axis[lo]


@kernel
def field_add(flow, t, point, v_out, a_out, grad):
    """``v_out += u_field``, ``a_out += du_field/dt``, ``grad += grad u_field`` at ``point`` and ``t`` (module
    docstring: trilinear in space, linear in time, the outside policy). A kernel of its own, not inlined: its
    code is long and :func:`local_parts_add` is inlined into every dynamics algorithm."""
    ix, sx, in_x = bracket(flow.field_x, point[0])
    iy, sy, in_y = bracket(flow.field_y, point[1])
    iz, sz, in_z = bracket(flow.field_z, point[2])
    if not (in_x and in_y and in_z):
        if flow.field_outside == ZERO:
            return
        if flow.field_outside == ERROR:
            flow.status[0] = OUTSIDE
            for k in range(3):
                v_out[k] = np.nan
                a_out[k] = np.nan
            return
    V = flow.field_velocity
    nt = flow.field_t.shape[0]
    it, st, in_t = bracket(flow.field_t, t)
    jt = it + 1 if nt > 1 else it
    moving = nt > 1 and in_t
    inv_dt = 1.0 / (flow.field_t[jt] - flow.field_t[it]) if moving else 0.0
    hx = _width(flow.field_x, ix, in_x)
    hy = _width(flow.field_y, iy, in_y)
    hz = _width(flow.field_z, iz, in_z)
    for k in range(3):
        v0 = _trilinear(V, it, ix, sx, iy, sy, iz, sz, k)
        v1 = _trilinear(V, jt, ix, sx, iy, sy, iz, sz, k)
        v_out[k] += (1.0 - st) * v0 + st * v1
        if moving:
            a_out[k] += (v1 - v0) * inv_dt
        grad[k, 0] += (1.0 - st) * _gradient(V, it, ix, sx, iy, sy, iz, sz, k, 0, hx) \
            + st * _gradient(V, jt, ix, sx, iy, sy, iz, sz, k, 0, hx)
        grad[k, 1] += (1.0 - st) * _gradient(V, it, ix, sx, iy, sy, iz, sz, k, 1, hy) \
            + st * _gradient(V, jt, ix, sx, iy, sy, iz, sz, k, 1, hy)
        grad[k, 2] += (1.0 - st) * _gradient(V, it, ix, sx, iy, sy, iz, sz, k, 2, hz) \
            + st * _gradient(V, jt, ix, sx, iy, sy, iz, sz, k, 2, hz)


@fused_kernel
def wave_terms_fast(table, work, terms, x, y, zeta, t):
    """Each component's depth factors times ``cos theta`` and ``sin theta`` into ``work`` (rows ``CH_C`` ...
    ``SH_C``), and ``ch cos theta``, ``ch sin theta`` and ``sh / ch`` into ``terms`` (rows ``ANCHOR_C`` ...
    ``RATIO``), at ``(x, y)`` and height ``zeta`` (already held within ``[-h, 0]``), time ``t``; with the
    vectorisable :mod:`uvms.hydro.elementary` functions, for ``|theta| <= SIN_COS_LIMIT`` (the caller checks).

    ``cosh(k (zeta + h)) / sinh(k h) = (e^{k zeta} + e^{-2 k h} e^{-k zeta}) / (1 - e^{-2 k h})`` (and ``sinh``
    with a minus): one exponential pair per component; ``theta = x k cos b + y k sin b + (phi - w t)``."""
    for i in range(table.shape[1]):
        kz = table[WAVENUMBER, i] * zeta
        live = kz >= _NEGLIGIBLE
        e_up, e_down = exp_pair_reduced(kz if live else _NEGLIGIBLE)     # e^{k zeta}, e^{-k zeta}
        bed = table[BED, i] * e_down                                    # e^{-k (zeta + 2 h)}
        ch = (e_up + bed) * table[NORM, i] if live else 0.0
        sh = (e_up - bed) * table[NORM, i] if live else 0.0
        theta = x * table[K_X, i] + y * table[K_Y, i] + (table[PHASE, i] - table[OMEGA, i] * t)
        s, c = sin_cos_reduced(theta)
        ch_c = ch * c
        ch_s = ch * s
        terms[ANCHOR_C, i] = ch_c
        terms[ANCHOR_S, i] = ch_s
        terms[RATIO, i] = sh / ch if live else 0.0
        work[CH_C, i] = ch_c
        work[CH_S, i] = ch_s
        work[SH_S, i] = sh * s
        work[SH_C, i] = sh * c


@kernel
def wave_terms_libm(table, work, terms, x, y, zeta, t):
    """:func:`wave_terms_fast` with libm's ``cos``, ``sin``, ``exp`` (any argument: the fallback and the
    reference), ``theta = k (x cos b + y sin b) - w t + phi``."""
    for i in range(table.shape[1]):
        k = table[WAVENUMBER, i]
        kz = k * zeta
        theta = k * (x * table[COS_B, i] + y * table[SIN_B, i]) - table[OMEGA, i] * t + table[PHASE, i]
        c = math.cos(theta)
        s = math.sin(theta)
        ch = sh = ratio = 0.0
        if kz >= _NEGLIGIBLE:
            e = math.exp(kz)
            bed = table[BED, i] / e              # e^{-k (zeta + 2 h)}
            ch = (e + bed) * table[NORM, i]      # cosh(k (zeta + h)) / sinh(k h)
            sh = (e - bed) * table[NORM, i]      # sinh(k (zeta + h)) / sinh(k h)
            ratio = sh / ch
        ch_c = ch * c
        ch_s = ch * s
        terms[ANCHOR_C, i] = ch_c
        terms[ANCHOR_S, i] = ch_s
        terms[RATIO, i] = ratio
        work[CH_C, i] = ch_c
        work[CH_S, i] = ch_s
        work[SH_S, i] = sh * s
        work[SH_C, i] = sh * c


@sum_kernel
def wave_sums_near(table, weights, anchors, deltas, out, count):
    """The wave sums ``out[b]`` (:func:`wave_sums`) of bodies ``b < count``, each at the point ``(dx, dy)`` [m],
    height ``dzeta`` [m] and time ``dt`` [s] (``deltas[b]``, columns ``X`` ... ``T``) from its anchor, whose terms
    are ``anchors[b]`` (rows ``ANCHOR_C`` ... ``RATIO``), for ``|d theta| <= NEAR`` and ``k |dzeta| <= NEAR`` (the
    caller checks): each component's terms turned by the angle-addition formulas (exact)::

        d theta = k cos b dx + k sin b dy - w dt
        ch0 e^{i (theta + d theta)} = ch0 e^{i theta} (cos d theta + i sin d theta)     (ch0 = ch(zeta))
        ch(zeta + dzeta) / ch0 = cosh(k dzeta) + (sh0 / ch0) sinh(k dzeta)
        sh(zeta + dzeta) / ch0 = (sh0 / ch0) cosh(k dzeta) + sinh(k dzeta)

    (``ch = cosh(k (zeta + h)) / sinh(k h)``, ``sh`` with ``sinh``; the anchor holds ``ch0 cos theta``, ``ch0 sin
    theta`` and ``sh0 / ch0``, so that the four products of the sums are the two ratios times the turned
    ``ch0 e^{i theta}``: 39 operations per component), the small angles' functions from their
    short series (:func:`uvms.hydro.elementary.sin_cos_small`; the hyperbolic pair as polynomials in ``k^2``
    whose coefficients depend on ``dzeta`` alone, :func:`~uvms.hydro.elementary.sinh_cosh_scaled`): no range
    reduction, so the loop may be reassociated (:data:`uvms.jit.sum_kernel`; the series' terms fall fast,
    nothing cancels) and the sums taken in the same loop. Within a few ulps of a full evaluation at the point
    (``tests/hydro/test_wave_kernels.py``). One call for all the bodies of a plant (:func:`bodies_waves`): one
    call's overhead per stage, and the components' constants stay in cache from body to body (``docs/flow.md``,
    "Cost")."""
    for b in range(count):
        anchor = anchors[b]
        dx = deltas[b, X]
        dy = deltas[b, Y]
        dzeta = deltas[b, ZETA]
        dt = deltas[b, T]
        vertical = small_hyperbolic_coefficients(dzeta)
        ux = uy = ax = ay = uz = az = p_cc = p_cs = p_ss = q_c = q_s = 0.0
        for i in range(table.shape[1]):
            d = dx * table[K_X, i] + dy * table[K_Y, i] - dt * table[OMEGA, i]
            sd, cd = sin_cos_small(d)
            se, ce = sinh_cosh_scaled(table[WAVENUMBER, i], table[K_SQUARED, i], vertical)
            re0 = anchor[ANCHOR_C, i]
            im0 = anchor[ANCHOR_S, i]
            rho = anchor[RATIO, i]
            re = re0 * cd - im0 * sd                 # ch0 cos(theta + d theta)
            im = im0 * cd + re0 * sd                 # ch0 sin(theta + d theta)
            g = ce + rho * se                        # ch(zeta + dzeta) / ch0
            f = rho * ce + se                        # sh(zeta + dzeta) / ch0
            ch_c = g * re
            ch_s = g * im
            sh_s = f * im
            sh_c = f * re
            ux += weights[UX, i] * ch_c
            uy += weights[UY, i] * ch_c
            ax += weights[AX, i] * ch_s
            ay += weights[AY, i] * ch_s
            uz += weights[UZ, i] * sh_s
            az += weights[AZ, i] * sh_c
            p_cc += weights[PCC, i] * ch_s
            p_cs += weights[PCS, i] * ch_s
            p_ss += weights[PSS, i] * ch_s
            q_c += weights[QC, i] * sh_c
            q_s += weights[QS, i] * sh_c
        o = out[b]
        o[UX] = ux
        o[UY] = uy
        o[AX] = ax
        o[AY] = ay
        o[UZ] = uz
        o[AZ] = az
        o[PCC] = p_cc
        o[PCS] = p_cs
        o[PSS] = p_ss
        o[QC] = q_c
        o[QS] = q_s


@sum_kernel
def wave_sums(weights, work, out):
    """The wave sums ``out[j] = sum_i weights[j, i] work[row(j), i]`` (rows ``UX`` ... ``QS``: the module
    constants' docstring), as dot products over the components (reassociated: vectorised)."""
    ux = uy = ax = ay = uz = az = p_cc = p_cs = p_ss = q_c = q_s = 0.0
    for i in range(work.shape[1]):
        ch_c = work[CH_C, i]
        ch_s = work[CH_S, i]
        sh_s = work[SH_S, i]
        sh_c = work[SH_C, i]
        ux += weights[UX, i] * ch_c
        uy += weights[UY, i] * ch_c
        ax += weights[AX, i] * ch_s
        ay += weights[AY, i] * ch_s
        uz += weights[UZ, i] * sh_s
        az += weights[AZ, i] * sh_c
        p_cc += weights[PCC, i] * ch_s
        p_cs += weights[PCS, i] * ch_s
        p_ss += weights[PSS, i] * ch_s
        q_c += weights[QC, i] * sh_c
        q_s += weights[QS, i] * sh_c
    out[UX] = ux
    out[UY] = uy
    out[AX] = ax
    out[AY] = ay
    out[UZ] = uz
    out[AZ] = az
    out[PCC] = p_cc
    out[PCS] = p_cs
    out[PSS] = p_ss
    out[QC] = q_c
    out[QS] = q_s


@block
def wave_height(flow, point):
    """``(zeta, held)``: the height of the world ``point`` above the mean surface, held within ``[-h, 0]``, and
    ``d zeta / d(height)`` there (1 inside, 0 where held)."""
    zeta = flow.up * (point[2] - flow.surface)
    held = 1.0
    if zeta > 0.0:
        zeta = 0.0
        held = 0.0
    if zeta < -flow.water_depth:
        zeta = -flow.water_depth
        held = 0.0
    return zeta, held


@block
def wave_terms(flow, terms, x, y, zeta, t):
    """Every component's terms at ``(x, y)``, height ``zeta`` and time ``t`` into ``flow.wave_work`` and
    ``terms``: :func:`wave_terms_fast` when every phase is within the polynomials' range (``|theta| <= |x|
    max|k cos b| + |y| max|k sin b| + max|phi| + max w |t| <= SIN_COS_LIMIT``), else (and for a non-finite point)
    :func:`wave_terms_libm`."""
    reach = flow.wave_reach
    bound = abs(x) * reach[REACH_KX] + abs(y) * reach[REACH_KY] + reach[REACH_PHASE] + reach[REACH_OMEGA] * abs(t)
    if bound <= SIN_COS_LIMIT and zeta == zeta:
        wave_terms_fast(flow.wave_table, flow.wave_work, terms, x, y, zeta, t)
    else:
        wave_terms_libm(flow.wave_table, flow.wave_work, terms, x, y, zeta, t)


@block
def anchor_delta(flow, body, x, y, zeta, t):
    """``flow.wave_deltas[body]``: body ``body``'s point ``(x, y)``, height ``zeta`` and time ``t`` less its
    anchor's, once the anchor is within :data:`NEAR` of it in every component's phase (``|dx| max|k cos b| +
    |dy| max|k sin b| + |dt| max w``) and in ``k |dzeta|``. Else the body takes a new anchor first: a full
    evaluation (:func:`wave_terms`) at its point, :data:`LEAD` ``NEAR / max w`` seconds ahead in time (its delta
    is then that lead, back in time)."""
    at = flow.wave_anchor_at[body]
    delta = flow.wave_deltas[body]
    delta[X] = x - at[X]
    delta[Y] = y - at[Y]
    delta[ZETA] = zeta - at[ZETA]
    delta[T] = t - at[T]
    reach = flow.wave_reach
    phase = abs(delta[X]) * reach[REACH_KX] + abs(delta[Y]) * reach[REACH_KY] + abs(delta[T]) * reach[REACH_OMEGA]
    if not (phase <= NEAR and abs(delta[ZETA]) * reach[REACH_K] <= NEAR):      # (true for a NaN: no anchor yet)
        lead = LEAD * NEAR / reach[REACH_OMEGA]
        wave_terms(flow, flow.wave_anchor[body], x, y, zeta, t + lead)
        at[X] = x
        at[Y] = y
        at[ZETA] = zeta
        at[T] = t + lead
        delta[X] = delta[Y] = delta[ZETA] = 0.0
        delta[T] = -lead


@block
def bodies_waves(flow, points, t, count):
    """The wave sums of bodies ``0 ... count - 1`` at their world ``points[b]`` and time ``t`` into
    ``flow.wave_body_sums[b]``: each body's delta from its anchor (:func:`anchor_delta`, renewing it where
    needed), then one :func:`wave_sums_near` for all of them. Bodies beyond the anchors' count, and flows
    without waves, are left alone (:func:`waves_add` evaluates those in full)."""
    n = min(count, flow.wave_anchor.shape[0])
    if n == 0:
        return
    for b in range(n):
        zeta, _ = wave_height(flow, points[b])
        anchor_delta(flow, b, points[b, 0], points[b, 1], zeta, t)
    wave_sums_near(flow.wave_table, flow.wave_weights, flow.wave_anchor, flow.wave_deltas, flow.wave_body_sums, n)


@block
def waves_add(flow, t, point, body, v_out, a_out, grad):
    """``v_out += u_waves``, ``a_out += du_waves/dt``, ``grad += grad u_waves``: the linear (Airy) kinematics of
    every component at ``point`` and ``t`` (module docstring), held at the mean surface above it and at the bed
    below it (there the vertical derivatives are zero).

    The sums are body ``body``'s, ``flow.wave_body_sums[body]``, when ``point`` is that body's and it has an
    anchor (``0 <= body <`` the anchors' count): the caller has evaluated them with :func:`bodies_waves` at
    ``point`` and ``t``. Else (``body = -1``) they come from the components' terms there (:func:`wave_terms`,
    :func:`wave_sums`)."""
    up = flow.up
    zeta, held = wave_height(flow, point)
    if 0 <= body < flow.wave_anchor.shape[0]:
        S = flow.wave_body_sums[body]
    else:
        S = flow.wave_sums
        wave_terms(flow, flow.wave_point, point[0], point[1], zeta, t)
        wave_sums(flow.wave_weights, flow.wave_work, S)
    v_out[0] += S[UX]
    v_out[1] += S[UY]
    v_out[2] += up * S[UZ]
    a_out[0] += S[AX]
    a_out[1] += S[AY]
    a_out[2] += up * S[AZ]
    vz = up * held                               # d zeta / dz where it is not held
    grad[0, 0] -= S[PCC]
    grad[0, 1] -= S[PCS]
    grad[0, 2] += S[QC] * vz
    grad[1, 0] -= S[PCS]
    grad[1, 1] -= S[PSS]
    grad[1, 2] += S[QS] * vz
    grad[2, 0] += up * S[QC]
    grad[2, 1] += up * S[QS]
    grad[2, 2] += up * vz * (S[PCC] + S[PSS])        # du_z/dzeta = sum a w k ch sin theta


@block
def local_parts_add(flow, t, point, body, v_out, a_out, grad):
    """The parts that vary in space at the world ``point`` (3,) and time ``t``, added to ``v_out``, ``a_out``
    (world, (3,); holding the uniform part, :func:`uniform_at`): profile, field and waves, then the convective
    acceleration ``a_out += (grad u) u`` (module docstring); ``grad`` (3, 3) is scratch, left holding
    ``grad[r, c] = du_r/dx_c``. ``body`` is the index of the body whose point it is, its wave sums evaluated
    with :func:`bodies_waves` at ``point`` and ``t`` before, or -1 (waves evaluated here, :func:`waves_add`)."""
    for r in range(3):
        for c in range(3):
            grad[r, c] = 0.0
    if flow.profile_depth.shape[0] > 0:
        profile_add(flow, point, v_out, grad)
    if flow.field_x.shape[0] > 0:
        field_add(flow, t, point, v_out, a_out, grad)
    if flow.wave_table.shape[1] > 0:
        waves_add(flow, t, point, body, v_out, a_out, grad)
    for r in range(3):
        a_out[r] += grad[r, 0] * v_out[0] + grad[r, 1] * v_out[1] + grad[r, 2] * v_out[2]


@kernel
def fluid_at(flow, t, point, v_out, a_out, grad):
    """The water's velocity ``v_out`` [m/s] and material acceleration ``a_out`` [m/s^2] (world, (3,)) at the
    world ``point`` (3,) and time ``t``: the sum of the flow's parts, then ``a_out += (grad u) u``
    (module docstring); ``grad`` (3, 3) is scratch, left holding ``grad[r, c] = du_r/dx_c``."""
    uniform_at(flow, t, v_out, a_out)
    local_parts_add(flow, t, point, -1, v_out, a_out, grad)


@kernel
def fluid_at_points(flow, t, points, v_out, a_out, grad):
    """:func:`fluid_at` at each row of ``points`` (P, 3) into the rows of ``v_out``, ``a_out`` (P, 3) and
    ``grad`` (P, 3, 3)."""
    for p in range(points.shape[0]):
        fluid_at(flow, t, points[p], v_out[p], a_out[p], grad[p])


# --------------------------------------------------------------------------------------- the Python side


def _array(value, name: str, shape_tail: tuple, *, increasing: bool = False, min_length: int = 1) -> np.ndarray:
    """A fresh C-ordered float64 array of ``value`` with trailing shape ``shape_tail``, finite (else a one-line
    :class:`~uvms.errors.UvmsInputError` naming ``name``)."""
    from uvms.checks import fail, show

    try:
        a = np.array(value, dtype=float, order="C")
    except (TypeError, ValueError):
        raise fail(name, f"expected numbers, got {show(value)}") from None
    if a.ndim != 1 + len(shape_tail) or a.shape[1:] != shape_tail or a.shape[0] < min_length:
        tail = "".join(f", {d}" for d in shape_tail)
        raise fail(name, f"expected an array of shape (N{tail}) with N >= {min_length}, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise fail(name, "expected finite numbers, found NaN or infinity")
    if increasing and np.any(np.diff(a) <= 0.0):
        raise fail(name, "expected strictly increasing values")
    return a


def _empty(*tail: int) -> np.ndarray:
    return np.zeros((0,) + tail)


class Flow:
    """The water of a run (module docstring): a uniform table plus optional depth profile, gridded field and
    linear waves, superposed. World frame of the model's convention, SI units.

    Args:
        times, velocity, acceleration: the uniform table, (T,) [s], (T, 3) [m/s], (T, 3) [m/s^2]; ``times``
            strictly increasing (one row: constant).
        profile: an object with ``depth`` (K,) [m, positive down, strictly increasing] and ``velocity`` (K, 3)
            (e.g. :class:`uvms.hydro.currents.CurrentProfile`), or ``None``.
        field: an object with ``x, y, z, t`` (each strictly increasing, length 1 allowed), ``velocity``
            (nt, nz, ny, nx, 3) and ``outside`` in ``{"hold", "zero", "error"}``, or ``None``.
        waves: an object with ``amplitude, omega, wavenumber, direction, phase`` (each (M,)) and
            ``water_depth`` (float, ``math.inf`` = deep) (e.g. :class:`uvms.hydro.waves.WaveComponents`), or
            ``None``.
        surface: world z of the mean free surface [m].
    """

    def __init__(self, times, velocity, acceleration, profile=None, field=None, waves=None,
                 surface: float = 0.0) -> None:
        from uvms.checks import fail, number

        self.times = _array(times, "flow.times", (), increasing=True)
        self.velocity = _array(velocity, "flow.velocity", (3,))
        self.acceleration = _array(acceleration, "flow.acceleration", (3,))
        if not self.times.shape[0] == self.velocity.shape[0] == self.acceleration.shape[0]:
            raise fail("flow.velocity", f"expected one row per time ({self.times.shape[0]}), got "
                                        f"{self.velocity.shape[0]} velocities and {self.acceleration.shape[0]} "
                                        "accelerations")
        self.surface = number(surface, "flow.surface", unit="m")
        self.profile = None if profile is None else _checked_profile(profile)
        self.field = None if field is None else _checked_field(field)
        self.waves = None if waves is None else _checked_waves(waves)

    @classmethod
    def constant(cls, velocity=(0.0, 0.0, 0.0), acceleration=(0.0, 0.0, 0.0), **parts) -> "Flow":
        """A flow whose uniform part is the constant ``velocity`` and ``acceleration`` (world, (3,))."""
        return cls([0.0], [velocity], [acceleration], **parts)

    @classmethod
    def of_model(cls, model, **parts) -> "Flow":
        """The model's own environment (``model.current``, ``model.fluid_acceleration``) as the uniform part."""
        return cls.constant(model.current, model.fluid_acceleration, **parts)

    def __repr__(self) -> str:
        parts = [f"table of {self.times.shape[0]}"]
        if self.profile is not None:
            parts.append(f"profile of {self.profile[0].shape[0]} depths")
        if self.field is not None:
            parts.append(f"field {self.field[4].shape[:4]} (t, z, y, x)")
        if self.waves is not None:
            parts.append(f"{self.waves[0].shape[0]} wave components")
        return f"Flow({', '.join(parts)})"

    def compiled(self, convention: str = "ned") -> FlowData:
        """The :class:`FlowData` of this flow in a world of ``convention`` (``"ned"``: z down, ``"enu"``: z up)."""
        from uvms.frames import check_frame

        up = 1.0 if check_frame(convention, "convention") == "enu" else -1.0
        depth, pv = self.profile if self.profile is not None else (_empty(), _empty(3))
        fx, fy, fz, ft, fv, outside = self.field if self.field is not None else (
            _empty(), _empty(), _empty(), _empty(), np.zeros((0, 0, 0, 0, 3)), HOLD)
        if self.waves is not None:
            a, w, k, b, phase, h = self.waves
        else:
            a, w, k, b, phase, h = _empty(), _empty(), _empty(), _empty(), _empty(), math.inf
        table, weights, reach = _wave_arrays(a, w, k, b, phase, h)
        return FlowData(
            uniform_only=self.profile is None and self.field is None and self.waves is None,
            times=self.times.copy(), velocity=self.velocity.copy(), acceleration=self.acceleration.copy(),
            profile_depth=depth.copy(), profile_velocity=pv.copy(), profile_slope=_profile_slope(depth, pv),
            field_x=fx.copy(), field_y=fy.copy(),
            field_z=fz.copy(), field_t=ft.copy(), field_velocity=fv.copy(), field_outside=int(outside),
            wave_table=table, wave_weights=weights, wave_reach=reach, wave_work=np.zeros((WORK_ROWS, table.shape[1])),
            wave_point=np.zeros((TERM_ROWS, table.shape[1])), wave_anchor=np.zeros((0, TERM_ROWS, table.shape[1])),
            wave_anchor_at=np.zeros((0, 4)), wave_deltas=np.zeros((0, 4)), wave_body_sums=np.zeros((0, N_SUMS)),
            wave_sums=np.zeros(N_SUMS), water_depth=float(h),
            surface=float(self.surface), up=up, status=np.zeros(1, dtype=np.int64))

    def at(self, t: float, points, convention: str = "ned") -> tuple[np.ndarray, np.ndarray]:
        """The velocity and material acceleration (each (P, 3), world) at the world ``points`` (P, 3) and time
        ``t`` [s] (:func:`fluid_at`; for drawing, records and tests). :meth:`kinematics` adds the gradient."""
        v, a, _ = self.kinematics(t, points, convention)
        return v, a

    def kinematics(self, t: float, points, convention: str = "ned") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(velocity (P, 3), material acceleration (P, 3), velocity gradient (P, 3, 3))`` at the world
        ``points`` and time ``t`` [s]; ``gradient[p, r, c] = du_r/dx_c``."""
        from uvms.checks import number

        t = number(t, "t", unit="s")
        points = _array(np.atleast_2d(points), "points", (3,))
        flow = self.compiled(convention)
        v = np.zeros_like(points)
        a = np.zeros_like(points)
        grad = np.zeros((points.shape[0], 3, 3))
        fluid_at_points(flow, t, points, v, a, grad)
        check_status(flow)
        return v, a, grad


def _profile_slope(depth: np.ndarray, velocity: np.ndarray) -> np.ndarray:
    """:attr:`FlowData.profile_slope`: each segment's ``(V_{j+1} - V_j) / (d_{j+1} - d_j)``, zero after the last
    depth."""
    slope = np.zeros_like(velocity)
    if depth.shape[0] > 1:
        slope[:-1] = np.diff(velocity, axis=0) / np.diff(depth)[:, None]
    return slope


def _wave_arrays(a, w, k, b, phase, h) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:attr:`FlowData.wave_table`, ``wave_weights`` and ``wave_reach`` of components of amplitude ``a``,
    frequency ``w``, wave number ``k``, direction ``b``, phase ``phase`` (each (M,)) in water ``h`` deep,
    padded to a multiple of :data:`WAVE_LANES` with copies of the last component of zero amplitude (every
    weight zero, every term finite)."""
    m = a.shape[0]
    padded = -(-m // WAVE_LANES) * WAVE_LANES
    table = np.zeros((WAVE_ROWS, padded))
    weights = np.zeros((N_SUMS, padded))
    if m == 0:
        return table, weights, np.zeros(REACH_SIZE)
    fill = np.arange(padded).clip(max=m - 1)                # the padding repeats the last component ...
    amplitude = np.where(np.arange(padded) < m, a[fill], 0.0)  # ... with zero amplitude
    k, w, b, phase = k[fill], w[fill], b[fill], phase[fill]
    bed = np.exp(-2.0 * k * h) if math.isfinite(h) else np.zeros_like(k)
    cb, sb = np.cos(b), np.sin(b)
    aw, aw2 = amplitude * w, amplitude * w * w
    table[WAVENUMBER], table[K_X], table[K_Y], table[OMEGA], table[PHASE] = k, k * cb, k * sb, w, phase
    table[COS_B], table[SIN_B], table[AW], table[AW2] = cb, sb, aw, aw2
    table[BED], table[NORM], table[K_SQUARED] = bed, 1.0 / (1.0 - bed), k * k
    awk = aw * k
    weights[UX], weights[UY], weights[AX], weights[AY] = aw * cb, aw * sb, aw2 * cb, aw2 * sb
    weights[UZ], weights[AZ] = aw, -aw2
    weights[PCC], weights[PCS], weights[PSS] = awk * cb * cb, awk * cb * sb, awk * sb * sb
    weights[QC], weights[QS] = awk * cb, awk * sb
    reach = np.array([np.abs(table[K_X]).max(), np.abs(table[K_Y]).max(), np.abs(phase).max(), w.max(), k.max()])
    return table, weights, reach


def with_body_anchors(flow: FlowData, n_bodies: int) -> FlowData:
    """``flow`` with fresh scratch and a wave anchor for each of ``n_bodies`` bodies (none yet), for one plant
    (:func:`uvms.dynamics.plant.build_plant`): the same constant arrays and ``status`` (the caller's
    :func:`check_status` reads it), its own scratch. Without waves the anchors stay empty."""
    m = flow.wave_table.shape[1]
    bodies = n_bodies if m > 0 else 0
    return flow._replace(wave_work=np.zeros_like(flow.wave_work), wave_point=np.zeros_like(flow.wave_point),
                         wave_sums=np.zeros_like(flow.wave_sums),
                         wave_anchor=np.zeros((bodies, TERM_ROWS, m)), wave_anchor_at=np.full((bodies, 4), np.nan),
                         wave_deltas=np.zeros((bodies, 4)), wave_body_sums=np.zeros((bodies, N_SUMS)))


def uniform_flow_data(times, velocity, acceleration) -> FlowData:
    """The :class:`FlowData` of a uniform table alone (today's current; the convention does not matter)."""
    return Flow(times, velocity, acceleration).compiled()


def check_status(flow: FlowData) -> None:
    """Raise the one-line :class:`~uvms.errors.UvmsInputError` of a flow whose evaluation found a point outside
    a field with ``outside: error`` (:data:`OUTSIDE`); nothing otherwise."""
    if int(flow.status[0]) == OUTSIDE:
        from uvms.checks import fail

        box = ", ".join(f"{name} [{axis[0]:g}, {axis[-1]:g}] m"
                        for name, axis in (("x", flow.field_x), ("y", flow.field_y), ("z", flow.field_z)))
        raise fail("current.field.outside", f"a body left the field's box ({box}) and the field says "
                                            "'error' (no outside)")


def _checked_profile(profile) -> tuple[np.ndarray, np.ndarray]:
    from uvms.checks import fail

    depth = _array(getattr(profile, "depth", None), "current.profile.depth", (), increasing=True)
    velocity = _array(getattr(profile, "velocity", None), "current.profile.velocity", (3,))
    if velocity.shape[0] != depth.shape[0]:
        raise fail("current.profile.velocity", f"expected one row per depth ({depth.shape[0]}), got "
                                               f"{velocity.shape[0]}")
    return depth, velocity


def _checked_field(field) -> tuple:
    from uvms.checks import fail, show

    axes = [_array(getattr(field, name, None), f"current.field.{name}", (), increasing=True)
            for name in ("x", "y", "z", "t")]
    velocity = np.array(getattr(field, "velocity", None), dtype=float, order="C")
    shape = (axes[3].size, axes[2].size, axes[1].size, axes[0].size, 3)
    if velocity.shape != shape:
        raise fail("current.field.velocity", f"expected shape (nt, nz, ny, nx, 3) = {shape}, got {velocity.shape}")
    if not np.all(np.isfinite(velocity)):
        raise fail("current.field.velocity", "expected finite numbers, found NaN or infinity")
    outside = getattr(field, "outside", None)
    if outside not in OUTSIDE_NAMES:
        raise fail("current.field.outside", f"expected one of 'hold', 'zero', 'error', got {show(outside)}")
    return (*axes, velocity, OUTSIDE_NAMES[outside])


def _checked_waves(waves) -> tuple:
    from uvms.checks import fail, number

    names = ("amplitude", "omega", "wavenumber", "direction", "phase")
    arrays = [_array(getattr(waves, name, None), f"waves.{name}", (), min_length=0) for name in names]
    if len({a.shape[0] for a in arrays}) != 1:
        raise fail("waves", f"expected equal lengths of {', '.join(names)}, got {[a.shape[0] for a in arrays]}")
    for name, a in zip(names[:3], arrays[:3]):
        if np.any(a < 0.0) or (name != "amplitude" and np.any(a == 0.0)):
            raise fail(f"waves.{name}", "expected positive values")
    h = getattr(waves, "water_depth", None)
    deep = isinstance(h, (float, np.floating)) and h == math.inf
    h = math.inf if deep else number(h, "waves.water_depth", positive=True, unit="m")
    return (*arrays, h)
