"""Linear waves' inputs against closed forms: the dispersion relation's deep and shallow limits, the spectra's
moments and peaks (independent quadrature), the discretisation's variance, the elevation record's variance
against its spectrum within the sampling error of a Gaussian sea, and the cos^2s spreading law."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import minimize_scalar

from uvms.errors import UvmsInputError
from uvms.hydro.waves import (DEFAULT_RANGE, Spectrum, WaveComponents, elevation, irregular_waves, jonswap,
                              pierson_moskowitz, regular_waves, significant_height, spreading_density, table_spectrum, wavenumber)

G = 9.81


# ------------------------------------------------------------------------------------------- dispersion


def test_deep_water_limit_is_omega_squared_over_g():
    omega = np.array([0.3, 1.0, 2.0, 6.0])
    assert np.array_equal(wavenumber(omega, math.inf, G), omega ** 2 / G)
    # k h > 20 for every omega here: tanh(k h) = 1 to 1e-17, so the finite-depth root is the deep one
    assert np.allclose(wavenumber(omega, 2000.0, G), omega ** 2 / G, rtol=1e-14, atol=0.0)


def test_shallow_water_limit_is_the_long_wave_speed():
    # omega^2 = g k tanh(k h) = g h k^2 (1 - (k h)^2 / 3 + ...)  =>  k = k0 (1 + (k0 h)^2 / 6 + O((k0 h)^4)),
    # k0 = omega / sqrt(g h) (celerity sqrt(g h))
    h = 0.5
    omega = np.array([0.01, 0.03, 0.1])
    k0 = omega / math.sqrt(G * h)
    k = wavenumber(omega, h, G)
    assert np.all(np.abs(k / k0 - 1.0) < 0.2 * (k0 * h) ** 2)                  # the leading order
    assert np.all(np.abs(k / (k0 * (1.0 + (k0 * h) ** 2 / 6.0)) - 1.0) < (k0 * h) ** 4)   # the next


@pytest.mark.parametrize("h", [0.3, 5.0, 50.0])
def test_dispersion_round_trip_from_chosen_wavenumbers(h):
    k = np.geomspace(1e-4, 1e2, 61)
    omega = np.sqrt(G * k * np.tanh(k * h))
    assert np.allclose(wavenumber(omega, h, G), k, rtol=1e-12, atol=0.0)


@pytest.mark.parametrize("kwargs, field", [({"omega": [0.0]}, "omega"), ({"omega": [-1.0]}, "omega"),
                                           ({"water_depth": 0.0}, "water_depth"),
                                           ({"water_depth": -3.0}, "water_depth"), ({"gravity": 0.0}, "gravity")])
def test_dispersion_refuses_non_positive_inputs(kwargs, field):
    args = {"omega": [1.0], "water_depth": 10.0, "gravity": G} | kwargs
    with pytest.raises(UvmsInputError) as info:
        wavenumber(**args)
    assert info.value.path == field


# ---------------------------------------------------------------------------------------------- spectra


def test_pierson_moskowitz_moments_and_peak():
    hs, tp = 0.5, 4.0
    wp = 2 * math.pi / tp
    m0 = quad(lambda w: float(pierson_moskowitz(w, hs, tp)), 0.05 * wp, wp)[0] + \
        quad(lambda w: float(pierson_moskowitz(w, hs, tp)), wp, np.inf)[0]
    assert m0 == pytest.approx(hs ** 2 / 16, rel=1e-8)
    peak = minimize_scalar(lambda w: -float(pierson_moskowitz(w, hs, tp)), bounds=(0.5 * wp, 2 * wp),
                           method="bounded", options={"xatol": 1e-9}).x
    assert peak == pytest.approx(wp, rel=1e-6)


@pytest.mark.parametrize("gamma", [1.0, 2.0, 3.3, 5.0, 7.0])
def test_jonswap_written_out_moments_and_peak(gamma):
    hs, tp = 2.0, 8.0
    wp = 2 * math.pi / tp
    w = np.linspace(0.3, 3.0, 37)
    # DNV-RP-C205 Eq. 3.5.5 written out independently
    sigma = np.where(w <= wp, 0.07, 0.09)
    expected = ((1 - 0.287 * np.log(gamma)) * 5 / 16 * hs ** 2 * wp ** 4 / w ** 5 * np.exp(-1.25 * (wp / w) ** 4)
                * gamma ** np.exp(-(w - wp) ** 2 / (2 * sigma ** 2 * wp ** 2)))
    assert np.allclose(jonswap(w, hs, tp, gamma), expected, rtol=1e-13, atol=0.0)
    m0 = quad(lambda x: float(jonswap(x, hs, tp, gamma)), 0.05 * wp, wp)[0] + \
        quad(lambda x: float(jonswap(x, hs, tp, gamma)), wp, np.inf, limit=200)[0]
    # A_g is DNV's approximate normalisation (Hs^2/16 to within 1.8 % on 1 <= gamma <= 7, docs/environment.md)
    assert m0 == pytest.approx(hs ** 2 / 16, rel=0.018)
    peak = minimize_scalar(lambda x: -float(jonswap(x, hs, tp, gamma)), bounds=(0.8 * wp, 1.2 * wp),
                           method="bounded", options={"xatol": 1e-10}).x
    assert peak == pytest.approx(wp, rel=1e-6)


def test_spectrum_constructors_default_range_and_refusals():
    wp = 2 * math.pi / 4.0
    spectrum = Spectrum.jonswap(0.5, 4.0)
    assert spectrum.peak == pytest.approx(wp) and spectrum.frequency_range == pytest.approx((0.5 * wp, 4 * wp))
    assert np.array_equal(spectrum.density(np.array([1.0, 2.0])), jonswap(np.array([1.0, 2.0]), 0.5, 4.0, 3.3))
    for call, field in ((lambda: Spectrum.jonswap(0.0, 4.0), "significant_height"),
                        (lambda: Spectrum.pierson_moskowitz(0.5, -1.0), "peak_period"),
                        (lambda: Spectrum.jonswap(0.5, 4.0, 0.5), "peak_factor"),
                        (lambda: Spectrum.table([1.0, 1.0], [0.0, 1.0]), "table")):
        with pytest.raises(UvmsInputError) as info:
            call()
        assert info.value.path == field


def test_jonswap_with_peak_factor_one_is_pierson_moskowitz():
    w = np.linspace(0.2, 4.0, 50)
    assert np.array_equal(jonswap(w, 1.0, 5.0, 1.0), pierson_moskowitz(w, 1.0, 5.0))


# ------------------------------------------------------------------------------------------- components


def _sea(seed=7, components=50, spectrum=None, **kwargs):
    hs, tp = 0.5, 4.0
    wp = 2 * math.pi / tp
    density = spectrum or (lambda w: jonswap(w, hs, tp, 3.3))
    return irregular_waves(Spectrum(density, wp, (DEFAULT_RANGE[0] * wp, DEFAULT_RANGE[1] * wp)),
                           components=components, seed=seed, water_depth=20.0, gravity=G, **kwargs)


def test_component_variances_sum_to_the_spectrum_in_the_range():
    hs, tp = 0.5, 4.0
    wp = 2 * math.pi / tp
    sea = _sea()
    in_range = quad(lambda w: float(jonswap(w, hs, tp)), 0.5 * wp, wp)[0] + \
        quad(lambda w: float(jonswap(w, hs, tp)), wp, 4.0 * wp)[0]
    assert 0.5 * np.sum(sea.amplitude ** 2) == pytest.approx(in_range, rel=1e-10)
    edges = np.linspace(0.5 * wp, 4.0 * wp, 51)
    assert np.all((sea.omega > edges[:-1]) & (sea.omega < edges[1:]))        # one random frequency per bin
    assert np.allclose(sea.omega ** 2, G * sea.wavenumber * np.tanh(sea.wavenumber * 20.0), rtol=1e-13)


def test_default_range_keeps_the_pierson_moskowitz_variance_it_promises():
    # PM's variance below omega is m0 exp(-5/4 (omega_p/omega)^4): the range (0.5, 4) omega_p keeps
    # 1 - exp(-20) - (1 - exp(-5/4 / 4^4)) of it
    hs, tp = 0.5, 4.0
    sea = _sea(spectrum=lambda w: pierson_moskowitz(w, hs, tp), components=200)
    kept = 1 - math.exp(-20) - (1 - math.exp(-1.25 / 4 ** 4))
    assert 0.5 * np.sum(sea.amplitude ** 2) / (hs ** 2 / 16) == pytest.approx(kept, rel=1e-10)
    assert significant_height(sea) == pytest.approx(hs * math.sqrt(kept), rel=1e-10)


def test_seed_gives_the_same_sea_and_another_seed_another():
    a, b, c = _sea(seed=3), _sea(seed=3), _sea(seed=4)
    assert all(np.array_equal(x, y) for x, y in zip(a[:5], b[:5]))
    assert not np.array_equal(a.phase, c.phase) and not np.array_equal(a.omega, c.omega)
    assert np.all((a.phase >= 0) & (a.phase < 2 * math.pi))


def _record_error_sd(sea, n, dt):
    """The standard deviation, over the random phases, of the mean of eta^2 over n samples dt apart minus
    sum a_i^2 / 2, for the sea's amplitudes and frequencies: eta^2 = sum_i a_i^2 / 2 + sum_i a_i^2 / 2 cos 2 th_i
    + sum_{i<j} a_i a_j (cos(th_i - th_j) + cos(th_i + th_j)); each cosine's sample mean is Re(e^{i phi} D(w)),
    D(w) = sin(n w dt / 2) / (n sin(w dt / 2)), of variance |D|^2 / 2 over a uniform phase, and distinct terms
    are uncorrelated."""
    def d(w):
        return np.sin(n * w * dt / 2) / (n * np.sin(w * dt / 2))
    a, w = sea.amplitude, sea.omega
    i, j = np.triu_indices(a.size, 1)
    pairs = np.sum((a[i] * a[j]) ** 2 * (d(w[i] - w[j]) ** 2 + d(w[i] + w[j]) ** 2) / 2)
    return math.sqrt(pairs + np.sum(a ** 4 / 4 * d(2 * w) ** 2 / 2))


def test_elevation_record_variance_is_the_spectrum_variance_within_sampling_error():
    """Random phases, deterministic amplitudes: the record's mean square differs from m0 = sum a_i^2 / 2 (the
    spectrum's variance in the range) only by cross terms that average out over the record
    (:func:`_record_error_sd`). Twenty seeds of a 600 s record: each error divided by its standard deviation
    has mean within 4 / sqrt(20) of zero and a scatter of one within the chi-square spread of 20 draws; that
    error is far below the sampling error of a Gaussian sea, sqrt(2 pi / T integral S^2 d omega) (Bendat &
    Piersol, *Random Data*), which random amplitudes would add."""
    hs, tp = 0.5, 4.0
    wp = 2 * math.pi / tp
    duration, dt = 600.0, 0.2
    t = np.arange(0.0, duration, dt)
    normalised, sds = [], []
    for seed in range(20):
        sea = _sea(seed=seed)
        m0 = 0.5 * np.sum(sea.amplitude ** 2)
        sd = _record_error_sd(sea, t.size, dt)
        normalised.append((np.mean(elevation(sea, t, 0.0, 0.0) ** 2) - m0) / sd)
        sds.append(sd / m0)
    normalised = np.array(normalised)
    assert abs(normalised.mean()) < 4 / math.sqrt(normalised.size)
    assert 0.6 < normalised.std() < 1.4
    s2 = quad(lambda w: float(jonswap(w, hs, tp)) ** 2, 0.5 * wp, wp)[0] + \
        quad(lambda w: float(jonswap(w, hs, tp)) ** 2, wp, 4 * wp)[0]
    gaussian = math.sqrt(2 * math.pi / duration * s2) / m0
    assert max(sds) < 0.5 * gaussian     # 600 s, 50 components: 0.8 to 3.6 % of m0 here, a Gaussian sea's 10 %


def test_peak_outside_the_frequency_range_is_refused():
    wp = 2 * math.pi / 4.0
    with pytest.raises(UvmsInputError, match="peak") as info:
        irregular_waves(Spectrum.pierson_moskowitz(0.5, 4.0, frequency_range=(2 * wp, 4 * wp)), components=10)
    assert info.value.path == "frequency_range"


@pytest.mark.parametrize("kwargs, field", [({"components": 0}, "components"), ({"components": 10 ** 6}, "components"),
                                           ({"frequency_range": (2.0, 1.0)}, "frequency_range"),
                                           ({"spreading": -1.0}, "spreading"), ({"water_depth": 0.0}, "water_depth")])
def test_irregular_refusals_name_the_field(kwargs, field):
    span = kwargs.pop("frequency_range", (0.5, 6.0))
    args = {"components": 10} | kwargs
    with pytest.raises(UvmsInputError) as info:
        irregular_waves(Spectrum(lambda w: pierson_moskowitz(w, 0.5, 4.0), 1.5, span), **args)
    assert info.value.path == field


def test_table_spectrum_is_linear_between_points_and_zero_outside():
    density = table_spectrum([1.0, 2.0, 3.0], [0.0, 1.0, 0.0])
    assert np.allclose(density(np.array([0.5, 1.5, 2.0, 2.25, 3.5])), [0.0, 0.5, 1.0, 0.75, 0.0])
    sea = irregular_waves(Spectrum(density, 2.0, (1.0, 3.0)), components=40, seed=1)
    assert Spectrum.table([1.0, 2.0, 3.0], [0.0, 1.0, 0.0])[1:] == (2.0, (1.0, 3.0))
    assert 0.5 * np.sum(sea.amplitude ** 2) == pytest.approx(1.0, rel=1e-12)        # triangle of area 1


# ---------------------------------------------------------------------------------------------- spreading


@pytest.mark.parametrize("s", [1.0, 2.0, 10.0])
def test_spreading_density_is_normalised_and_its_draws_follow_it(s):
    assert quad(lambda b: float(spreading_density(b, s)), -math.pi / 2, math.pi / 2)[0] == pytest.approx(1, rel=1e-9)
    variance = quad(lambda b: b * b * float(spreading_density(b, s)), -math.pi / 2, math.pi / 2)[0]
    sea = _sea(components=4000, spreading=s, direction=0.3)
    offsets = sea.direction - 0.3
    assert np.all(np.abs(offsets) < math.pi / 2)
    n = offsets.size
    assert abs(offsets.mean()) < 4 * math.sqrt(variance / n)
    assert np.mean(offsets ** 2) == pytest.approx(variance, rel=4 * math.sqrt(2.0 / n) * 1.5)


def test_without_spreading_every_component_travels_the_mean_direction():
    assert np.all(_sea(direction=1.2).direction == 1.2)


# ---------------------------------------------------------------------------------------------- elevation


def test_regular_wave_elevation_travels_at_the_phase_speed_in_its_direction():
    wave = regular_waves(0.5, 4.0, direction=math.pi / 2, water_depth=20.0, gravity=G)
    assert isinstance(wave, WaveComponents) and wave.amplitude[0] == 0.25
    k, w = wave.wavenumber[0], wave.omega[0]
    assert w == pytest.approx(2 * math.pi / 4.0)
    assert elevation(wave, 0.0, 0.0, 0.0) == pytest.approx(0.25)              # a crest at the origin
    t, y = np.linspace(0, 10, 11), np.linspace(-5, 5, 11)
    assert np.allclose(elevation(wave, t, 0.0, y), 0.25 * np.cos(k * y - w * t), atol=1e-14)
    c = w / k                                                                 # the crest moves toward +y at c
    assert np.allclose(elevation(wave, 3.0, 7.0, y + 3.0 * c), elevation(wave, 0.0, 7.0, y), atol=1e-12)
    assert np.allclose(elevation(wave, t, 9.0, 0.0), elevation(wave, t, 0.0, 0.0), atol=1e-14)   # no x change


@pytest.mark.parametrize("kwargs, field", [({"height": 0.0}, "height"), ({"height": -1.0}, "height"),
                                           ({"period": 0.0}, "period"), ({"water_depth": -2.0}, "water_depth")])
def test_regular_refusals_name_the_field(kwargs, field):
    args = {"height": 0.5, "period": 4.0, "water_depth": 20.0} | kwargs
    height, period = args.pop("height"), args.pop("period")
    with pytest.raises(UvmsInputError) as info:
        regular_waves(height, period, **args)
    assert info.value.path == field
