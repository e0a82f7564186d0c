"""The plant owner (:mod:`uvms.dynamics.plant`, :class:`uvms.dynamics.api.Dynamics`): checked arguments, the
same arithmetic on every path, and the articulated inertia against an independent algorithm."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import uvms
from uvms.dynamics.api import Dynamics, dynamics_of
from uvms.dynamics.plant import empty_model_data, fluid_table, forward_into, kernel_model, model_data
from uvms.errors import UvmsInputError


@pytest.fixture(scope="module")
def paper():
    return uvms.load_model("paper")


@pytest.fixture(scope="module")
def state(paper):
    rng = np.random.default_rng(4)
    return uvms.State.from_euler(paper, position=[0.3, -1.0, 2.0], euler=[0.2, -0.4, 1.1], nu=rng.normal(size=6),
                                 q=rng.uniform(-1, 1, 3), qd=rng.normal(size=3))


@pytest.mark.parametrize("call, argument", [
    (lambda d, s: d.forward(s, joint_torques=np.zeros(4)), "joint_torques"),
    (lambda d, s: d.forward(s, joint_torques="zero"), "joint_torques"),
    (lambda d, s: d.forward(s, body_wrench=np.zeros((6, 1))), "body_wrench"),
    (lambda d, s: d.forward(s, ee_wrench=[0.0] * 5), "ee_wrench"),
    (lambda d, s: d.forward(s, current=np.array([1, 2])), "current"),
    (lambda d, s: d.forward(s, fluid_acceleration=[np.nan, 0, 0]), "fluid_acceleration"),
    (lambda d, s: d.forward(np.zeros(19)), "state"),
    (lambda d, s: d.inverse(s, nu_dot=np.zeros(5), qdd=np.zeros(3)), "nu_dot"),
    (lambda d, s: d.inverse(s, nu_dot=np.zeros(6), qdd=np.zeros(3, dtype=complex)), "qdd"),
    (lambda d, s: d.mass_matrix("state"), "state"),
])
def test_the_owner_refuses_an_argument_of_the_wrong_type_or_shape(paper, state, call, argument):
    """What used to reach a resolved entry point unchecked (an integer or mis-shaped array read as garbage) is
    one line naming the argument."""
    with pytest.raises(UvmsInputError, match=rf"^{argument}: expected"):
        call(Dynamics(paper), state)


def test_the_owner_refuses_a_non_model_and_a_non_flag():
    with pytest.raises(UvmsInputError, match="^model: expected a uvms Model"):
        Dynamics("paper")
    with pytest.raises(UvmsInputError, match="^fixed_base: expected True or False"):
        Dynamics(uvms.load_model("paper"), fixed_base="yes")


def test_integer_and_float32_inputs_give_the_float64_answer(paper, state):
    d = Dynamics(paper)
    ref = d.forward(state, joint_torques=np.array([1.0, -2.0, 0.0]))
    for tau in (np.array([1, -2, 0]), np.array([1, -2, 0], dtype=np.float32), [1, -2, 0]):
        acc = d.forward(state, joint_torques=tau)
        np.testing.assert_array_equal(acc.nu_dot, ref.nu_dot)
        np.testing.assert_array_equal(acc.qdd, ref.qdd)


def test_every_path_is_the_same_arithmetic(paper, state):
    """``Dynamics.forward`` (packed through the plant) and the compiled wrapper on a ModelData agree bitwise."""
    tau, wrench = np.array([0.5, -1.0, 2.0]), np.array([1.0, 2.0, -3.0, 10.0, -5.0, 4.0])
    acc = Dynamics(paper).forward(state, joint_torques=tau, body_wrench=wrench)
    md = model_data(paper)
    nu_dot, qdd = np.zeros(6), np.zeros(3)
    forward_into(md, np.ascontiguousarray(state.rotation), np.array(state.position), np.array(state.nu),
                 np.array(state.q), np.array(state.qd), tau, wrench, np.zeros(6),
                 fluid_table([0.0], [paper.current], [paper.fluid_acceleration]), 0.0, False, nu_dot, qdd)
    np.testing.assert_allclose(acc.nu_dot, nu_dot, rtol=0, atol=1e-13 * (1 + np.abs(nu_dot).max()))
    np.testing.assert_allclose(acc.qdd, qdd, rtol=0, atol=1e-13 * (1 + np.abs(qdd).max()))


def test_the_articulated_inertia_is_the_schur_complement_of_the_mass_matrix(paper, state):
    """``I_0^*`` (Featherstone 7.1: the inertia the vehicle presents with every joint free) equals
    ``M_00 - M_0q M_qq^-1 M_q0`` of the composite-rigid-body mass matrix: an independent algorithm."""
    d = Dynamics(paper)
    M = d.mass_matrix(state)
    schur = M[:6, :6] - M[:6, 6:] @ np.linalg.solve(M[6:, 6:], M[6:, :6])
    I0 = d.vehicle_articulated_inertia(state)
    np.testing.assert_allclose(I0, schur, rtol=1e-11, atol=1e-11 * np.abs(schur).max())
    I0[0, 0] = -1.0                                    # a copy: the workspace is untouched
    assert d.vehicle_articulated_inertia(state)[0, 0] > 0


def test_each_thread_has_its_own_owner_for_the_convenience_functions(paper, state):
    mine = dynamics_of(paper)
    assert dynamics_of(paper) is mine
    theirs = []
    t = threading.Thread(target=lambda: theirs.append(dynamics_of(paper)))
    t.start()
    t.join()
    assert theirs[0] is not mine and theirs[0].model is paper


def test_a_state_is_views_of_one_vector_in_the_simulation_layout(paper, state):
    """The compiled dynamics take a state's packed vector; its fields are read-only views of it, in the layout of
    :mod:`uvms.sim.integrate` (``pack``), and a ``State.trusted`` of separate arrays gives the same answer."""
    from uvms.sim.integrate import pack, unpack

    np.testing.assert_array_equal(state._packed, pack(state))
    for name in ("position", "quaternion", "nu", "q", "qd", "actuator"):
        assert getattr(state, name).base is state._packed
    assert not state._packed.flags.writeable
    tau = np.array([0.5, -1.0, 2.0])
    ref = Dynamics(paper).forward(state, joint_torques=tau)
    separate = uvms.State.trusted(*(np.array(getattr(state, k)) for k in ("position", "quaternion", "nu", "q",
                                                                          "qd", "actuator")))
    assert separate._packed is None
    for other in (separate, unpack(pack(state), 3)):
        acc = Dynamics(paper).forward(other, joint_torques=tau)
        np.testing.assert_array_equal(acc.nu_dot, ref.nu_dot)
        np.testing.assert_array_equal(acc.qdd, ref.qdd)


def test_a_nan_torque_is_named_though_checked_only_after_the_kernel(paper, state):
    """A float64 torque array of the right shape goes to the kernel unread; a NaN or infinity in it makes the
    accelerations non-finite and the error then names ``joint_torques`` and the entry."""
    d = Dynamics(paper)
    for bad in (np.nan, np.inf, -np.inf):
        tau = np.array([0.0, bad, 0.0])
        with pytest.raises(UvmsInputError, match=r"^joint_torques: expected 3 finite values .* at index 1"):
            d.forward(state, joint_torques=tau)
    acc = d.forward(state, joint_torques=np.zeros(3))          # the workspace is fine afterwards
    np.testing.assert_array_equal(acc.qdd, Dynamics(paper).forward(state).qdd)


# -------------------------------------------------------------- the kernel arrays: built once, in the dynamics


def test_the_kernel_arrays_are_built_once_per_model_and_shared():
    """A model's :class:`KernelModel` is built at the first use and kept with the model: every ``ModelData`` and
    ``Dynamics`` of it reads the same arrays (no copy); a changed model gets its own."""
    from numba import typeof

    model = uvms.load_model("paper").with_hydrodynamics_scaled(added_mass=0.4, drag=0.4)
    km = kernel_model(model)
    assert kernel_model(model) is km
    assert model_data(model).body is km and model_data(model).work is not model_data(model).work
    assert Dynamics(model).data.body is km
    assert all(a.flags.writeable for a in km if isinstance(a, np.ndarray))      # one numba type for all
    heavier = model.replace(mass=model.mass * 2.0)
    assert kernel_model(heavier) is not km
    np.testing.assert_array_equal(kernel_model(heavier).mass, 2.0 * km.mass)
    assert typeof(kernel_model(heavier)) == typeof(km)


def test_the_model_holds_no_kernel_arrays_and_imports_nothing_of_the_dynamics():
    import ast
    from pathlib import Path

    import uvms.model.model as source

    assert not hasattr(uvms.load_model("paper").with_effects(drag=False), "kernel")
    tree = ast.parse(Path(source.__file__).read_text())
    imported = [n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
    assert not [m for m in imported if m and m.startswith("uvms.dynamics")], imported


def test_the_empty_model_data_has_every_models_numba_type_and_reads_no_model_file(monkeypatch):
    """The placeholder of an unused model slot is zero-size arrays of the right types, built without any model
    (it used to load the bundled ``paper`` model file)."""
    from numba import typeof

    import uvms.model.load

    paper = uvms.load_model("paper")

    def refuse(*args, **kwargs):
        raise AssertionError("a model file was read")

    monkeypatch.setattr(uvms.model.load, "load_model", refuse)
    empty = empty_model_data()
    assert typeof(empty) == typeof(model_data(paper))
    assert all(a.size == 0 for part in empty for a in part if isinstance(a, np.ndarray))
    from uvms.control.arm import constant_arm
    from uvms.control.kernels import no_controller

    assert no_controller().system.body.mass.size == 0 and constant_arm([0.0, 0.0]).model.work.v.size == 0
