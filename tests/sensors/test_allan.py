"""The overlapping Allan deviation and the datasheet noise it reads back (IEEE Std 952-1997, Annex C)."""

from __future__ import annotations

import numpy as np
import pytest

from uvms.sensors import FLICKER_FLOOR, NoiseDensity, allan_deviation
from uvms.sensors.noise import GAUSS_MARKOV_PEAK, axis_noise, gauss_markov_avar

# An ADIS16470-class MEMS gyro as its datasheet gives it: angle random walk 0.34 deg/sqrt(h), bias instability
# 8 deg/h, converted to SI (module docstring of uvms.sensors.noise).
ARW = 0.34 * np.pi / 180 / 60           # N [rad/s/sqrt(Hz)]
BIAS_INSTABILITY = 8 * np.pi / 180 / 3600   # B [rad/s]


def test_allan_deviation_of_white_noise_and_a_ramp_by_hand():
    """White samples of standard deviation s at rate f: sigma(tau) = s / sqrt(f tau) (each cluster mean has
    variance s^2 / m); a ramp y = c t has the Allan deviation c tau / sqrt(2) (Riley, NIST SP 1065, Table 3)."""
    rng = np.random.default_rng(3)
    y = rng.standard_normal(200_000) * 0.5
    tau, s = allan_deviation(y, 100.0, clusters=[1, 10, 100])
    np.testing.assert_allclose(tau, [0.01, 0.1, 1.0])
    np.testing.assert_allclose(s, 0.5 / np.sqrt(100.0 * tau), rtol=0.03)
    t = np.arange(1000) / 10.0
    tau, s = allan_deviation(2.0 * t, 10.0, clusters=[1, 7, 50])
    np.testing.assert_allclose(s, 2.0 * tau / np.sqrt(2.0), rtol=1e-9)


def test_flicker_floor_and_gauss_markov_peak_constants():
    """0.664 = sqrt(2 ln 2 / pi); the first-order Gauss-Markov Allan deviation peaks at 0.6174 s, tau = 1.89 T."""
    assert FLICKER_FLOOR == pytest.approx(0.6643, abs=1e-4)
    tau = np.linspace(1.0, 3.0, 200_001)
    a = np.sqrt(gauss_markov_avar(tau, 1.0, 1.0))
    assert a.max() == pytest.approx(GAUSS_MARKOV_PEAK, abs=1e-4)
    assert tau[a.argmax()] == pytest.approx(1.89, abs=0.01)


def test_a_long_static_gyro_record_reads_back_its_datasheet():
    """40000 s at 10 Hz of the datasheet gyro: the Allan slope over 0.1-1 s is -1/2 and its value at 1 s is N
    (within 5 %), and the least-squares fit of IEEE Std 952's model sigma^2 = N^2 / tau + (0.664 B)^2 over
    1 s <= tau <= 4000 s (weights: each estimate's ~sqrt(L / tau) clusters) gives B within 10 %, on each axis."""
    rate, seconds = 10.0, 40_000
    e = axis_noise(NoiseDensity(white=ARW, bias_instability=BIAS_INSTABILITY, band=(1.0, 1e5)), 1 / rate,
                   int(seconds * rate), 3, seed=11, part=0)
    tau, s = allan_deviation(e, rate)
    short = (tau >= 0.1) & (tau <= 1.0)
    one = np.argmin(abs(tau - 1.0))
    fit = (tau >= 1.0) & (tau <= seconds / 10)
    for j in range(3):
        slope = np.polyfit(np.log(tau[short]), np.log(s[short, j]), 1)[0]
        assert slope == pytest.approx(-0.5, abs=0.03)
        assert s[one, j] == pytest.approx(ARW, rel=0.05)
        w = np.sqrt(seconds / tau[fit]) / s[fit, j] ** 2
        a, b = np.linalg.lstsq(np.stack([1 / tau[fit], np.ones(fit.sum())], 1) * w[:, None],
                               s[fit, j] ** 2 * w, rcond=None)[0]
        assert np.sqrt(b) / FLICKER_FLOOR == pytest.approx(BIAS_INSTABILITY, rel=0.10)


def test_bias_random_walk_and_single_gauss_markov():
    """A rate random walk K reads sigma(3 s) = K (Table C.1: K sqrt(tau / 3)); one correlation time gives the
    single Gauss-Markov bias whose Allan peak (at 1.89 T) is 0.664 B."""
    rate = 20.0
    e = axis_noise(NoiseDensity(random_walk=1e-4), 1 / rate, 200_000, 4, seed=2, part=0)
    tau, s = allan_deviation(e, rate, clusters=[60])
    np.testing.assert_allclose(s[0], 1e-4, rtol=0.12)
    e = axis_noise(NoiseDensity(bias_instability=1e-3, band=(5.0, 5.0)), 1 / rate, 400_000, 4, seed=2, part=0)
    tau, s = allan_deviation(e, rate, clusters=[int(1.89 * 5.0 * rate)])
    np.testing.assert_allclose(s[0], FLICKER_FLOOR * 1e-3, rtol=0.10)


def test_noise_is_seeded_and_prefix_stable():
    """The same seed gives the same samples; a longer record starts with the shorter one; parts are apart."""
    noise = NoiseDensity(white=1e-3, bias_instability=1e-4, random_walk=1e-5)
    a = axis_noise(noise, 0.01, 500, 3, seed=4, part=0)
    np.testing.assert_array_equal(a, axis_noise(noise, 0.01, 500, 3, seed=4, part=0))
    np.testing.assert_array_equal(a, axis_noise(noise, 0.01, 900, 3, seed=4, part=0)[:500])
    assert not np.allclose(a, axis_noise(noise, 0.01, 500, 3, seed=5, part=0))
    assert not np.allclose(a, axis_noise(noise, 0.01, 500, 3, seed=4, part=1))


def test_allan_deviation_refuses_bad_input():
    with pytest.raises(ValueError, match="finite"):
        allan_deviation([1.0, np.nan, 2.0, 3.0], 1.0)
    with pytest.raises(ValueError, match="rate"):
        allan_deviation(np.zeros(10), 0.0)
    with pytest.raises(ValueError, match="cluster"):
        allan_deviation(np.zeros(10), 1.0, clusters=[6])
