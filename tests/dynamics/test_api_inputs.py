"""Issue 17 (class 5): every public entry point checks its arguments at the boundary.

A bad argument (wrong shape or joint count, NaN or infinity, a string or a boolean where numbers go, a
non-bool flag, an object of the wrong type) raises :class:`uvms.errors.UvmsInputError` (one line, naming the
argument), never an ``IndexError``/``TypeError``/plain ``ValueError`` from deep inside, and never a result
computed from memory past the end of an array. Good calls keep working (and the checked arrays are copies).
"""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms import checks
from uvms.dynamics.api import environment
from uvms.dynamics.energy import kinetic_energy, potential_energy, spatial_momentum
from uvms.hydro.added_mass import cylinder_added_mass
from uvms.hydro.drag import box_rotational_drag_by_strips, box_rotational_drag_coefficient
from uvms.errors import UvmsInputError
from uvms.sim.inputs import CurrentTable, TorqueSchedule
from uvms.sim.integrate import pack, unpack
from uvms.sim.run import Actuation, check_steps


@pytest.fixture(scope="module")
def paper():
    return uvms.load_model("paper")


@pytest.fixture(scope="module")
def state(paper):
    return uvms.State.from_euler(paper, euler=[0.1, -0.2, 0.3], nu=[0.1, 0.0, -0.1, 0.2, 0.0, 0.1],
                                 q=[0.3, -0.5, 0.7], qd=[0.1, 0.2, -0.1])


class _Other:
    """Not a model, not a state."""


def _four_joint_state(paper):
    s = uvms.State.zero(paper)
    return uvms.State(position=s.position, quaternion=s.quaternion, nu=s.nu, q=np.zeros(4), qd=np.zeros(4))


BAD_3 = [([1.0, 2.0], "shape (2,)"), ([1.0, 2.0, 3.0, 4.0], "shape (4,)"), ([[1.0, 2.0, 3.0]], "shape (1, 3)"),
         ([1.0, np.nan, 3.0], "nan at index 1"), ([np.inf, 0.0, 0.0], "inf at index 0"), ("abc", "a string 'abc'"),
         (["1", "2", "3"], "values of type <U1"), ([True, False, True], "values of type bool"), ({"a": 1}, "a dict"),
         ([[1.0], [2.0, 3.0]], "got a list"), (3.0, "shape ()")]
"""Bad values for a 3-vector (the paper's joint count, a current) and a fragment of the message each gives."""
BAD_JOINTS = [bad for bad in BAD_3 if not isinstance(bad[0], dict)] + [
    ({"a": 1}, "has no joint 'a'; joints: joint1, joint2, joint3"), ({"joint2": "x"}, "a string 'x'"),
    ({"joint1": np.nan}, "nan")]
"""Joint values may also be ``{joint name: value}`` mappings (``State.from_euler``): bad names and values."""
BAD_6 = [([1.0] * 5, "shape (5,)"), ([1.0] * 7, "shape (7,)"), ([0.0] * 5 + [np.nan], "nan at index 5"),
         ([0.0, -np.inf, 0, 0, 0, 0], "-inf at index 1"), ("wrench", "a string"), (_Other(), "a _Other")]
BAD_FLAG = [("yes", "a string 'yes'"), (1, "1"), (None, "None"), (np.array([True]), "an array")]


