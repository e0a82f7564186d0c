"""A depth profile's kernel (:func:`uvms.hydro.flow.profile_add`, precomputed segment slopes): its velocity
gradient against central differences of its own velocity (independent of the slope table), zero where the
profile is held, and NaN carried through."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from uvms.hydro.flow import Flow, fluid_at

PROFILE = SimpleNamespace(depth=np.array([0.0, 2.0, 5.0, 10.0, 30.0]),
                          velocity=np.array([[0.5, 0.1, 0.02], [0.4, 0.1, 0.0], [0.3, 0.0, -0.01], [0.1, 0, 0],
                                             [0, 0, 0]]))


@pytest.mark.parametrize("convention,up", [("ned", -1.0), ("enu", 1.0)])
@pytest.mark.parametrize("depth", [0.7, 2.0 + 1e-3, 4.9, 7.5, 29.0])
def test_gradient_is_the_derivative_of_the_velocity(convention, up, depth):
    flow = Flow.constant(profile=PROFILE)
    z = -up * depth                                  # world z of the depth (surface at 0)
    step = 1e-4
    v_up, _ = flow.at(0.0, [0.0, 0.0, z + step], convention)
    v_down, _ = flow.at(0.0, [0.0, 0.0, z - step], convention)
    _, _, grad = flow.kinematics(0.0, [0.0, 0.0, z], convention)
    np.testing.assert_allclose(grad[0][:, 2], (v_up[0] - v_down[0]) / (2 * step), rtol=1e-9, atol=1e-12)
    assert np.all(grad[0][:, :2] == 0.0)
    # the material acceleration of a steady field is (grad u) u
    v, a, _ = flow.kinematics(0.0, [0.0, 0.0, z], convention)
    np.testing.assert_allclose(a[0], grad[0] @ v[0], rtol=1e-14, atol=1e-16)


def test_held_beyond_the_ends_without_gradient_and_nan_propagates():
    flow = Flow.constant(profile=PROFILE)
    v, _, grad = flow.kinematics(0.0, [[0, 0, -1.0], [0, 0, 31.0]], "ned")   # above the surface, below 30 m
    np.testing.assert_array_equal(v, PROFILE.velocity[[0, -1]])
    assert np.all(grad == 0.0)
    data = Flow.constant(profile=PROFILE).compiled("ned")
    out_v, out_a, g = np.zeros(3), np.zeros(3), np.zeros((3, 3))
    fluid_at(data, 0.0, np.array([0.0, 0.0, np.nan]), out_v, out_a, g)
    assert np.all(np.isnan(out_v))
