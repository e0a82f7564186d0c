"""Issue 17: long runs are integrated in bounded compiled calls (Ctrl-C and progress respond), with the same
arithmetic as one call; the final state is always recorded, at exactly ``t = duration``."""

from __future__ import annotations

import os
import signal

import numpy as np
import pytest

import uvms
import uvms.sim.run as run_module
from uvms.sim.inputs import TorqueSchedule, paper_torques
from uvms.sim.run import _next_chunk, simulate


@pytest.fixture(scope="module")
def paper():
    return uvms.load_model("paper")


def _one_call(monkeypatch):
    """Make the first compiled call cover any segment: the unchunked reference."""
    monkeypatch.setattr(run_module, "FIRST_CHUNK_STEPS", 10**9)


def _tiny_calls(monkeypatch):
    """Calls of 16 steps (the floor) whatever they cost."""
    monkeypatch.setattr(run_module, "FIRST_CHUNK_STEPS", 16)
    monkeypatch.setattr(run_module, "CHUNK_SECONDS", 0.0)


@pytest.mark.parametrize("options", [
    dict(duration=1.5, step=1e-3, joint_torques=paper_torques()),
    dict(duration=0.731, step=1e-3, joint_torques=np.array([1.0, -0.5, 0.2]), record_period=0.007,
         current=lambda t: [0.2 * np.sin(3.0 * t), 0.1, 0.0]),          # time enters the derivative
    dict(duration=0.4, step=2e-3, fixed_base=True, joint_torques=np.array([2.0, 0.0, 0.0]), record_period=0.05),
])
def test_a_chunked_run_equals_one_call_bitwise(paper, monkeypatch, options):
    _one_call(monkeypatch)
    whole = simulate(paper, **options)
    _tiny_calls(monkeypatch)
    chunked = simulate(paper, **options)
    np.testing.assert_array_equal(chunked.time, whole.time)
    np.testing.assert_array_equal(chunked.states, whole.states)
    np.testing.assert_array_equal(chunked.joint_torques, whole.joint_torques)
    assert chunked.complete and whole.complete


def test_chunks_do_not_change_a_controlled_run(paper, monkeypatch):
    from uvms.control.registry import make_controller

    def run():
        c = make_controller("smc-ab", paper, period=0.01, parameters={"hydro_scale": 0.4})
        return simulate(paper, duration=0.3, joint_torques=paper_torques(), controller=c)

    _one_call(monkeypatch)
    whole = run()
    _tiny_calls(monkeypatch)
    chunked = run()
    np.testing.assert_array_equal(chunked.states, whole.states)
    for name, values in whole.signals.items():
        np.testing.assert_array_equal(chunked.signals[name], values)


def test_progress_is_reported_during_a_long_segment(paper, monkeypatch):
    """A run without a controller is one held-input segment: progress still comes after every compiled call."""
    _tiny_calls(monkeypatch)
    seen = []
    simulate(paper, duration=0.5, progress=lambda t, T: seen.append((t, T)))
    times = [t for t, _ in seen]
    assert len(times) >= 0.5 / 1e-3 / 16 - 1 and times == sorted(times)
    np.testing.assert_allclose(times[0], 16e-3)
    assert all(T == 0.5 for _, T in seen) and times[-1] == pytest.approx(0.5)


def test_ctrl_c_stops_a_run_between_compiled_calls(paper, monkeypatch):
    """SIGINT delivered during a run without a controller: KeyboardInterrupt surfaces at the end of the current
    compiled call, long before the run would have finished (it used to wait for the whole run)."""
    _tiny_calls(monkeypatch)
    seen = []

    def interrupt_once(t, T):
        seen.append(t)
        if len(seen) == 3:
            os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        simulate(paper, duration=2.0, progress=interrupt_once)
    assert 3 <= len(seen) <= 4 and seen[-1] < 0.1


def test_the_next_call_aims_at_the_chunk_time():
    T = run_module.CHUNK_SECONDS
    assert _next_chunk(1000, 1000 * 1e-5, 1000) == 4000                  # grows at most 4-fold per call
    assert _next_chunk(100_000, 100_000 * 1e-5, 100_000) == int(T / 1e-5)  # 10 us a step: T / 10 us steps
    assert _next_chunk(1000, 10.0, 1000) == 16                            # never below the floor
    assert _next_chunk(10, 1.0, 1000) == 1000                             # a short remainder changes nothing


@pytest.mark.parametrize("duration, step, record_period", [
    (0.0105, 5e-4, 0.002),          # the example: 21 steps, a row every 4
    (0.0105, 1e-4, 0.002),
    (0.0105, 1e-3, 0.004),          # 10 steps of 1.05 ms, a row every 4
    (0.05, 1e-3, 1.0),              # a record period longer than the run: the first and the last state
])
def test_the_final_state_is_always_recorded_at_exactly_the_duration(paper, duration, step, record_period):
    sparse = simulate(paper, duration=duration, step=step, record_period=record_period,
                      joint_torques=paper_torques())
    every = simulate(paper, duration=duration, step=step, record_period=step, joint_torques=paper_torques())
    assert sparse.time[-1] == duration and every.time[-1] == duration
    np.testing.assert_array_equal(sparse.states[-1], every.states[-1])
    assert sparse.complete and np.all(np.diff(sparse.time) > 0)
    # the rows before the last stay on the record grid, and equal the full record's rows at those times
    rows = np.searchsorted(every.time, sparse.time[:-1] - 1e-12)
    np.testing.assert_array_equal(sparse.states[:-1], every.states[rows])
    np.testing.assert_array_equal(sparse.joint_torques[-1], every.joint_torques[-1])
    np.testing.assert_array_equal(sparse.end_effector[-1], every.end_effector[-1])


def test_the_final_state_equals_a_run_to_that_time(paper):
    """The last row of a sparse record is the state at the duration: the same as a run recorded at its end."""
    a = simulate(paper, duration=0.0105, step=5e-4, record_period=0.002, joint_torques=paper_torques())
    b = simulate(paper, duration=0.0105, step=5e-4, record_period=0.0105, joint_torques=paper_torques())
    assert list(b.time) == [0.0, 0.0105]
    np.testing.assert_array_equal(a.states[-1], b.states[-1])


def test_the_default_record_keeps_the_final_state(paper):
    """Above 20 000 steps the default record thins out; the last step was dropped when it was off the grid
    (a 130 s run ended at 129.997 s marked complete)."""
    r = simulate(paper, duration=20.001, step=1e-3, joint_torques=paper_torques())
    assert r.time[-1] == 20.001 and r.time[-2] == pytest.approx(20.0) and r.complete


def test_a_record_that_divides_the_run_has_no_extra_row(paper):
    r = simulate(paper, duration=0.01, step=1e-3, record_period=0.002)
    np.testing.assert_allclose(r.time, np.arange(0.0, 0.0101, 0.002), rtol=0, atol=1e-15)
    assert r.time[-1] == 0.01


def test_the_adaptive_integrator_keeps_the_final_state_too(paper):
    r = simulate(paper, duration=0.0105, step=5e-4, record_period=0.002, integrator="DOP853",
                 joint_torques=TorqueSchedule.constant([0.5, 0.0, 0.0]))
    ref = simulate(paper, duration=0.0105, step=5e-4, integrator="DOP853",
                   joint_torques=TorqueSchedule.constant([0.5, 0.0, 0.0]))
    assert r.time[-1] == 0.0105 and r.complete
    np.testing.assert_allclose(r.states[-1], ref.states[-1], rtol=0, atol=1e-12)