def _calls(paper, state):
    """``(label, call(**kwargs), argument, bad values)``: every public function and each of its arguments."""
    fd = lambda **kw: uvms.forward_dynamics(paper, state, **kw)          # noqa: E731
    zero = {"nu_dot": np.zeros(6), "qdd": np.zeros(3)}
    inv = lambda **kw: uvms.inverse_dynamics(paper, state, **{**zero, **kw})  # noqa: E731
    hw = lambda **kw: uvms.hydrodynamic_wrenches(paper, state, **kw)      # noqa: E731
    sim = lambda **kw: uvms.simulate(paper, **{"duration": 0.002, **kw})  # noqa: E731
    fe = lambda **kw: uvms.State.from_euler(paper, **kw)                  # noqa: E731
    s0 = dict(position=np.zeros(3), quaternion=[1.0, 0, 0, 0], nu=np.zeros(6), q=np.zeros(3), qd=np.zeros(3))
    st = lambda **kw: uvms.State(**{**s0, **kw})                          # noqa: E731
    return [
        ("forward_dynamics", fd, "joint_torques", BAD_3),
        ("forward_dynamics", fd, "body_wrench", BAD_6),
        ("forward_dynamics", fd, "ee_wrench", BAD_6),
        ("forward_dynamics", fd, "current", BAD_3),
        ("forward_dynamics", fd, "fluid_acceleration", BAD_3),
        ("forward_dynamics", fd, "fixed_base", BAD_FLAG),
        ("inverse_dynamics", inv, "nu_dot", BAD_6 + [(None, "None")]),
        ("inverse_dynamics", inv, "qdd", BAD_3 + [(None, "None")]),
        ("inverse_dynamics", inv, "ee_wrench", BAD_6),
        ("inverse_dynamics", inv, "current", BAD_3),
        ("bias_forces", lambda **kw: uvms.bias_forces(paper, state, **kw), "fluid_acceleration", BAD_3),
        ("hydrodynamic_wrenches", hw, "joint_torques", BAD_3),
        ("hydrodynamic_wrenches", hw, "body_wrench", BAD_6),
        ("hydrodynamic_wrenches", hw, "current", BAD_3),
        ("hydrodynamic_wrenches", hw, "fixed_base", BAD_FLAG),
        ("State.from_euler", fe, "euler", BAD_3),
        ("State.from_euler", fe, "position", BAD_3),
        ("State.from_euler", fe, "nu", BAD_6),
        ("State.from_euler", fe, "q", BAD_JOINTS),
        ("State.from_euler", fe, "qd", BAD_JOINTS),
        ("State.from_euler", fe, "actuator", [("abc", "a string"), ([np.nan], "nan"), ([[1.0]], "shape (1, 1)")]),
        ("State", st, "position", BAD_3),
        ("State", st, "quaternion", [([1.0, 0, 0], "shape (3,)"), ([0.0, 0, 0, 0], "norm 0"),
                                     ([np.nan, 0, 0, 0], "nan"), ("1000", "a string"), (None, "None")]),
        ("State", st, "nu", BAD_6),
        ("State", st, "q", [("abc", "a string"), ([0.0, np.nan, 0.0], "nan"), (None, "None"),
                            ([[0.0, 0.0, 0.0]], "shape (1, 3)")]),
        ("State", st, "qd", BAD_3),
        ("simulate", sim, "joint_torques", BAD_3),
        ("simulate", sim, "body_wrench", BAD_6),
        ("simulate", sim, "ee_wrench", BAD_6),
        ("simulate", sim, "current", BAD_3[:-1]),
        ("simulate", sim, "fixed_base", BAD_FLAG),
        ("simulate", sim, "duration", [(0.0, "0.0"), (-1.0, "-1.0"), (np.nan, "nan"), (np.inf, "inf"),
                                       ("10", "a string '10'"), (True, "True"), (None, "None")]),
        ("simulate", sim, "step", [(0.0, "0.0"), (np.nan, "nan"), ("1e-3", "a string"), (1.0, "steps"),
                                   (1e-15, "steps")]),
        ("simulate", sim, "integrator", [("euler", "'euler'"), (4, "4"), (None, "None")]),
        ("simulate", sim, "record_period", [(0.0, "0.0"), (np.nan, "nan"), ("1", "a string")]),
        ("simulate", sim, "control_period", [(-0.01, "-0.01"), (np.inf, "inf")]),
        ("simulate", sim, "rtol", [(0.0, "0.0"), ("small", "a string")]),
        ("simulate", sim, "atol", [(-1.0, "-1.0"), (None, "None")]),
        ("simulate", sim, "bounds", [([1.0, 2.0, 3.0], "got"), ([1.0, 2.0, 3.0, -1.0], "got"),
                                     ([1.0, 2.0, 3.0, np.nan], "got"), ("big", "a string")]),
        ("simulate", sim, "initial_state", [(_four_joint_state(paper), "4"), ("rest", "a string"),
                                            (np.zeros(19), "an array")]),
        ("simulate", sim, "controller", [("smc-ab", "a string"), (3, "3")]),
        ("simulate", sim, "actuation", [("paper", "a string"), (Actuation(("paper",)), "a tuple"),
                                        (Actuation(["x"]), "a list")]),
        ("simulate", sim, "progress", [("bar", "a string"), (1, "1")]),
        ("simulate", sim, "metadata", [("note", "a string"), ([1, 2], "a list")]),
        ("TorqueSchedule", lambda **kw: TorqueSchedule(**{"times": [0.0, 1.0], "torques": np.zeros((2, 3)), **kw}),
         "torques", [(np.zeros((3, 3)), "shape (3, 3)"), ([[1.0, 2.0], [1.0]], "different lengths"),
                     ([[1.0, np.nan, 0.0], [0.0, 0.0, 0.0]], "nan at row 0, column 1"), ("abc", "a string")]),
        ("TorqueSchedule", lambda **kw: TorqueSchedule(**{"times": [0.0, 1.0], "torques": np.zeros((2, 3)), **kw}),
         "times", [([1.0, 2.0], "start at 0"), ([0.0, 0.0], "increase"), ("0", "a string"), ([0.0, np.nan], "nan")]),
        ("CurrentTable", lambda **kw: CurrentTable(**{"times": [0.0], "velocity": [[0.1, 0, 0]],
                                                      "acceleration": [[0.0, 0, 0]], **kw}),
         "velocity", [([[0.1, 0.0]], "shape (1, 2)"), ([[np.nan, 0, 0]], "nan"), ("fast", "a string")]),
        ("load_model", lambda name_or_path: uvms.load_model(name_or_path), "name_or_path",
         [(None, "None"), (3, "3"), (["paper"], "a list")]),
        ("Actuation.named", lambda name: Actuation.named(name), "name", [(3, "3"), (["ideal"], "a list")]),
        ("check_steps", lambda duration: check_steps(duration, 1e-3), "duration", [("1", "a string"), (-1, "-1")]),
        ("CurrentTable.from_function", lambda **kw: CurrentTable.from_function(**{
            "velocity": lambda t: [0.1, 0.0, 0.0], "duration": 1.0, "step": 0.1, **kw}), "velocity",
         [("x", "a string"), (lambda t: [0.1, 0.0], "shape (2,)"), (lambda t: [np.nan, 0, 0], "nan")]),
        ("CurrentTable.from_function", lambda **kw: CurrentTable.from_function(**{
            "velocity": lambda t: [0.1, 0.0, 0.0], "duration": 1.0, "step": 0.1, **kw}), "step",
         [(0.0, "0.0"), ("0.1", "a string")]),
        ("CurrentTable.from_velocity_table", lambda **kw: CurrentTable.from_velocity_table(**{
            "times": [0.0, 1.0], "velocity": [[0.1, 0, 0], [0.2, 0, 0]], "duration": 1.0, "step": 0.1, **kw}),
         "velocity", [([[0.1, 0, 0]], "shape (1, 3)"), ([[0.1, 0], [0.2, 0]], "shape (2, 2)")]),
        ("environment", lambda model: environment(model), "model", [("paper", "a string")]),
        ("environment", lambda current: environment(paper, current=current), "current", BAD_3),
        ("pack", lambda state: pack(state), "state", [("s", "a string"), (np.zeros(19), "an array")]),
        ("unpack", lambda x: unpack(x, 3), "x", [(np.zeros(18), "shape (18,)"), ([0.0] * 19, "a list"),
                                                  (np.zeros((1, 19)), "shape (1, 19)")]),
        ("cylinder_added_mass", lambda **kw: cylinder_added_mass(**{"density": 1000.0, "radius": 0.01,
                                                                    "length": 0.2, **kw}), "radius",
         [(-0.01, "-0.01"), ("0.01", "a string"), (np.nan, "nan"), (None, "None")]),
        ("box_rotational_drag_coefficient", lambda **kw: box_rotational_drag_coefficient(**{
            "density": 1000.0, "drag_coefficient": 1.0, "side": 0.6, **kw}), "side", [(-1.0, "-1.0"), ("a", "a str")]),
        ("box_rotational_drag_by_strips", lambda **kw: box_rotational_drag_by_strips(**{
            "density": 1000.0, "drag_coefficient": 1.0, "side": 0.6, "omega": 1.0, **kw}), "n_strips",
         [(0, "0"), (2.5, "2.5"), (True, "True")]),
    ]


