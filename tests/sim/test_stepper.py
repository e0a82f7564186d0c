"""The step API (:class:`uvms.Simulator`): stepping is the same arithmetic as one long run."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.control.registry import make_controller
from uvms.errors import UvmsInputError
from uvms.sim.inputs import paper_torques
from uvms.sim.integrate import pack


@pytest.fixture(scope="module")
def paper():
    return uvms.load_model("paper")


def test_stepping_10_s_in_10_ms_calls_equals_one_run(paper):
    """The issue's acceptance: 1000 calls of 10 ms with the paper's case 3 (smc-ab, the arm's torque schedule)
    against one 10 s ``simulate``, state by state at every call, to 1e-12."""
    controller = make_controller("smc-ab", paper, period=0.01, parameters={"hydro_scale": 0.4})
    run = uvms.simulate(paper, duration=10.0, step=1e-3, joint_torques=paper_torques(), controller=controller,
                        record_period=0.01)
    sim = uvms.Simulator(paper, step=1e-3, controller=controller, inputs=uvms.Inputs(joint_torques=paper_torques()))
    worst = 0.0
    for k in range(1, 1001):
        state = sim.step(0.01)
        worst = max(worst, float(np.abs(pack(state) - run.states[k]).max()))
    assert sim.time == pytest.approx(10.0, abs=1e-12)
    assert worst <= 1e-12


def test_reset_replays_and_inputs_are_held(paper):
    """Without a controller, a body wrench given to step() is held like simulate's constant body_wrench."""
    wrench = np.array([0.0, 0.0, 1.0, 5.0, -2.0, 0.0])
    sim = uvms.Simulator(paper, step=1e-3)
    for _ in range(2):
        sim.reset()
        for _ in range(10):
            state = sim.step(0.02, body_wrench=wrench, joint_torques=[0.5, 0.0, 0.0])
        run = uvms.simulate(paper, duration=0.2, body_wrench=wrench, joint_torques=[0.5, 0.0, 0.0])
        np.testing.assert_allclose(pack(state), run.states[-1], rtol=0, atol=1e-12)


def test_new_joint_torques_apply_from_the_call_that_gives_them(paper):
    sim = uvms.Simulator(paper, step=1e-3)
    sim.step(0.05, joint_torques=[0.0, 0.0, 0.0])
    state = sim.step(0.05, joint_torques=[2.0, 0.0, 0.0])
    schedule = uvms.TorqueSchedule(times=np.array([0.0, 0.05]), torques=np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]]))
    run = uvms.simulate(paper, duration=0.1, joint_torques=schedule)
    assert abs(state.qd[0]) > 1e-3
    np.testing.assert_allclose(pack(state), run.states[-1], rtol=0, atol=1e-12)


def test_a_torque_schedule_changes_at_its_breakpoint_between_calls(paper):
    """Without a controller the arm's schedule still switches at its breakpoint (2 s), inside a call."""
    sim = uvms.Simulator(paper, step=1e-3, inputs=uvms.Inputs(joint_torques=paper_torques()))
    for _ in range(7):
        state = sim.step(0.35)
    run = uvms.simulate(paper, duration=2.45, step=1e-3, joint_torques=paper_torques())
    np.testing.assert_allclose(pack(state), run.states[-1], rtol=0, atol=1e-12)


def test_reset_to_a_given_state(paper):
    start = uvms.State.from_euler(paper, euler=[0.1, 0.0, 0.0], q=[0.2, -0.1, 0.0])
    sim = uvms.Simulator(paper)
    sim.step(0.01)
    assert sim.reset(start).q.tolist() == pytest.approx([0.2, -0.1, 0.0]) and sim.time == 0.0
    np.testing.assert_allclose(pack(sim.step(0.05)), uvms.simulate(paper, start, duration=0.05).states[-1],
                               rtol=0, atol=1e-12)


@pytest.mark.parametrize("call, argument", [
    (lambda s: s.step(0.0), "duration"),
    (lambda s: s.step(1e-5), "duration"),
    (lambda s: s.step(0.01, joint_torques=[1.0]), "joint_torques"),
    (lambda s: s.step(0.01, body_wrench=[np.nan] * 6), "body_wrench"),
    (lambda s: s.reset("zero"), "state"),
])
def test_bad_steps_are_one_line(paper, call, argument):
    with pytest.raises(UvmsInputError, match=rf"^{argument}: expected"):
        call(uvms.Simulator(paper))


@pytest.mark.parametrize("duration", [1e12, 1e306, 1e6 + 1e-3])
def test_a_step_beyond_the_step_cap_is_refused_at_once(paper, duration):
    """``step(1e12)`` used to compute forever: more than MAX_STEPS (10^9, the scenarios' cap) steps since the
    reset is refused before any step, in well under a second, naming ``duration``; the simulator is untouched."""
    from uvms.sim.plan import MAX_STEPS
    import time

    sim = uvms.Simulator(paper, step=1e-3)
    before = pack(sim.state)
    tic = time.perf_counter()
    with pytest.raises(UvmsInputError, match=r"^duration: expected at most 1e\+09 steps of 0.001 s since the last "
                                             r"reset") as info:
        sim.step(duration)
    assert time.perf_counter() - tic < 1.0 and "\n" not in str(info.value)
    assert sim.steps_done == 0 and np.array_equal(pack(sim.state), before)
    assert MAX_STEPS == 10**9


def test_the_cap_counts_the_steps_since_the_reset(paper, monkeypatch):
    """After 10 steps only MAX_STEPS - 10 are left; a reset gives them back."""
    import uvms.sim.stepper as stepper

    monkeypatch.setattr(stepper, "MAX_STEPS", 100)
    sim = uvms.Simulator(paper, step=1e-3)
    sim.step(0.01)
    with pytest.raises(UvmsInputError, match=r"\(0.09 s left\), got 0.091 s"):
        sim.step(0.091)
    sim.step(0.09)
    assert sim.steps_done == 100
    sim.reset()
    sim.step(0.1)


def test_a_long_step_is_cut_into_bounded_calls_with_the_same_arithmetic(paper, monkeypatch):
    """One ``step`` of 2.5 chunks makes three compiled calls (Ctrl-C is seen between them) and gives the state
    bit for bit that one uncut call gives."""
    import uvms.sim.compiled_loop as compiled_loop
    import uvms.sim.stepper as stepper

    wrench = np.array([0.0, 0.0, 1.0, 5.0, -2.0, 0.0])
    whole = uvms.Simulator(paper, step=1e-3)
    whole.step(0.25, body_wrench=wrench)
    calls = []
    advance = compiled_loop.advance_loop
    monkeypatch.setattr(compiled_loop, "advance_loop", lambda loop, a, b: calls.append(b - a) or advance(loop, a, b))
    monkeypatch.setattr(stepper, "STEP_CHUNK", 100)
    cut = uvms.Simulator(paper, step=1e-3)
    cut.step(0.25, body_wrench=wrench)
    assert calls == [100, 100, 50]
    np.testing.assert_array_equal(pack(cut.state), pack(whole.state))
