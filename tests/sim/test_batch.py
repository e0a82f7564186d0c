"""Batched rollouts (:func:`uvms.rollout`): each trajectory is its own ``simulate`` run, to the last bit."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.control.registry import make_controller
from uvms.errors import UvmsInputError
from uvms.sim.batch import Trial
from uvms.sim.inputs import TorqueSchedule


@pytest.fixture(scope="module")
def paper():
    return uvms.load_model("paper")


def _trials(paper, count: int, seed: int = 11) -> list[Trial]:
    rng = np.random.default_rng(seed)
    trials = []
    for k in range(count):
        state = uvms.State.from_euler(paper, position=rng.normal(scale=0.05, size=3),
                                      euler=[0.0, 0.0, rng.uniform(-0.3, 0.3)], q=rng.uniform(-0.5, 0.5, 3))
        torques = TorqueSchedule(times=np.array([0.0, 0.2]),
                                 torques=np.array([[rng.uniform(1, 3), 0.0, 0.0], [0.01, 0.0, 0.0]]))
        controller = make_controller("smc-ab", paper, period=0.01,
                                     parameters={"hydro_scale": float(rng.uniform(0.3, 1.7))})
        trials.append(Trial(initial_state=state, hydro_scale=(float(rng.uniform(0.8, 1.2)), float(rng.uniform(0.8, 1.2))),
                            current=rng.normal(scale=0.1, size=3), joint_torques=torques,
                            controller=controller if k % 4 else None))
    return trials


def test_64_trajectories_equal_their_simulate_runs(paper):
    """The issue's acceptance: every trajectory of a 64-run batch (own initial state, plant scale factors,
    current, joint-torque schedule and controller parameters) against the same run through ``simulate``."""
    shared = make_controller("pid", paper, period=0.01)
    trials = _trials(paper, 64)
    batch = uvms.rollout(paper, trials, duration=0.5, step=1e-3, controller=shared, threads=2)
    assert len(batch) == 64 and batch.complete.all()
    for trial, result in zip(trials, batch.results):
        plant = paper.with_hydrodynamics_scaled(added_mass=trial.hydro_scale[0], drag=trial.hydro_scale[1])
        alone = uvms.simulate(plant, trial.initial_state, duration=0.5, step=1e-3, current=trial.current,
                              joint_torques=trial.joint_torques, controller=trial.controller or shared)
        np.testing.assert_allclose(result.states, alone.states, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(result.time, alone.time)
        for name, values in alone.signals.items():
            np.testing.assert_allclose(result.signals[name], values, rtol=0, atol=1e-9, err_msg=name)
    assert batch.states.shape == (64, len(batch.time), batch[0].states.shape[1])
    assert len(batch.summary()) == 64


def test_states_alone_are_trials(paper):
    states = [uvms.State.zero(paper), uvms.State.from_euler(paper, q=[0.3, 0.0, 0.0])]
    batch = uvms.rollout(paper, states, duration=0.05, threads=1, joint_torques=[1.0, 0.0, 0.0])
    for state, result in zip(states, batch.results):
        alone = uvms.simulate(paper, state, duration=0.05, joint_torques=[1.0, 0.0, 0.0])
        np.testing.assert_array_equal(result.states, alone.states)


@pytest.mark.parametrize("trials, options, argument", [
    ([], {}, "trials"),
    ("paper", {}, "trials"),
    ([42], {}, "trials"),
    (None, {"threads": 0}, "threads"),
    (None, {"threads": 1.5}, "threads"),
    (None, {"progress": "yes"}, "progress"),
    (None, {"threads": 10**6}, "threads"),
])
def test_bad_batches_are_one_line(paper, trials, options, argument):
    with pytest.raises(UvmsInputError, match=rf"^{argument}: expected"):
        uvms.rollout(paper, [uvms.State.zero(paper)] if trials is None else trials, duration=0.01, **options)


def test_a_python_controller_is_sent_to_simulate(paper):
    class Mine:
        period = 0.01

        def update(self, measurement):
            raise AssertionError("never called")

    with pytest.raises(UvmsInputError, match=r"^trials\[0\]: expected bundled controllers"):
        uvms.rollout(paper, [uvms.State.zero(paper)], duration=0.01, controller=Mine())


def test_a_million_trials_are_refused_at_once(paper):
    """``rollout`` of 10^6 trials used to run out of memory building them: more than MAX_TRIALS is one line
    naming ``trials``, in well under a second (nothing built)."""
    import time

    from uvms.sim.batch import MAX_TRIALS

    trials = [uvms.State.zero(paper)] * 10**6
    tic = time.perf_counter()
    with pytest.raises(UvmsInputError, match=rf"^trials: expected at most {MAX_TRIALS} trials in one rollout, got "
                                             r"1000000"):
        uvms.rollout(paper, trials, duration=1.0)
    assert time.perf_counter() - tic < 1.0


def test_records_beyond_the_memory_limit_are_refused_before_they_are_allocated(paper):
    """A batch whose records together exceed MAX_RECORDED_VALUES is refused naming ``trials`` after one plan;
    one run recording every step of a day is refused naming ``record_period`` (simulate and rollout alike)."""
    import time

    from uvms.sim.plan import MAX_RECORDED_VALUES

    tic = time.perf_counter()
    with pytest.raises(UvmsInputError, match=r"^trials: expected at most 2e\+08 recorded values in all, found 5000 "
                                             r"trials x"):
        uvms.rollout(paper, [uvms.State.zero(paper)] * 5000, duration=100.0, record_period=1e-3)
    with pytest.raises(UvmsInputError, match=r"^record_period: expected at most 2e\+08 recorded values"):
        uvms.simulate(paper, duration=86400.0, step=1e-3, record_period=1e-3)
    with pytest.raises(UvmsInputError, match=r"^record_period: expected at most 2e\+08 recorded values"):
        uvms.rollout(paper, [uvms.State.zero(paper)], duration=86400.0, record_period=1e-3)
    assert time.perf_counter() - tic < 3.0 and MAX_RECORDED_VALUES == 2 * 10**8


def test_a_noisy_imu_noise_table_beyond_the_limit_is_refused_at_once(paper):
    """``smc-ne`` with a noisy IMU draws its noise for every update before the run: 5 x 10^8 updates (a
    6 x 8 x 5e8 byte table) are refused naming ``duration``, in well under a second once the kernels are loaded."""
    import time

    controller = make_controller("smc-ne", paper, period=0.001, parameters={"imu_noise": 0.05})
    assert uvms.simulate(paper, duration=0.01, controller=controller).complete
    tic = time.perf_counter()
    with pytest.raises(UvmsInputError, match=r"^duration: expected at most 3.33e\+07 updates of a noisy IMU"):
        uvms.simulate(paper, duration=5e5, step=1e-3, controller=controller)
    assert time.perf_counter() - tic < 1.0
