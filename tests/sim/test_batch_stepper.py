"""BatchSimulator: N step-API loops advanced together give each member's own Simulator / simulate numbers."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.errors import UvmsInputError
from uvms.sim.batch_stepper import BatchSimulator
from uvms.sim.integrate import pack
from uvms.sim.options import Inputs
from uvms.sim.stepper import Simulator


@pytest.fixture(scope="module")
def model():
    return uvms.load_model("paper")


def _inputs(k: int) -> Inputs:
    return Inputs(joint_torques=np.array([0.5 * k, -0.2, 0.1]), current=np.array([0.05 * k, -0.02, 0.0]))


@pytest.mark.parametrize("threads", [1, 2])
def test_members_match_their_own_simulators(model, threads):
    """Same calls, same arithmetic: each member equals a Simulator stepped alone, to the last bit."""
    n = 3
    rng = np.random.default_rng(4)
    states = [uvms.State.from_euler(model, position=rng.normal(0, 0.1, 3), euler=rng.normal(0, 0.1, 3))
              for _ in range(n)]
    batch = BatchSimulator(model, n, step=1e-3, inputs=[_inputs(k) for k in range(n)], states=states,
                           threads=threads)
    alone = [Simulator(model, states[k], step=1e-3, inputs=_inputs(k)) for k in range(n)]
    for call in range(4):
        wrenches = rng.normal(0.0, 5.0, (n, 6))
        x = batch.step(0.01, commands=wrenches)
        for k in range(n):
            expected = pack(alone[k].step(0.01, command=wrenches[k]))
            np.testing.assert_array_equal(x[k], expected)
    np.testing.assert_allclose(batch.time, 0.04, rtol=0, atol=1e-15)
    assert not np.array_equal(batch.x[0], batch.x[1])          # the members really differ
    batch.close()


def test_stepping_equals_one_simulate_run(model):
    """0.3 s in 10 ms calls with an external body wrench held = one 0.3 s simulate (issue 14's step API test,
    through the batch)."""
    wrench = np.array([0.0, 0.0, 1.0, 10.0, 0.0, -2.0])
    state = uvms.State.from_euler(model, euler=[0.05, -0.02, 0.1])
    batch = BatchSimulator(model, 2, step=1e-3, inputs=_inputs(1), states=[state, state], threads=2)
    for _ in range(30):
        x = batch.step(0.01, body_wrenches=np.tile(wrench, (2, 1)))
    result = uvms.simulate(model, state, duration=0.3, step=1e-3, inputs=Inputs(
        joint_torques=_inputs(1).joint_torques, current=_inputs(1).current, body_wrench=wrench))
    np.testing.assert_allclose(x[0], result.states[-1], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(x[0], x[1])
    assert np.linalg.norm(x[0][:3] - state.position) > 1e-3        # it moved


def test_reset_restarts_one_member(model):
    """A reset member replays its first steps exactly; the others carry on."""
    batch = BatchSimulator(model, 2, step=1e-3, inputs=_inputs(2), threads=1)
    first = batch.step(0.02, commands=np.ones((2, 6))).copy()
    batch.step(0.02, commands=np.ones((2, 6)))
    batch.reset(0)
    assert batch.done[0] == 0 and batch.done[1] == 40
    again = batch.step(0.02, commands=np.ones((2, 6)))
    np.testing.assert_array_equal(again[0], first[0])
    active = np.array([False, True])
    before = batch.x.copy()
    batch.advance(5, np.ones((2, 6)), 1, active)
    np.testing.assert_array_equal(batch.x[0], before[0])
    assert batch.done[1] == 65                                  # 3 x 20 steps, then 5


def test_bad_inputs_name_the_argument(model):
    batch = BatchSimulator(model, 2, step=1e-3, threads=1)
    with pytest.raises(UvmsInputError, match="commands"):
        batch.step(0.01, commands=np.ones((3, 6)))
    with pytest.raises(UvmsInputError, match="body_wrenches"):
        batch.step(0.01, body_wrenches=np.ones((2, 5)))
    with pytest.raises(UvmsInputError, match="index"):
        batch.reset(2)
    with pytest.raises(UvmsInputError, match="inputs"):
        BatchSimulator(model, 2, inputs=[Inputs()])


def test_members_with_a_bundled_controller_equal_their_simulate_runs(model):
    """The paper's case 3 set-up (smc-ab every 10 ms, the arm's torque schedule): each member, from its own
    initial state and with its own controller memory, follows its own 1 s simulate run to 1e-12."""
    from uvms.control.registry import make_controller
    from uvms.sim.inputs import paper_torques

    controller = make_controller("smc-ab", model, period=0.01, parameters={"hydro_scale": 0.4})
    states = [uvms.State.from_euler(model, position=[0.0, 0.1 * k, 0.0], euler=[0.0, 0.0, 0.05 * k])
              for k in range(2)]
    batch = BatchSimulator(model, 2, step=1e-3, controller=controller, states=states, threads=2,
                           inputs=Inputs(joint_torques=paper_torques()))
    runs = [uvms.simulate(model, s, duration=1.0, step=1e-3, controller=controller, joint_torques=paper_torques(),
                          record_period=0.01) for s in states]
    worst = 0.0
    for k in range(1, 101):
        x = batch.step(0.01)
        worst = max(worst, max(float(np.abs(x[j] - runs[j].states[k]).max()) for j in range(2)))
    assert worst <= 1e-12
    assert np.abs(runs[0].states[-1] - runs[1].states[-1]).max() > 1e-3       # two different trajectories
    with pytest.raises(UvmsInputError, match="commands"):
        batch.step(0.01, commands=np.zeros((2, 6)))


def test_sizes_and_steps_beyond_the_limits_are_refused_at_once(model):
    """10^6 members (each its own compiled loop) and a step beyond the step cap: one line naming the argument,
    refused in well under a second, nothing built or advanced."""
    import time

    from uvms.sim.batch_stepper import MAX_MEMBERS

    tic = time.perf_counter()
    with pytest.raises(UvmsInputError, match=rf"^n: expected at most {MAX_MEMBERS} members, got 1000000"):
        BatchSimulator(model, 10**6, step=1e-3)
    with pytest.raises(UvmsInputError, match=r"^threads: expected at most 1024 threads, got 1000000"):
        BatchSimulator(model, 2, step=1e-3, threads=10**6)
    assert time.perf_counter() - tic < 1.0
    batch = BatchSimulator(model, 2, step=1e-3, threads=1)
    before = batch.x.copy()
    tic = time.perf_counter()
    with pytest.raises(UvmsInputError, match=r"^duration: expected at most 1e\+09 steps"):
        batch.step(1e12)
    assert time.perf_counter() - tic < 1.0
    np.testing.assert_array_equal(batch.x, before)
    assert (batch.done == 0).all()
