"""Linear (Airy) waves: the dispersion relation, wave spectra and their discretisation into components.

This module turns a sea state (a regular wave, or a spectrum with a seed) into the arrays of
:class:`WaveComponents`; the particle kinematics at a point (velocity, acceleration) are evaluated by the
compiled fluid object (:mod:`uvms.hydro.flow`). References: DNV-RP-C205 *Environmental conditions and
environmental loads* (2010/2021), sections 3.2 (linear wave theory), 3.5.5 (JONSWAP), 3.5.8 (directional
spreading); O. M. Faltinsen, *Sea Loads on Ships and Offshore Structures* (1990), ch. 2. ``docs/environment.md``
documents the fields and where linear theory stops holding.

Conventions (``docs/environment.md``): ``omega`` in rad/s, ``wavenumber`` in rad/m, a spectrum ``S(omega)`` is
one-sided in m^2 s/rad (its variance ``m0 = integral of S d omega``), ``direction`` is the direction the waves
travel to, in radians from world +x toward world +y, and the free-surface elevation ``eta`` (m, positive
*above* the mean surface whatever the world convention) is

    eta(t, x, y) = sum_i a_i cos(k_i (x cos b_i + y sin b_i) - omega_i t + phi_i).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from uvms.errors import UvmsInputError

MAX_COMPONENTS = 10_000
"""Most wave components a sea state may have (bounds what a scenario makes uvms allocate)."""

DEFAULT_RANGE = (0.5, 4.0)
"""Default frequency range of an analytic spectrum, in multiples of the peak frequency ``omega_p``: Pierson-
Moskowitz keeps ``exp(-1.25 (omega_p / omega)^4)`` of its variance below ``omega``, so the range holds 99.5 %
of it (``1 - exp(-1.25 / 4^4)`` above, ``exp(-20)`` below)."""


class WaveComponents(NamedTuple):
    """A sum of linear wave components (each array ``(M,)``), the waves of :class:`uvms.hydro.flow.Flow`.

    Attributes:
        amplitude: ``a_i`` [m] (half the height of a regular wave).
        omega: angular frequency ``omega_i`` [rad/s].
        wavenumber: ``k_i`` [rad/m], from :func:`wavenumber` at ``water_depth``.
        direction: propagation direction ``b_i`` [rad], from world +x toward world +y.
        phase: ``phi_i`` [rad].
        water_depth: ``h`` [m] below the mean surface (``math.inf``: deep water).
    """

    amplitude: np.ndarray
    omega: np.ndarray
    wavenumber: np.ndarray
    direction: np.ndarray
    phase: np.ndarray
    water_depth: float


# ------------------------------------------------------------------------------------------- dispersion


def wavenumber(omega, water_depth: float, gravity: float) -> np.ndarray:
    """The wavenumber ``k`` [rad/m] of waves of angular frequency ``omega`` [rad/s] in water ``water_depth``
    deep [m] (``math.inf``: deep water), from the finite-depth dispersion relation (DNV-RP-C205 Eq. 3.2.4;
    Faltinsen Eq. 2.11)

        omega^2 = g k tanh(k h).

    With ``x = k h`` and ``y = omega^2 h / g`` it reads ``x tanh x = y``, solved by Newton's method kept inside
    the bracket ``max(y, sqrt(y)) <= x <= (y + sqrt(y^2 + 4 y)) / 2`` (``tanh x <= min(1, x)`` and
    ``tanh x >= x / (1 + x)``), bisecting whenever a Newton step would leave it: converges for every
    ``y > 0`` to a relative residual of a few 1e-16. Deep water: ``k = omega^2 / g``.

    Raises:
        UvmsInputError: ``omega``, ``water_depth`` or ``gravity`` not positive and finite (``water_depth`` may
            be ``inf``).
    """
    w = np.asarray(omega, dtype=float)
    if not np.all(np.isfinite(w)) or np.any(w <= 0.0):
        raise UvmsInputError(f"expected positive finite angular frequencies, found {_first_bad(w)}", None, "omega")
    if not (gravity > 0.0 and math.isfinite(gravity)):
        raise UvmsInputError(f"expected a positive finite gravity, found {gravity!r}", None, "gravity")
    if not water_depth > 0.0 or math.isnan(water_depth):
        raise UvmsInputError(f"expected a positive water depth (inf: deep water), found {water_depth!r}", None,
                             "water_depth")
    deep = w * w / gravity
    if math.isinf(water_depth):
        return deep
    y = deep * water_depth
    lo = np.maximum(y, np.sqrt(y))
    hi = 0.5 * (y + np.sqrt(y * y + 4.0 * y))
    x = 0.5 * (lo + hi)
    for _ in range(100):
        t = np.tanh(x)
        f = x * t - y
        lo = np.where(f < 0.0, x, lo)
        hi = np.where(f > 0.0, x, hi)
        slope = t + x * (1.0 - t * t)
        step = x - f / slope
        inside = (step > lo) & (step < hi)
        new = np.where(inside, step, 0.5 * (lo + hi))
        if np.all(np.abs(new - x) <= 1e-15 * new):
            x = new
            break
        x = new
    return x / water_depth


def _first_bad(values: np.ndarray) -> str:
    bad = values[~(np.isfinite(values) & (values > 0.0))]
    return f"{bad.ravel()[0]!r}" if bad.size else "none"


# ---------------------------------------------------------------------------------------------- spectra


def peak_frequency(peak_period: float) -> float:
    """``omega_p = 2 pi / T_p`` [rad/s]."""
    return 2.0 * math.pi / peak_period


def pierson_moskowitz(omega, significant_height: float, peak_period: float) -> np.ndarray:
    """The Pierson-Moskowitz spectrum [m^2 s/rad] in ``H_s`` [m] and ``T_p`` [s] (DNV-RP-C205 Eq. 3.5.3; also
    called Bretschneider or the two-parameter ITTC spectrum):

        S_PM(omega) = 5/16 H_s^2 omega_p^4 omega^-5 exp(-5/4 (omega_p / omega)^4),   omega_p = 2 pi / T_p.

    Its variance is exactly ``H_s^2 / 16`` and its peak lies at ``omega_p``.
    """
    w = np.asarray(omega, dtype=float)
    wp = peak_frequency(peak_period)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        s = 5.0 / 16.0 * significant_height ** 2 * wp ** 4 * w ** -5.0 * np.exp(-1.25 * (wp / w) ** 4)
    return np.where(w > 0.0, s, 0.0)


def jonswap(omega, significant_height: float, peak_period: float, peak_factor: float = 3.3) -> np.ndarray:
    """The JONSWAP spectrum [m^2 s/rad] (DNV-RP-C205 Eq. 3.5.5):

        S_J(omega) = A_g S_PM(omega) g^exp(-(omega - omega_p)^2 / (2 s^2 omega_p^2)),
        s = 0.07 for omega <= omega_p, 0.09 above,   A_g = 1 - 0.287 ln(g),

    ``g`` the peak factor (``peak_factor``, 1 gives Pierson-Moskowitz; DNV: 1 to 7, 3.3 typical). ``A_g`` is
    DNV's normalising factor: the variance is ``H_s^2 / 16`` to within 1.8 % for ``1 <= g <= 7``
    (``docs/environment.md``). The peak lies at ``omega_p``.
    """
    w = np.asarray(omega, dtype=float)
    wp = peak_frequency(peak_period)
    sigma = np.where(w <= wp, 0.07, 0.09)
    shape = peak_factor ** np.exp(-((w - wp) ** 2) / (2.0 * sigma ** 2 * wp ** 2))
    return (1.0 - 0.287 * math.log(peak_factor)) * pierson_moskowitz(w, significant_height, peak_period) * shape


def table_spectrum(frequencies, densities) -> Callable[[np.ndarray], np.ndarray]:
    """A user spectrum: ``S`` [m^2 s/rad] given at ``frequencies`` [rad/s] (increasing), linear between them
    and zero outside."""
    f = np.asarray(frequencies, dtype=float)
    s = np.asarray(densities, dtype=float)

    def density(omega):
        return np.interp(np.asarray(omega, dtype=float), f, s, left=0.0, right=0.0)

    return density


class Spectrum(NamedTuple):
    """A spectrum to discretise: ``density(omega)`` [m^2 s/rad], its ``peak`` frequency [rad/s] and the
    ``frequency_range`` ``(lo, hi)`` [rad/s] its components are drawn from (:func:`irregular_waves`)."""

    density: Callable[[np.ndarray], np.ndarray]
    peak: float
    frequency_range: tuple[float, float]

    @classmethod
    def jonswap(cls, significant_height: float, peak_period: float, peak_factor: float = 3.3,
                frequency_range: tuple[float, float] | None = None) -> Spectrum:
        """:func:`jonswap` (range: :data:`DEFAULT_RANGE` times ``omega_p`` unless given)."""
        _positive(significant_height, "significant_height")
        _positive(peak_period, "peak_period")
        if not (1.0 <= peak_factor <= 7.0):
            raise UvmsInputError(f"expected a peak factor in 1..7 (DNV-RP-C205 3.5.5), found {peak_factor!r}", None,
                                 "peak_factor")

        def density(omega):
            return jonswap(omega, significant_height, peak_period, peak_factor)

        return cls._analytic(density, peak_period, frequency_range)

    @classmethod
    def pierson_moskowitz(cls, significant_height: float, peak_period: float,
                          frequency_range: tuple[float, float] | None = None) -> Spectrum:
        """:func:`pierson_moskowitz` (range: :data:`DEFAULT_RANGE` times ``omega_p`` unless given)."""
        _positive(significant_height, "significant_height")
        _positive(peak_period, "peak_period")

        def density(omega):
            return pierson_moskowitz(omega, significant_height, peak_period)

        return cls._analytic(density, peak_period, frequency_range)

    @classmethod
    def table(cls, frequencies, densities, frequency_range: tuple[float, float] | None = None) -> Spectrum:
        """:func:`table_spectrum`; its peak is the frequency of the largest density, its range the table's
        unless given."""
        f = np.asarray(frequencies, dtype=float)
        s = np.asarray(densities, dtype=float)
        if f.ndim != 1 or f.size < 2 or s.shape != f.shape or not np.all(np.isfinite(f)) or \
                not np.all(np.isfinite(s)) or np.any(np.diff(f) <= 0) or f[0] <= 0 or np.any(s < 0):
            raise UvmsInputError("expected increasing positive frequencies with one finite density >= 0 each",
                                 None, "table")
        span = (float(f[0]), float(f[-1])) if frequency_range is None else frequency_range
        return cls(table_spectrum(f, s), float(f[int(np.argmax(s))]), span)

    @classmethod
    def _analytic(cls, density, peak_period, frequency_range) -> Spectrum:
        wp = peak_frequency(peak_period)
        span = (DEFAULT_RANGE[0] * wp, DEFAULT_RANGE[1] * wp) if frequency_range is None else frequency_range
        return cls(density, wp, (float(span[0]), float(span[1])))


# ---------------------------------------------------------------------------------------------- spreading


def spreading_density(angle, spreading: float) -> np.ndarray:
    """DNV-RP-C205 Eq. 3.5.8's cos^2s directional spreading about the mean direction (``angle = b - b0`` [rad]):

        D(b) = Gamma(1 + s) / (sqrt(pi) Gamma(1/2 + s)) cos^(2 s)(b - b0)   for |b - b0| < pi / 2, else 0,

    normalised so that it integrates to 1 over ``b``."""
    x = np.asarray(angle, dtype=float)
    norm = math.exp(math.lgamma(1.0 + spreading) - math.lgamma(0.5 + spreading)) / math.sqrt(math.pi)
    inside = np.abs(x) < 0.5 * math.pi
    return np.where(inside, norm * np.abs(np.cos(np.where(inside, x, 0.0))) ** (2.0 * spreading), 0.0)


def _draw_directions(rng: np.random.Generator, count: int, mean: float, spreading: float) -> np.ndarray:
    """``count`` directions drawn from :func:`spreading_density` by inverting its cumulative distribution
    (tabulated on 4001 points of ``(-pi/2, pi/2)``, trapezoidal, linear in between)."""
    grid = np.linspace(-0.5 * math.pi, 0.5 * math.pi, 4001)
    d = spreading_density(grid, spreading)
    cdf = np.concatenate(([0.0], np.cumsum(0.5 * (d[1:] + d[:-1]) * np.diff(grid))))
    cdf /= cdf[-1]
    return mean + np.interp(rng.random(count), cdf, grid)


# ------------------------------------------------------------------------------------------- sea states


def regular_waves(height: float, period: float, *, direction: float = 0.0, water_depth: float = math.inf,
                  gravity: float = 9.81, phase: float = 0.0) -> WaveComponents:
    """One regular wave: height ``H = 2 a`` [m], period ``T`` [s] (``omega = 2 pi / T``), ``direction`` [rad],
    ``water_depth`` [m], crest at the origin at ``t = 0`` for ``phase = 0``.

    Raises:
        UvmsInputError: height, period or depth not positive (one line naming the field).
    """
    _positive(height, "height")
    _positive(period, "period")
    _depth(water_depth)
    omega = np.array([2.0 * math.pi / period])
    return WaveComponents(amplitude=np.array([0.5 * height]), omega=omega,
                          wavenumber=wavenumber(omega, water_depth, gravity), direction=np.array([float(direction)]),
                          phase=np.array([float(phase)]), water_depth=float(water_depth))


def irregular_waves(spectrum: Spectrum, *, components: int, seed: int | None = None, direction: float = 0.0,
                    spreading: float | None = None, water_depth: float = math.inf,
                    gravity: float = 9.81) -> WaveComponents:
    """The components of a :class:`Spectrum` (its ``density(omega)`` [m^2 s/rad], ``peak`` [rad/s] and
    ``frequency_range``).

    Discretisation (``docs/environment.md``): ``frequency_range = (omega_lo, omega_hi)`` is cut into
    ``components`` equal bins of width ``d omega``; component ``i`` has a frequency drawn uniformly inside bin
    ``i`` (so that the record does not repeat after ``2 pi / d omega``, DNV-RP-C205 3.5.10) and the amplitude
    ``a_i = sqrt(2 m0_i)`` of the bin's variance ``m0_i`` (the bin's integral of ``S``, 8-point Gauss-Legendre
    on 16 sub-intervals, split at the peak), so that ``sum a_i^2 / 2`` is the spectrum's variance in the range
    whatever the draw.
    Phases are uniform in ``[0, 2 pi)``; with ``spreading = s`` each component gets one direction drawn from
    the cos^2s law about ``direction`` (:func:`spreading_density`), else ``direction``. The draws come from
    ``numpy.random.default_rng(seed)`` in this order: frequencies, phases, directions.

    Raises:
        UvmsInputError: a count outside ``1..MAX_COMPONENTS``, a range not ``0 < lo < hi``, the peak outside
            the range, a negative spreading, a spectrum with no variance in the range (one line each).
    """
    if not isinstance(components, (int, np.integer)) or not 1 <= components <= MAX_COMPONENTS:
        raise UvmsInputError(f"expected a whole number of components in 1..{MAX_COMPONENTS}, found {components!r}",
                             None, "components")
    density, peak = spectrum.density, float(spectrum.peak)
    lo, hi = (float(v) for v in spectrum.frequency_range)
    if not (0.0 < lo < hi and math.isfinite(hi)):
        raise UvmsInputError(f"expected 0 < lower < upper [rad/s], found [{lo:g}, {hi:g}]", None, "frequency_range")
    if not lo <= peak <= hi:
        raise UvmsInputError(f"expected the spectrum's peak ({peak:g} rad/s) inside the frequency range, found "
                             f"[{lo:g}, {hi:g}] rad/s", None, "frequency_range")
    if spreading is not None and not (spreading >= 0.0 and math.isfinite(spreading)):
        raise UvmsInputError(f"expected a spreading exponent s >= 0, found {spreading!r}", None, "spreading")
    _depth(water_depth)
    rng = np.random.default_rng(seed)
    edges = np.linspace(lo, hi, components + 1)
    omega = edges[:-1] + rng.random(components) * np.diff(edges)
    phase = rng.random(components) * (2.0 * math.pi)
    variance = _bin_variances(density, edges, peak)
    if not np.all(np.isfinite(variance)) or np.any(variance < 0.0) or variance.sum() <= 0.0:
        raise UvmsInputError("expected a spectrum with finite, non-negative density and some variance in the "
                             "frequency range", None, "spectrum")
    if spreading is None:
        directions = np.full(components, float(direction))
    else:
        directions = _draw_directions(rng, components, float(direction), float(spreading))
    return WaveComponents(amplitude=np.sqrt(2.0 * variance), omega=omega,
                          wavenumber=wavenumber(omega, water_depth, gravity), direction=directions, phase=phase,
                          water_depth=float(water_depth))


def _bin_variances(density: Callable[[np.ndarray], np.ndarray], edges: np.ndarray, peak: float) -> np.ndarray:
    """The integral of ``density`` over each bin ``[edges[i], edges[i + 1]]``: 8-point Gauss-Legendre on 16
    equal sub-intervals of each bin, the bin holding the peak split there first (JONSWAP's width ``s`` changes
    at the peak, so its second derivative jumps)."""
    nodes, weights = np.polynomial.legendre.leggauss(8)
    points = np.union1d(edges, [peak])
    first = np.searchsorted(points, edges[:-1])               # each bin's first segment
    sub = np.linspace(0.0, 1.0, 17)
    width = np.diff(points)
    left = points[:-1, None] + width[:, None] * sub[None, :-1]          # (segments, 16) sub-interval starts
    h = width[:, None] / 16.0
    at = left[:, :, None] + 0.5 * h[:, :, None] * (nodes[None, None, :] + 1.0)
    values = np.asarray(density(at), dtype=float)
    segments = 0.5 * h[:, 0] * np.einsum("msk,k->m", values, weights)
    return np.add.reduceat(segments, first)


def elevation(components: WaveComponents, t, x, y) -> np.ndarray:
    """Free-surface elevation ``eta`` [m] above the mean surface (module doc), at times ``t`` [s] and world
    points ``(x, y)`` [m]; ``t``, ``x``, ``y`` broadcast together and so does the result. Evaluated one
    component at a time (memory of one result array)."""
    t, x, y = np.broadcast_arrays(np.asarray(t, dtype=float), np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    eta = np.zeros(t.shape)
    for a, w, k, b, p in zip(components.amplitude, components.omega, components.wavenumber, components.direction,
                             components.phase):
        eta += a * np.cos(k * (x * math.cos(b) + y * math.sin(b)) - w * t + p)
    return eta


def significant_height(components: WaveComponents) -> float:
    """``H_m0 = 4 sqrt(m0)`` [m] of the components, ``m0 = sum a_i^2 / 2`` (DNV-RP-C205 3.5.1)."""
    return 4.0 * math.sqrt(0.5 * float(np.sum(components.amplitude ** 2)))


def _positive(value: float, field: str) -> None:
    if not (value > 0.0 and math.isfinite(value)):
        raise UvmsInputError(f"expected a positive finite value, found {value!r}", None, field)


def _depth(water_depth: float) -> None:
    if not water_depth > 0.0 or math.isnan(water_depth):
        raise UvmsInputError(f"expected a positive water depth [m] (inf: deep water), found {water_depth!r}", None,
                             "water_depth")