def _cases():
    from uvms.model.load import load_model

    paper = load_model("paper")
    state = uvms.State.from_euler(paper, q=[0.3, -0.5, 0.7])
    for label, call, argument, bad_values in _calls(paper, state):
        for k, (value, found) in enumerate(bad_values):
            yield pytest.param(label, call, argument, value, found, id=f"{label}-{argument}-{k}")


@pytest.mark.parametrize("label, call, argument, value, found", list(_cases()))
def test_a_bad_argument_is_a_one_line_input_error_naming_it(label, call, argument, value, found):
    with pytest.raises(UvmsInputError) as info:
        call(**{argument: value})
    message = str(info.value)
    assert message.startswith(f"{argument}: ") or message.startswith(f"{argument} ("), message
    assert found in message, message
    assert "\n" not in message
    assert isinstance(info.value, ValueError)           # the project's error is a ValueError subclass


@pytest.mark.parametrize("function", [uvms.forward_dynamics, uvms.mass_matrix, uvms.bias_forces,
                                      uvms.end_effector_position, uvms.forward_kinematics,
                                      uvms.hydrodynamic_wrenches, kinetic_energy, potential_energy,
                                      spatial_momentum])
def test_a_state_of_the_wrong_joint_count_is_refused_before_any_kernel_runs(paper, function):
    """The kernels would read past the end of ``q`` (plausible numbers from memory): refused at the boundary."""
    s = uvms.State.zero(paper)
    for n in (0, 2, 4, 7):
        wrong = uvms.State(position=s.position, quaternion=s.quaternion, nu=s.nu, q=np.zeros(n), qd=np.zeros(n))
        with pytest.raises(UvmsInputError, match=rf"^state: expected a state of the model's 3 joints, got one of {n} "):
            function(paper, wrong)


