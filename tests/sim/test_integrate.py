"""The integrators (issue 4 acceptance): RK4's order, adaptive vs RK4, pitch through 90 deg, clamped and
released vehicles, divergence handling."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.dynamics.energy import spatial_momentum
from uvms.sim.inputs import TorqueSchedule, paper_torques
from uvms.sim.integrate import unpack
from uvms.sim.run import simulate


@pytest.fixture(scope="module")
def paper():
    return uvms.load_model("paper")


def test_rk4_is_fourth_order_on_the_paper_model(paper):
    """Vehicle released, arm driven: log-log slope of the final-state error over step sizes is 4 +/- 0.5."""
    T = 1.5                                   # before the torque switch at 2 s: smooth inputs
    ref = simulate(paper, duration=T, step=1e-4, joint_torques=paper_torques(), record_period=T)
    steps = np.array([0.04, 0.02, 0.01, 0.005])
    errors = []
    for h in steps:
        r = simulate(paper, duration=T, step=h, joint_torques=paper_torques(), record_period=T)
        errors.append(np.abs(r.states[-1] - ref.states[-1]).max())
    slope = np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert 3.5 <= slope <= 4.5, (slope, errors)


@pytest.mark.slow
def test_adaptive_agrees_with_fine_rk4_over_10s(paper):
    """DOP853 (rtol 1e-10) and RK4 at 0.25 ms agree to 1e-6 over the paper's 10 s (released, case 2)."""
    a = simulate(paper, duration=10.0, step=1e-3, joint_torques=paper_torques(), integrator="DOP853",
                 record_period=0.5)
    b = simulate(paper, duration=10.0, step=2.5e-4, joint_torques=paper_torques(), record_period=0.5)
    np.testing.assert_allclose(a.time, b.time)
    assert np.abs(a.states - b.states).max() < 1e-6


def test_pitch_through_90_degrees_is_smooth(paper):
    """An initial pitch rate carries the vehicle through theta = 90 deg: no singularity (quaternion state)."""
    model = paper.with_effects(drag=False, buoyancy=False, gravity=False)
    s0 = uvms.State.from_euler(model, nu=[0.0, 1.2, 0.0, 0.0, 0.0, 0.0])
    rk = simulate(model, s0, duration=3.0, step=1e-3, record_period=0.01)
    ad = simulate(model, s0, duration=3.0, step=1e-3, integrator="DOP853", record_period=0.01)
    pitch = rk.euler[:, 1]
    assert pitch.max() > np.radians(89.0)                            # it went through the top
    assert rk.complete and np.all(np.isfinite(rk.states))
    np.testing.assert_allclose(np.linalg.norm(rk.quaternion, axis=1), 1.0, atol=1e-12)
    assert np.abs(rk.states - ad.states).max() < 1e-7                 # the same smooth solution
    assert np.abs(np.diff(rk.nu[:, 1])).max() < 1e-2                  # no kick in the pitch rate


def test_clamped_vehicle_pose_stays_exactly_zero(paper):
    r = simulate(paper, duration=3.0, step=1e-3, joint_torques=paper_torques(), fixed_base=True, record_period=0.01)
    assert np.all(r.position == 0.0)
    assert np.all(r.quaternion == np.array([1.0, 0.0, 0.0, 0.0]))
    assert np.all(r.nu == 0.0)
    assert np.abs(r.q[-1, 0]) > 1.0                                  # while the arm moves


def test_released_momentum_balance(paper):
    """No drag, no gravity (and so no buoyancy): the arm's torques are internal; the body-plus-fluid momentum
    about the world origin stays at its initial value (zero) to 1e-8 over the run."""
    model = paper.with_effects(drag=False, gravity=False, buoyancy=False)
    sched = TorqueSchedule(times=np.array([0.0, 1.0, 2.0]), torques=np.array([[0.5, 0.2, -0.1], [-0.3, 0.1, 0.05],
                                                                               [0.01, 0.0, 0.0]]))
    r = simulate(model, duration=4.0, step=1e-3, joint_torques=sched, record_period=0.05)
    h = np.array([spatial_momentum(model, unpack(x, 3), include_added_mass=True) for x in r.states])
    scale = max(np.abs(spatial_momentum(model, unpack(x, 3), include_added_mass=False)).max() for x in r.states)
    assert scale > 0.1                                                # the bodies do move
    assert np.abs(h).max() < 1e-8 * max(scale, 1.0)
    assert np.abs(r.position).max() > 1e-3                            # the vehicle reacts


def test_divergence_stops_with_a_message_and_partial_results(paper):
    r = simulate(paper, duration=1.0, step=0.05, joint_torques=[1e7, 0.0, 0.0])
    assert not r.complete
    assert "diverged" in r.message and "smaller step" in r.message
    assert r.time[-1] < 1.0
    assert len(r.time) >= 1


@pytest.mark.parametrize("form", ["function", "table"])
def test_neutral_body_is_carried_by_an_accelerating_current(paper, form):
    """A neutrally buoyant vehicle (m_f = m, centre of buoyancy at the CoM) in a uniformly accelerating current
    is pushed by m_f a_f (Eq. 7) plus I_A a_fluid (Eq. 2) = (m + m_A) a_f: it moves with the fluid, so its velocity
    relative to the current stays zero, during the acceleration and after it stops."""
    from uvms.sim.inputs import CurrentTable

    vehicle = paper.vehicle_only()
    vehicle = vehicle.replace(buoyancy_mass=vehicle.mass, cob=vehicle.com)
    a = np.array([0.3, -0.2, 0.0])
    if form == "function":
        current = lambda t: a * min(t, 1.0)  # noqa: E731  (accelerates for 1 s, then steady)
    else:
        current = CurrentTable.from_velocity_table([0.0, 1.0], [np.zeros(3), a], 2.0, 1e-3)
    r = simulate(vehicle, duration=2.0, step=1e-3, current=current, record_period=0.05)
    v_fluid = np.array([a * min(t, 1.0) for t in r.time])
    # exact but for the one step that straddles the end of the acceleration (O(h a) = 3e-4 m/s at most)
    np.testing.assert_allclose(r.nu[:, 3:], v_fluid, atol=3e-4)
    # no rotation, but for the Munk moment (x-y added-mass difference) of that step's small residual slip
    np.testing.assert_allclose(r.nu[:, :3], 0.0, atol=1e-8)
    np.testing.assert_allclose(r.position[-1], a * 0.5 + a * 1.0, atol=3e-4)   # 0.5 a t^2 then a t


