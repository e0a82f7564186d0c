"""One event loop: a bundled controller or arm tracker gives the same recorded rows whether the whole loop is
compiled (:func:`uvms.sim.compiled_loop.advance`) or its events run in Python (:mod:`uvms.sim.loop`: the
piece wrapped as a user's Python object), on the paper model and the BlueROV2 Heavy + Alpha 5, with ideal
and modelled thrusters, and controller periods that do and do not divide the record period."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.control.arm import ComputedTorqueArm, JointTrajectory, PdArm
from uvms.control.registry import make_controller
from uvms.sim.compiled_loop import compilable
from uvms.sim.inputs import paper_torques
from uvms.sim.options import Actuation
from uvms.sim.run import prepare, simulate
from uvms.state import State

pytestmark = pytest.mark.filterwarnings("ignore:sliding-mode controller. its b bounds")

CONTROLLERS = [
    ("smc-ab", {}),
    ("smc-ne", {}),                                                        # a perfect IMU (the true nu_dot)
    ("smc-ne", {"imu_noise": 0.05, "imu_bias": 0.01, "imu_delay": 2, "imu_seed": 4}),   # a noisy, late IMU
    ("smc-ne", {"imu_mode": "finite_difference"}),                         # no accelerometer: differences of nu
    ("smc-vehicle", {}),
    ("pid", {}),
]
"""Every bundled controller with a compiled form (``lqr`` has none: :func:`test_lqr_runs_its_events_in_python`)."""

REACH = JointTrajectory([0.0, 0.5, 1.0, 1.5], [[0.05, 0.4, 0.4, 0.05], [0.05, 0.4, 0.4, 0.05],
                                               [0.05, 1.2, 1.6, 0.05], [0.05, 0.4, 0.4, 0.05]])
"""A reach out and back of the Alpha 5 in 1.5 s."""

WAVE = JointTrajectory([0.0, 0.6, 1.2], [[0.0, 0.0, 0.0], [1.0, -0.4, 0.3], [0.2, 0.1, -0.2]])
"""A motion of the paper's three joints."""

DURATION, STEP, RECORD = 2.0, 1e-3, 0.01


@pytest.fixture(scope="module")
def models():
    return {"paper": uvms.load_model("paper"), "bluerov2_heavy_alpha5": uvms.load_model("bluerov2_heavy_alpha5")}


def in_python(piece):
    """``piece`` seen as a user's Python object: a controller subclass whose ``update`` is its own (so
    ``compiled_update`` is false), or an arm callable without ``compiled``."""
    if hasattr(piece, "compiled") and hasattr(piece, "torques"):
        class PythonArm:
            period = piece.period

            def __call__(self, t, state):
                return piece.torques(t, state)
        return PythonArm()
    cls = type(piece)
    piece.__class__ = type(f"Python{cls.__name__}", (cls,), {"update": lambda self, m: cls.update(self, m)})
    assert not getattr(piece, "compiled_update", False)
    return piece


def assert_same_rows(compiled, python) -> None:
    """Every recorded row the same to 1e-12: time, state, joint torques, end effector and every signal."""
    assert compiled.complete == python.complete and compiled.time.size > 100
    np.testing.assert_array_equal(python.time, compiled.time)
    for name in ("states", "joint_torques", "end_effector"):
        np.testing.assert_allclose(getattr(python, name), getattr(compiled, name), rtol=1e-12, atol=1e-12,
                                   err_msg=name)
    assert list(python.signals) == list(compiled.signals)
    for name, column in compiled.signals.items():
        np.testing.assert_allclose(python.signals[name], column, rtol=1e-12, atol=1e-12, err_msg=name)


def setup(models, name: str, thrusters: bool):
    """``(model, initial state, arm input, actuation)`` of a case: the paper's torques on the paper model (Healey
    thrusters: its four), a computed-torque reach on the BlueROV2 (its eight T200)."""
    model = models[name]
    if name == "paper":
        return model, None, paper_torques(), Actuation.named("paper" if thrusters else "ideal")
    start = State.from_euler(model, q=[0.05, 0.4, 0.4, 0.05])
    return model, start, ComputedTorqueArm(model, REACH, base="moving"), (
        Actuation.named("model", model) if thrusters else Actuation.named("ideal"))


