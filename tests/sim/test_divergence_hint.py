"""A run that diverges because a joint's friction is too stiff for the step names that joint and its
``friction_speed`` (with the value that would keep RK4 stable), not only "a smaller step"."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.sim.record import RK4_STABILITY, divergence_hint, stiff_joint

REAL_ARM_FRICTION = 1000.0      # N m: UUV Simulator's Oberon 7 joints (the newcomer's case)


@pytest.fixture(scope="module")
def stiff():
    """The BlueROV2 Heavy + Alpha 5 with a real arm's joint friction on its shoulder joint ``axis_d``."""
    model = uvms.load_model("bluerov2_heavy_alpha5")
    return model.replace(joint_friction=np.array([0.0, REAL_ARM_FRICTION, 0.0, 0.0]))


def test_the_stiff_joint_is_found_with_its_time_constant(stiff):
    j, J, tau, speed = stiff_joint(stiff, 1e-3)
    assert stiff.joint_names[j] == "axis_d"
    assert tau == pytest.approx(J * 0.01 / REAL_ARM_FRICTION)        # J v_s / F_c, no damping
    assert speed == pytest.approx(REAL_ARM_FRICTION * 1e-3 / J)      # tau = h at that friction speed
    relaxed = stiff.replace(joint_friction_speed=np.array([0.01, speed, 0.01, 0.01]))
    assert stiff_joint(relaxed, 1e-3) is None                       # h = tau < 2.785 tau: stable
    assert stiff_joint(stiff, RK4_STABILITY * tau * 0.99) is None


def test_hint_names_the_joint_and_friction_speed(stiff):
    hint = divergence_hint(stiff, 1e-3)
    assert hint.startswith("joint 'axis_d' is too stiff for the step 0.001 s: friction 1000 over friction_speed 0.01")
    assert "raise joints.axis_d.friction_speed in the model file to at least" in hint
    assert "\n" not in hint


def test_without_friction_the_hint_is_a_smaller_step():
    assert divergence_hint(uvms.load_model("bluerov2_heavy_alpha5"), 1e-3) == "try a smaller step (now 0.001 s)"
    assert divergence_hint(uvms.load_model("paper"), 1e-3) == "try a smaller step (now 0.001 s)"


def test_a_diverging_run_says_it(stiff):
    """The run itself, every joint with the real arm's friction (released vehicle, arm under gravity): it
    diverges at a 1 ms step, and the message names the stiffest joint (the light wrist ``axis_b``)."""
    import warnings

    model = stiff.replace(joint_friction=np.full(4, REAL_ARM_FRICTION))
    assert model.joint_names[stiff_joint(model, 1e-3)[0]] == "axis_b"
    state = uvms.State.from_euler(model, q=[0.05, 0.4, 0.4, 0.05])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")          # joint-limit crossings of the chattering joints
        result = uvms.simulate(model, duration=0.2, step=1e-3, initial_state=state)
    assert not result.complete
    assert "diverged" in result.message and "joint 'axis_b' is too stiff for the step 0.001 s" in result.message
    assert "raise joints.axis_b.friction_speed in the model file to at least" in result.message
    assert "try a smaller step" not in result.message