def test_adaptive_divergence_stops_at_the_bad_sample(paper):
    r = simulate(paper, duration=1.0, step=1e-3, joint_torques=[1e7, 0.0, 0.0], integrator="DOP853",
                 record_period=0.01)
    assert not r.complete and "diverged" in r.message
    assert r.time[-1] < 0.1                                              # not at the end of the segment
    assert np.all(np.diff(r.time) > 0)                                   # no duplicated rows


class _Counter:
    """A stand-in controller that counts its updates and logs the time it was called."""

    def __init__(self, period):
        self.period = period
        self.calls = []

    def reset(self):
        self.calls = []

    def update(self, measurement):
        from uvms.control.base import ControlOutput

        self.calls.append(measurement.time)
        return ControlOutput(wrench=np.zeros(6), signals={"called_at": measurement.time})


def test_controller_runs_at_its_own_period_beside_a_faster_arm(paper):
    controller = _Counter(0.01)
    arm_calls = []

    def arm(t, state):
        arm_calls.append(t)
        return np.zeros(3)

    r = simulate(paper, duration=0.1, step=1e-3, controller=controller, joint_torques=arm, control_period=0.002)
    np.testing.assert_allclose(controller.calls, np.arange(10) * 0.01, atol=1e-12)
    np.testing.assert_allclose(arm_calls, np.arange(50) * 0.002, atol=1e-12)
    # logged signals hold the value of the last update at or before each row's time (zero-order hold)
    expected = np.floor(r.time / 0.01 + 1e-9) * 0.01
    np.testing.assert_allclose(r.signals["called_at"], np.minimum(expected, 0.09), atol=1e-12)


class _Sometimes(_Counter):
    """Logs ``count`` always and ``odd`` only on odd updates, in a different order then."""

    def update(self, measurement):
        from uvms.control.base import ControlOutput

        k = len(self.calls)
        self.calls.append(measurement.time)
        signals = {"odd": -float(k), "count": float(k)} if k % 2 else {"count": float(k)}
        return ControlOutput(wrench=np.zeros(6), signals=signals)


def test_a_signal_logged_only_on_some_updates_is_nan_elsewhere(paper):
    r = simulate(paper, duration=0.05, step=1e-3, controller=_Sometimes(0.01))
    update = np.minimum(np.floor(r.time / 0.01 + 1e-9), 4)           # the update each row holds
    np.testing.assert_array_equal(r.signals["count"], update)
    odd = update % 2 == 1
    np.testing.assert_array_equal(r.signals["odd"][odd], -update[odd])
    assert np.all(np.isnan(r.signals["odd"][~odd])) and odd.any() and (~odd).any()


def test_a_schedule_of_the_wrong_width_is_refused(paper):
    with pytest.raises(ValueError, match="3 joints"):
        simulate(paper, duration=0.1, joint_torques=TorqueSchedule.constant([1.0]))


def test_events_are_the_merged_multiples_breakpoints_and_end():
    """The lazily generated stop steps equal the sorted union of every period's multiples, the breakpoints
    and the end (what a set of them would hold, without building one for a long run)."""
    from uvms.sim.run import _events

    rng = np.random.default_rng(3)
    for _ in range(300):
        n_total = int(rng.integers(1, 400))
        periods = tuple(int(p) for p in rng.integers(0, 30, size=2))
        breaks = [int(b) for b in rng.integers(-5, n_total + 5, size=int(rng.integers(0, 5)))]
        expected = {n_total} | set(breaks)
        for p in periods:
            if p:
                expected.update(range(p, n_total, p))
        assert list(_events(n_total, periods, breaks)) == sorted(e for e in expected if 0 < e <= n_total)


def test_sparse_records_hold_the_same_signals_as_a_full_record(paper):
    """With a record every 7 ms and updates every 10 ms, most updates own no row and are not kept; every row
    still holds the signals and torques of the last update at or before it (as in the full 1 ms record)."""
    full = simulate(paper, duration=0.3, step=1e-3, controller=_Sometimes(0.01), joint_torques=paper_torques())
    sparse = simulate(paper, duration=0.3, step=1e-3, controller=_Sometimes(0.01), joint_torques=paper_torques(),
                      record_period=0.007)
    rows = np.searchsorted(full.time, sparse.time - 1e-12)
    np.testing.assert_allclose(full.time[rows], sparse.time, atol=1e-12)
    assert len(sparse.time) == 44                 # 0, 7, ..., 294 ms, and the final state at 300 ms
    np.testing.assert_array_equal(sparse.joint_torques, full.joint_torques[rows])
    for name in ("count", "odd"):
        np.testing.assert_array_equal(sparse.signals[name], full.signals[name][rows])


@pytest.mark.parametrize("duration, step", [(1e300, 1e-3), (1.0, 1e-12), (1e-4, 1e-3), (float("nan"), 1e-3)])
def test_a_run_of_no_steps_or_of_too_many_is_refused(paper, duration, step):
    with pytest.raises(ValueError, match="step"):
        simulate(paper, duration=duration, step=step)