def test_inverse_dynamics_refuses_the_wrong_joint_count(paper):
    s = uvms.State.zero(paper)
    wrong = uvms.State(position=s.position, quaternion=s.quaternion, nu=s.nu, q=np.zeros(4), qd=np.zeros(4))
    with pytest.raises(UvmsInputError, match="^state: .* 3 joints"):
        uvms.inverse_dynamics(paper, wrong, nu_dot=np.zeros(6), qdd=np.zeros(4))


@pytest.mark.parametrize("function", [uvms.forward_dynamics, uvms.mass_matrix, uvms.end_effector_position,
                                      uvms.forward_kinematics, uvms.bias_forces, uvms.hydrodynamic_wrenches])
def test_model_and_state_must_be_a_model_and_a_state(paper, state, function):
    with pytest.raises(UvmsInputError, match="^model: expected a uvms Model .*got a string 'paper'"):
        function("paper", state)
    with pytest.raises(UvmsInputError, match="^state: expected a uvms State .*got an array of shape \\(19,\\)"):
        function(paper, np.zeros(19))
    with pytest.raises(UvmsInputError, match="^state: expected a uvms State .*got None"):
        function(paper, None)


def test_state_constructors_refuse_a_non_model(paper):
    with pytest.raises(UvmsInputError, match="^model: "):
        uvms.State.from_euler("paper")
    with pytest.raises(UvmsInputError, match="^model: "):
        uvms.State.zero(None)
    with pytest.raises(UvmsInputError, match="^colour: not a state field; expected one of: position"):
        uvms.State.zero(paper).replace(colour=[1, 2, 3])
    with pytest.raises(UvmsInputError, match=r"^qd: expected 4 finite values \(one per joint, as q\), got shape "):
        uvms.State.zero(paper).replace(q=np.zeros(4))


@pytest.mark.parametrize("argument, value", [("joint_torques", [np.nan, 0, 0]), ("joint_torques", [0, np.inf, 0]),
                                             ("body_wrench", [0, 0, 0, 0, 0, -np.inf]), ("ee_wrench", [np.nan] * 6),
                                             ("current", [np.nan, 0, 0]), ("fluid_acceleration", [0, 0, np.inf])])
def test_forward_dynamics_refuses_non_finite_inputs_instead_of_returning_nan(paper, state, argument, value):
    with pytest.raises(UvmsInputError, match=rf"^{argument}: expected \d finite values"):
        uvms.forward_dynamics(paper, state, **{argument: value})


@pytest.mark.parametrize("argument, value", [("nu_dot", [np.nan, 0, 0, 0, 0, 0]), ("qdd", [0, 0, np.inf]),
                                             ("ee_wrench", [0, 0, 0, np.nan, 0, 0]), ("current", [0, -np.inf, 0])])
def test_inverse_dynamics_refuses_non_finite_inputs_instead_of_returning_nan(paper, state, argument, value):
    kwargs = {"nu_dot": np.zeros(6), "qdd": np.zeros(3), argument: value}
    with pytest.raises(UvmsInputError, match=rf"^{argument}: expected \d finite values"):
        uvms.inverse_dynamics(paper, state, **kwargs)


def test_the_message_of_the_issue(paper, state):
    with pytest.raises(UvmsInputError) as info:
        uvms.forward_dynamics(paper, state, joint_torques=[1.0, 2.0, 3.0, 4.0])
    assert str(info.value) == "joint_torques: expected 3 finite values (one per joint), got shape (4,)"


