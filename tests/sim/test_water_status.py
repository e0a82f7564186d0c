"""A body leaving a gridded current field that says ``outside: error`` stops every kind of run with the same
one line (``current.field.outside``), not only :func:`uvms.simulate`: a rollout names the trial, the step API
raises it from ``step`` (and the gym environments, which step it), a batch of simulators names the member."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import uvms
from uvms.errors import UvmsInputError
from uvms.hydro.flow import Flow

PUSH = np.array([0.0, 0.0, 0.0, 60.0, 0.0, 0.0])
"""A body wrench [N m, N] that carries the paper's vehicle out of the 1 m box within the run."""


def boxed_water(outside: str = "error") -> Flow:
    """A still field on the box |x|, |y| <= 1 m, 0 <= z <= 2 m (values zero: only its edge matters)."""
    axis = np.array([-1.0, 1.0])
    field = SimpleNamespace(x=axis, y=axis, z=np.array([0.0, 2.0]), t=np.array([0.0]),
                            velocity=np.zeros((1, 2, 2, 2, 3)), outside=outside)
    return Flow.constant(field=field)


@pytest.fixture(scope="module")
def paper():
    return uvms.load_model("paper")


def start(paper, x: float = 0.0) -> uvms.State:
    """At rest at (x, 0, 1) m, the arm straight."""
    return uvms.State.from_euler(paper, position=[x, 0.0, 1.0])


def test_simulate_and_rollout_say_which_trial_left_the_field(paper):
    inputs = uvms.Inputs(flow=boxed_water(), body_wrench=PUSH, joint_torques=np.zeros(paper.n_joints))
    with pytest.raises(UvmsInputError, match="current.field.outside") as info:
        uvms.simulate(paper, start(paper), duration=3.0, step=0.01, inputs=inputs)
    assert "field's box" in str(info.value)
    held = uvms.Inputs(flow=boxed_water(), joint_torques=np.zeros(paper.n_joints))       # no push: stays inside
    assert uvms.simulate(paper, start(paper), duration=0.5, step=0.01, inputs=held).time[-1] == pytest.approx(0.5)
    with pytest.raises(UvmsInputError, match=r"trial 1: current\.field\.outside"):
        uvms.rollout(paper, [start(paper), start(paper, 5.0)], duration=0.2, step=0.01, inputs=held, threads=1)


def test_the_step_api_raises_it_from_step_and_forgets_it_at_reset(paper):
    sim = uvms.Simulator(paper, start(paper), step=0.01, inputs=uvms.Inputs(flow=boxed_water(),
                                                                            body_wrench=PUSH))
    with pytest.raises(UvmsInputError, match="current.field.outside"):
        sim.step(3.0)
    sim.reset()
    sim.step(0.1)                                   # back inside: no error left over from the last episode
    assert sim.time == pytest.approx(0.1)


def test_a_batch_of_simulators_names_the_member(paper):
    batch = uvms.BatchSimulator(paper, 2, step=0.01, states=[start(paper), start(paper, 5.0)],
                                inputs=uvms.Inputs(flow=boxed_water()))
    try:
        with pytest.raises(UvmsInputError, match=r"member 1: current\.field\.outside"):
            batch.step(0.1)
    finally:
        batch.close()


def test_a_field_that_holds_its_faces_lets_the_body_go(paper):
    result = uvms.simulate(paper, start(paper), duration=3.0, step=0.01,
                           inputs=uvms.Inputs(flow=boxed_water("hold"), body_wrench=PUSH,
                                              joint_torques=np.zeros(paper.n_joints)))
    assert result.position[-1, 0] > 1.0           # it did leave the box
