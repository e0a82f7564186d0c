"""The overlapping Allan deviation of a sampled rate signal (IEEE Std 952-1997, Annex C; Riley, *Handbook of
Frequency Stability Analysis*, NIST SP 1065, 2008, Eq. 13).

For samples ``y_k`` (a gyro's rate, an accelerometer's specific force) taken every ``tau0 = 1 / rate``, the
cumulative sum ``theta_k = tau0 sum_{i<k} y_i`` (the angle, the velocity) and a cluster time ``tau = m tau0``::

    sigma^2(tau) = 1 / (2 tau^2 (K - 2m)) sum_{k=0}^{K-2m-1} (theta_{k+2m} - 2 theta_{k+m} + theta_k)^2

(``K`` the number of ``theta`` values, every start ``k`` used: "overlapping"). The datasheet parameters read
off a log-log plot of ``sigma(tau)`` (IEEE Std 952, Annex C, Table C.1)::

    white noise (angle / velocity random walk) N:   sigma = N / sqrt(tau)          slope -1/2, N at tau = 1 s
    bias instability B (flicker):                   sigma = B sqrt(2 ln 2 / pi)    = 0.664 B, the flat floor
    bias (rate) random walk K:                      sigma = K sqrt(tau / 3)        slope +1/2, K at tau = 3 s
"""

from __future__ import annotations

import numpy as np

FLICKER_FLOOR = float(np.sqrt(2.0 * np.log(2.0) / np.pi))
"""``sqrt(2 ln 2 / pi) = 0.664``: the Allan floor of a flicker (bias-instability) noise of coefficient ``B`` is
``0.664 B`` (IEEE Std 952-1997, Table C.1)."""


def cluster_sizes(n_samples: int, per_decade: int = 10, *, max_fraction: float = 0.25) -> np.ndarray:
    """Cluster sizes ``m`` (samples per cluster), log-spaced, ``per_decade`` a decade, from 1 to
    ``max_fraction`` of the record (beyond it fewer than 2 independent clusters pairs remain), each once."""
    top = max(1, int(n_samples * max_fraction))
    m = np.unique(np.round(np.logspace(0, np.log10(top), max(2, int(per_decade * np.log10(top)) + 1))).astype(int))
    return m[m >= 1]


def allan_deviation(samples, rate: float, clusters=None) -> tuple[np.ndarray, np.ndarray]:
    """The overlapping Allan deviation (module docstring) of ``samples`` (K,) or (K, c) taken at ``rate`` [Hz].

    Args:
        samples: the signal, one row per sample (a column per axis).
        rate: samples per second [Hz].
        clusters: cluster sizes ``m`` in samples (default :func:`cluster_sizes`).

    Returns:
        ``(tau, sigma)``: cluster times (M,) [s] and deviations (M,) or (M, c), in the samples' unit.
    """
    y = np.asarray(samples, dtype=float)
    if y.ndim not in (1, 2) or y.shape[0] < 3 or not np.all(np.isfinite(y)):
        raise ValueError(f"expected at least 3 finite samples (K,) or (K, c), got shape {y.shape}")
    if not (np.isfinite(rate) and rate > 0):
        raise ValueError(f"expected a positive rate [Hz], got {rate!r}")
    tau0 = 1.0 / rate
    theta = np.concatenate([np.zeros((1,) + y.shape[1:]), np.cumsum(y, axis=0) * tau0])
    m = cluster_sizes(y.shape[0]) if clusters is None else np.asarray(clusters, dtype=int)
    if m.ndim != 1 or m.size == 0 or np.any(m < 1) or np.any(2 * m >= theta.shape[0]):
        raise ValueError(f"expected cluster sizes in [1, {(theta.shape[0] - 1) // 2}] samples")
    sigma = np.empty((m.size,) + y.shape[1:])
    for i, mi in enumerate(m):
        d = theta[2 * mi:] - 2.0 * theta[mi:-mi] + theta[:-2 * mi]
        sigma[i] = np.sqrt(np.sum(d * d, axis=0) / (2.0 * (mi * tau0) ** 2 * d.shape[0]))
    return m * tau0, sigma
