"""The measurement models on truths built by hand (no simulation): the DVL's range limit and dropouts, a
static IMU's reading of gravity, and quantisation."""

from __future__ import annotations

import numpy as np
import pytest

from uvms.sensors import Dvl, Imu, Mount, PressureSensor, Truth
from uvms.sensors.base import quantised


def _truth(K, *, z=None, convention="ned", nu=None):
    z = np.zeros(K) if z is None else np.asarray(z, float)
    position = np.stack([np.zeros(K), np.zeros(K), z], 1)
    g = np.array([0.0, 0.0, 9.81 if convention == "ned" else -9.81])
    return Truth(time=np.arange(K) * 0.1, position=position, rotation=np.tile(np.eye(3), (K, 1, 1)),
                 nu=np.zeros((K, 6)) if nu is None else np.tile(nu, (K, 1)), nu_dot=np.zeros((K, 6)),
                 q=np.zeros((K, 0)), gravity=g, convention=convention)


def test_dvl_bottom_track_only_within_its_altitudes():
    """Altitude = water_depth - depth; outside [min_altitude, max_altitude] the bottom track is NaN, valid 0,
    and the water track is still measured."""
    z = np.linspace(0.0, 60.0, 61)                  # depth 0 .. 60 m over a bottom at 50 m
    dvl = Dvl(water_depth=50.0, min_altitude=0.5, max_altitude=30.0)
    r = dvl.measure(_truth(61, z=z, nu=[0, 0, 0, 1.0, 0, 0]))
    altitude = 50.0 - z
    np.testing.assert_allclose(r["altitude"], altitude)
    inside = (altitude >= 0.5) & (altitude <= 30.0)
    np.testing.assert_array_equal(r["bottom_valid"], inside.astype(float))
    assert np.all(np.isnan(r["bottom_x"][~inside])) and np.all(r["bottom_x"][inside] == 1.0)
    assert np.all(r["water_x"] == 1.0)


def test_dvl_dropouts_have_their_probability():
    """20 000 samples with dropout 0.2: the dropped fraction is 0.2 within 4 binomial standard deviations."""
    K, p = 20_000, 0.2
    r = Dvl(dropout=p, seed=9).measure(_truth(K))
    dropped = 1.0 - r["bottom_valid"].mean()
    assert abs(dropped - p) < 4 * np.sqrt(p * (1 - p) / K)
    again = Dvl(dropout=p, seed=9).measure(_truth(K))
    np.testing.assert_array_equal(r["bottom_valid"], again["bottom_valid"])


@pytest.mark.parametrize("convention", ["ned", "enu"])
def test_a_level_imu_at_rest_reads_minus_gravity_and_a_pressure_sensor_rho_g_depth(convention):
    """At rest and level the accelerometer measures -g (1 g upward: -9.81 on z down, +9.81 on z up), the gyro
    zero; a turned mount reads it in its own axes; depth 10 m reads p_atm + rho g 10 in either convention."""
    t = _truth(3, z=[10.0] * 3 if convention == "ned" else [-10.0] * 3, convention=convention)
    r = Imu().measure(t)
    np.testing.assert_allclose(r["accel_z"], -t.gravity[2])
    np.testing.assert_allclose([r["accel_x"], r["accel_y"], r["gyro_x"]], 0.0, atol=1e-15)
    turned = Imu(mount=Mount.of(rpy=(np.pi / 2, 0.0, 0.0))).measure(t)      # sensor y along body z
    np.testing.assert_allclose(turned["accel_y"], -t.gravity[2], atol=1e-12)
    np.testing.assert_allclose(turned["accel_z"], 0.0, atol=1e-12)
    p = PressureSensor(density=1025.0, atmosphere=1e5).measure(t)
    np.testing.assert_allclose(p["pressure"], 1e5 + 1025.0 * 9.81 * 10.0)


def test_quantisation_rounds_to_the_nearest_count():
    np.testing.assert_array_equal(quantised(np.array([0.04, 0.06, -0.14]), 0.1), [0.0, 0.1, -0.1])
    np.testing.assert_array_equal(quantised(np.array([0.123]), 0.0), [0.123])
