"""Scenario files that start from the trimmed state (issue 16): ``initial_state: {trimmed: true, q: ...}``
starts at rest at the attitude the system rests at with the arm at ``q``; checked against the physics (the
righting moment vanishes there, unlike at level) and the trim's closed form, and bad input in one line."""

from __future__ import annotations

import math

import numpy as np
import pytest

import uvms
from uvms.analysis.trim import centres
from uvms.errors import UvmsInputError
from uvms.sim.scenario import run_scenario, scenario_from_data

REACHED = [0.05, 2.0, 2.6, 0.05]
"""The Alpha 5 reached forward and down: the BlueROV2 Heavy rests about 10 deg nose down."""


def data(**initial_state):
    return {"model": "bluerov2_heavy_alpha5", "duration": 1.0, "initial_state": initial_state}


def test_trimmed_start_is_at_rest_and_level_is_not():
    """At the trimmed start the weight and buoyancy are on one vertical line: the moment that holds the vehicle
    at rest (RNEA at zero acceleration, the arm held) is (nearly, the system is 0.003 N from neutral) zero, a
    thousand times less than at level with the same arm pose; the attitude is the closed form phi = atan2(d_y, d_z), theta = atan2(-d_x, |d_yz|), d = r_G - r_B
    (docs/conventions.md, "Trim"); the yaw, position and joint angles are the file's."""
    trimmed = scenario_from_data(data(trimmed=True, q=REACHED, euler=[0.0, 0.0, 0.6], position=[1.0, 2.0, 3.0]))
    level = scenario_from_data(data(q=REACHED, euler=[0.0, 0.0, 0.6], position=[1.0, 2.0, 3.0]))
    model = trimmed.model
    start = trimmed.initial_state()
    p_com, p_cob = centres(model, np.array(REACHED))                          # per body, level at the origin
    r_g = model.mass @ p_com / model.mass.sum()
    r_b = model.buoyancy_mass @ p_cob / model.buoyancy_mass.sum()
    d = r_g - r_b
    roll, pitch, yaw = start.euler
    assert roll == pytest.approx(math.atan2(d[1], d[2]), abs=1e-12)
    assert pitch == pytest.approx(math.atan2(-d[0], math.hypot(d[1], d[2])), abs=1e-12)
    assert math.degrees(pitch) < -5.0                                            # nose down: the arm is out
    assert yaw == pytest.approx(0.6, abs=1e-12)
    np.testing.assert_allclose(start.position, [1.0, 2.0, 3.0], atol=0)
    np.testing.assert_allclose(start.q, REACHED, atol=0)
    held = {}
    for name, state in (("trimmed", start), ("level", level.initial_state())):
        f0, _ = uvms.inverse_dynamics(model, state, nu_dot=np.zeros(6), qdd=np.zeros(model.n_joints))
        held[name] = np.abs(f0[0:3]).max()          # moment [N m] that holds the vehicle still, the arm held
    assert held["level"] > 0.3                                                   # from level it pitches
    assert held["trimmed"] < 1e-3 * held["level"]


def test_untrimmed_default_is_unchanged():
    """Without ``trimmed`` the file's Euler angles are used as they are."""
    s = scenario_from_data(data(q=REACHED, euler=[0.1, -0.2, 0.3]))
    np.testing.assert_allclose(s.initial_state().euler, [0.1, -0.2, 0.3], atol=1e-12)


@pytest.mark.parametrize("changes, path, words", [
    ({"trimmed": True, "euler": [0.1, 0.0, 0.0]}, "initial_state.euler", "roll and pitch come from the trim"),
    ({"trimmed": "yes"}, "initial_state.trimmed", ""),
])
def test_bad_trimmed_start_one_line(changes, path, words):
    with pytest.raises(UvmsInputError) as info:
        scenario_from_data(data(q=REACHED, **changes))
    assert path in str(info.value) and words in str(info.value) and "\n" not in str(info.value)


def test_no_rest_attitude_is_one_line():
    """Without gravity there is no rest attitude: one line naming ``initial_state.trimmed`` at load time."""
    spec = data(trimmed=True, q=REACHED)
    spec["model_overrides"] = {"environment": {"gravity": [0.0, 0.0, 0.0]}}
    with pytest.raises(UvmsInputError) as info:
        scenario_from_data(spec)
    assert info.value.path == "initial_state.trimmed" and "no stable rest attitude" in str(info.value)
    assert "\n" not in str(info.value)


def test_trimmed_start_stays_at_rest_while_a_level_start_pitches():
    """Integrated (2 s, the arm held at q by computed torque, no vehicle control): from the trimmed start the
    attitude moves by less than 0.01 deg; from level with the same arm pose the vehicle pitches by degrees."""
    hold = {"joint_trajectory": {"times": [0.0, 1.0], "angles": [REACHED, REACHED]}}
    changes = {}
    for trimmed in (True, False):
        spec = data(trimmed=trimmed, q=REACHED) | {"duration": 2.0, "inputs": hold}
        result = run_scenario(scenario_from_data(spec))
        assert result.complete
        euler = np.degrees(result.euler)
        changes[trimmed] = np.abs(euler - euler[0]).max()
    assert changes[True] < 0.01
    assert changes[False] > 1.0