def test_good_calls_still_work_and_inputs_of_any_numeric_kind_are_taken(paper, state):
    """Lists, integer arrays, float32 and read-only arrays are accepted; the result does not depend on the form."""
    ref = uvms.forward_dynamics(paper, state, joint_torques=np.array([1.0, 0.0, -2.0]))
    ro = np.array([1.0, 0.0, -2.0])
    ro.setflags(write=False)
    for tau in ([1, 0, -2], (1.0, 0.0, -2.0), np.array([1, 0, -2]), np.array([1, 0, -2], dtype=np.float32), ro):
        acc = uvms.forward_dynamics(paper, state, joint_torques=tau)
        np.testing.assert_array_equal(acc.qdd, ref.qdd)
        np.testing.assert_array_equal(acc.nu_dot, ref.nu_dot)
    assert uvms.forward_dynamics(paper, state, fixed_base=np.bool_(False)).qdd.shape == (3,)


def test_checked_vectors_are_fresh_float64_copies():
    caller = np.array([1.0, 2.0, 3.0])
    a = checks.vector(caller, 3, "x")
    assert a is not caller and a.dtype == np.float64 and a.flags.c_contiguous and a.flags.writeable
    a[0] = 9.0
    assert caller[0] == 1.0
    # a finite sum that overflows is still finite input
    np.testing.assert_array_equal(checks.vector([1e308, 1e308, 0.0], 3, "x"), [1e308, 1e308, 0.0])


def test_a_callable_returning_the_wrong_shape_or_nan_is_named(paper):
    with pytest.raises(UvmsInputError, match=r"^joint_torques \(returned at t = 0 s\): expected 3 finite values "
                                             r"\(one per joint\), got shape \(2,\)"):
        uvms.simulate(paper, duration=0.01, joint_torques=lambda t, s: np.zeros(2))
    with pytest.raises(UvmsInputError, match=r"^joint_torques \(returned at t = 0.005 s\): .*got nan at index 1"):
        uvms.simulate(paper, duration=0.01, control_period=0.005,
                      joint_torques=lambda t, s: np.array([0.0, np.nan if t > 0 else 0.0, 0.0]))
    with pytest.raises(UvmsInputError, match=r"^joint_torques \(returned at t = 0 s\): .*got a string"):
        uvms.simulate(paper, duration=0.01, joint_torques=lambda t, s: "zero")
    with pytest.raises(UvmsInputError, match=r"^current \(returned at t = 0 s\): expected 3 finite values"):
        uvms.simulate(paper, duration=0.01, current=lambda t: [0.1, 0.0])


def test_a_controller_returning_a_bad_wrench_is_named(paper):
    from uvms.control.base import ControlOutput

    class Bad:
        period = 0.01

        def update(self, measurement):
            return ControlOutput(wrench=np.zeros(5))

    with pytest.raises(UvmsInputError, match=r"^controller.update\(\).wrench \(returned at t = 0 s\): expected 6"):
        uvms.simulate(paper, duration=0.02, controller=Bad())


def test_a_schedule_for_another_joint_count_names_joint_torques(paper):
    with pytest.raises(UvmsInputError, match="^joint_torques: expected a schedule of 3 torques per row"):
        uvms.simulate(paper, duration=0.01, joint_torques=TorqueSchedule.constant([1.0, 2.0, 3.0, 4.0]))


def test_integrator_names_are_case_insensitive(paper):
    r = uvms.simulate(paper, duration=0.004, integrator="RK4")
    assert r.metadata["integrator"] == "rk4" and r.complete


@pytest.mark.parametrize("call, culprit", [
    (lambda m: uvms.forward_dynamics(m, uvms.State.from_euler(m, nu=[1e200] * 6)), "state.nu"),
    (lambda m: uvms.forward_dynamics(m, uvms.State.from_euler(m, qd=[0.0, 1e200, 0.0])), "state.qd"),
    (lambda m: uvms.forward_dynamics(m, uvms.State.zero(m), joint_torques=[1e308, 1e308, 0.0]), "joint_torques"),
    (lambda m: uvms.forward_dynamics(m, uvms.State.zero(m), current=[1e200, 0.0, 0.0]), "current"),
    (lambda m: uvms.inverse_dynamics(m, uvms.State.zero(m), nu_dot=[1e308] * 6, qdd=np.zeros(3)), "nu_dot"),
    (lambda m: uvms.bias_forces(m, uvms.State.from_euler(m, nu=[0, 0, 0, 1e300, 0, 0])), "state.nu"),
])
def test_finite_inputs_too_large_to_evaluate_are_named_not_returned_as_nan(paper, call, culprit):
    """Finite but huge inputs overflow inside the kernels: an error naming the largest input, never NaN."""
    with pytest.raises(UvmsInputError, match=rf"^{culprit}: expected values the dynamics can evaluate .* overflowed"):
        call(paper)
