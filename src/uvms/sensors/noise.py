"""Inertial sensor noise from datasheet (Allan-deviation) parameters, sampled at ``dt = 1 / rate``.

One axis's error is the sum of three parts (IEEE Std 952-1997, Annex C; El-Sheimy, Hou and Niu, "Analysis and
modeling of inertial sensors using Allan variance", IEEE Trans. Instrum. Meas. 57(1), 2008)::

    e_k = white_k + flicker_k + walk_k

- **white noise** (angle / velocity random walk), density ``N`` [unit / sqrt(Hz)]: independent samples of
  standard deviation ``N / sqrt(dt)``; Allan deviation ``N / sqrt(tau)``.
- **bias instability** ``B`` [unit]: flicker noise (one-sided PSD ``h / f``, ``h = B^2 / pi``, Allan floor
  ``sqrt(2 h ln 2) = 0.664 B``) over the band ``[T_lo, T_hi]`` of correlation times, approximated by
  first-order Gauss-Markov processes ``b_{k+1} = phi b_k + s sqrt(1 - phi^2) w_k``, ``phi = exp(-dt / T_j)``
  (the exact discretisation of ``db/dt = -b / T + noise``, stationary standard deviation ``s``), with ``T_j``
  spaced ``r = 10^(1/4)`` apart (four a decade) and equal variances ``s^2 = h ln r`` (a log-uniform family of
  Lorentzians, ``4 s^2 T / (1 + (2 pi f T)^2)``, integrates to ``s^2 / (f ln r)``: flicker). Each process
  starts from its stationary distribution. The variances are then scaled by one factor, so that the closed-form
  Allan variance of the sum (:func:`gauss_markov_avar`) is ``(0.664 B)^2`` at the band's geometric centre
  (the finite family's edge loss, about 5 %). One correlation time (``T_lo = T_hi``) is the single
  Gauss-Markov bias many simulators use: its Allan deviation peaks at ``0.6174 s`` at ``tau = 1.89 T``, and
  ``s`` is chosen so that the peak is ``0.664 B``.
- **bias random walk** (rate random walk) ``K`` [unit / s / sqrt(Hz)]: ``walk_{k+1} = walk_k + K sqrt(dt) w_k``
  from 0; Allan deviation ``K sqrt(tau / 3)``.

Units for a gyro: ``N`` [rad/s/sqrt(Hz)] (a datasheet's ARW in deg/sqrt(h) times ``pi / 180 / 60``), ``B``
[rad/s] (deg/h times ``pi / 180 / 3600``), ``K`` [rad/s^2/sqrt(Hz)]; for an accelerometer m/s^2/sqrt(Hz) (VRW
in m/s/sqrt(h) over 60), m/s^2, m/s^3/sqrt(Hz).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uvms.sensors.allan import FLICKER_FLOOR
from uvms.sensors.base import stream

STEPS_PER_DECADE = 4
"""Gauss-Markov correlation times per decade of the bias-instability band."""

GAUSS_MARKOV_PEAK = 0.6174
"""Peak of a first-order Gauss-Markov process's Allan deviation over its standard deviation (at ``tau = 1.89 T``,
from :func:`gauss_markov_avar`; the tests recompute it)."""


DEFAULT_BAND = (1.0, 1.0e5)
"""Default correlation times ``(T_lo, T_hi)`` of the bias instability [s], in Python and in scenario files
(``docs/conventions.md``, "Sensors", item 4): the Allan floor holds from about 10 s to 30 000 s."""


@dataclass(frozen=True)
class NoiseDensity:
    """One axis family's datasheet parameters (module docstring); zero switches a part off.

    Attributes:
        white: ``N`` [unit/sqrt(Hz)].
        bias_instability: ``B`` [unit] (the Allan floor is ``0.664 B``).
        band: ``(T_lo, T_hi)`` correlation times of the bias instability [s].
        random_walk: ``K`` [unit/s/sqrt(Hz)].
        bias: constant (turn-on) bias [unit], the same on every axis.
    """

    white: float = 0.0
    bias_instability: float = 0.0
    band: tuple[float, float] = DEFAULT_BAND
    random_walk: float = 0.0
    bias: float = 0.0

    @property
    def is_zero(self) -> bool:
        return self.white == 0 and self.bias_instability == 0 and self.random_walk == 0 and self.bias == 0


def gauss_markov_avar(tau, variance: float, correlation_time: float):
    """Closed-form Allan variance of a first-order Gauss-Markov process of ``variance`` and ``correlation_time``
    ``T`` (IEEE Std 952-1997, Table C.1, "exponentially correlated noise")::

        sigma^2(tau) = 2 s^2 T / tau (1 - T / (2 tau) (3 - 4 e^{-tau/T} + e^{-2 tau/T}))
    """
    x = np.asarray(tau, dtype=float) / correlation_time
    return 2.0 * variance / x * (1.0 - (3.0 - 4.0 * np.exp(-x) + np.exp(-2.0 * x)) / (2.0 * x))


def correlation_times(band: tuple[float, float]) -> np.ndarray:
    """The Gauss-Markov correlation times of a band (module docstring): ``T_lo`` times ``10^(j/4)`` up to
    ``T_hi`` (one time when they are equal)."""
    lo, hi = band
    steps = int(np.ceil(np.log10(hi / lo) * STEPS_PER_DECADE - 1e-9))
    return lo * (hi / lo) ** (np.arange(steps + 1) / max(steps, 1)) if steps > 0 else np.array([float(lo)])


def flicker_variances(bias_instability: float, band: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """``(T_j, s_j^2)`` of the bias-instability processes (module docstring)."""
    T = correlation_times(band)
    if T.size == 1:
        return T, np.array([(FLICKER_FLOOR * bias_instability / GAUSS_MARKOV_PEAK) ** 2])
    variance = np.full(T.size, bias_instability ** 2 / np.pi * np.log(T[1] / T[0]))
    centre = np.sqrt(band[0] * band[1])
    model = sum(gauss_markov_avar(centre, s2, Tj) for s2, Tj in zip(variance, T))
    return T, variance * (FLICKER_FLOOR * bias_instability) ** 2 / model


def axis_noise(noise: NoiseDensity, dt: float, n_samples: int, axes: int, seed: int, part: int) -> np.ndarray:
    """(K, axes) error samples (module docstring) every ``dt`` [s], seeded: stream ``(seed, part, j)`` for
    noise part ``j`` (0 white, 1 random walk, 2 + i the i-th Gauss-Markov process)."""
    from scipy.signal import lfilter

    K = int(n_samples)
    e = np.full((K, axes), float(noise.bias))
    if noise.white > 0:
        e += stream(seed, part, 0).standard_normal((K, axes)) * (noise.white / np.sqrt(dt))
    if noise.random_walk > 0:
        steps = stream(seed, part, 1).standard_normal((K, axes)) * (noise.random_walk * np.sqrt(dt))
        e += np.cumsum(steps, axis=0) - steps            # walk_0 = 0
    if noise.bias_instability > 0:
        for i, (T, s2) in enumerate(zip(*flicker_variances(noise.bias_instability, noise.band))):
            phi = np.exp(-dt / T)
            rng = stream(seed, part, 2 + i)
            start = rng.standard_normal(axes) * np.sqrt(s2)
            w = rng.standard_normal((K, axes)) * np.sqrt(s2 * (1.0 - phi * phi))
            w[0] = start
            e += lfilter([1.0], [1.0, -phi], w, axis=0)  # b_0 = start, b_k = phi b_{k-1} + w_k
    return e