@pytest.mark.parametrize("period", [0.005, 0.007], ids=["period-divides-record", "period-does-not-divide"])
@pytest.mark.parametrize("thrusters", [False, True], ids=["ideal", "thrusters"])
@pytest.mark.parametrize("model_name", ["paper", "bluerov2_heavy_alpha5"])
@pytest.mark.parametrize("name, parameters", CONTROLLERS,
                         ids=["smc-ab", "smc-ne", "smc-ne-noisy-imu", "smc-ne-no-imu", "smc-vehicle", "pid"])
def test_each_bundled_controller_gives_the_same_rows_in_both_loops(models, name, parameters, model_name, thrusters,
                                                                   period):
    model, start, arm, actuation = setup(models, model_name, thrusters)
    rows = []
    for python in (False, True):
        controller = make_controller(name, model, period=period, parameters=parameters)
        if python:
            controller = in_python(controller)
        kw = dict(duration=DURATION, step=STEP, controller=controller, actuation=actuation, joint_torques=arm,
                  record_period=RECORD)
        assert compilable(prepare(model, start, **kw)) is not python
        rows.append(simulate(model, start, **kw))
    assert_same_rows(*rows)
    assert "command_X" in rows[0].signals and len(rows[0].signals) > 6


@pytest.mark.parametrize("tracker", ["computed-torque-fixed", "computed-torque-moving", "pd"])
@pytest.mark.parametrize("period", [0.004, 0.013])
def test_arm_trackers_give_the_same_rows_in_both_loops(models, tracker, period):
    """A bundled tracker compiled, or called from Python, with a compiled or a Python controller (each mix
    runs the Python loop): the same rows."""
    model = models["paper"]

    def arm():
        if tracker == "pd":
            return PdArm(WAVE, kp=1.0, kd=0.1, period=period)      # the default 25, 5 are stiff for these links
        return ComputedTorqueArm(model, WAVE, base=tracker.rsplit("-", 1)[1], period=period)

    rows = []
    for python_arm, python_controller in ((False, False), (True, False), (False, True), (True, True)):
        controller = make_controller("smc-ab", model, period=0.01)
        kw = dict(duration=DURATION, step=STEP, record_period=0.006, actuation=Actuation.named("paper"),
                  controller=in_python(controller) if python_controller else controller,
                  joint_torques=in_python(arm()) if python_arm else arm())
        assert compilable(prepare(model, **kw)) is not (python_arm or python_controller)
        rows.append(simulate(model, **kw))
    for python in rows[1:]:
        assert_same_rows(rows[0], python)


@pytest.mark.parametrize("model_name", ["paper", "bluerov2_heavy_alpha5"])
def test_lqr_runs_its_events_in_python(models, model_name):
    """``lqr`` has no compiled form: it always runs in the Python loop, and there a bundled arm input is the
    compiled one; called from Python instead, it gives the same rows."""
    model, start, _, actuation = setup(models, model_name, True)
    trajectory = WAVE if model_name == "paper" else REACH
    rows = []
    for python_arm in (False, True):
        arm = ComputedTorqueArm(model, trajectory, period=0.007)
        kw = dict(duration=DURATION, step=STEP, record_period=RECORD, actuation=actuation,
                  controller=make_controller("lqr", model, period=0.005),
                  joint_torques=in_python(arm) if python_arm else arm)
        assert not compilable(prepare(model, start, **kw))
        rows.append(simulate(model, start, **kw))
    assert_same_rows(*rows)


def test_an_adaptive_integrator_runs_the_bundled_controller_compiled(models):
    """With an adaptive integrator the events run in Python; a bundled controller there is the compiled one and
    equals its Python update, row by row (the same solver steps: the segments run from event to event)."""
    model = models["paper"]
    rows = []
    for python in (False, True):
        controller = make_controller("smc-ab", model, period=0.02)
        rows.append(simulate(model, duration=1.0, step=0.01, integrator="RK45", joint_torques=paper_torques(),
                             controller=in_python(controller) if python else controller,
                             actuation=Actuation.named("paper")))
    assert_same_rows(*rows)
