"""A model's constant disturbance wrench (``Model.disturbance_wrench``) against a closed form, and honoured by
every way of running the model exactly as the same wrench held as ``inputs.body_wrench``."""

import numpy as np
import pytest

import uvms
from uvms.model.parameters import with_parameters
from uvms.sim.integrate import pack
from uvms.sim.joint_motion import JointMotion

WRENCH = np.array([0.3, -0.2, 0.1, 4.0, -1.5, 2.0])


def test_a_constant_surge_force_against_linear_damping_reaches_x_over_d():
    """Vehicle alone, centre of mass at its origin, only linear surge damping ``d``, no gravity, buoyancy or
    added mass: ``m v' = X - d v``, so ``v(t) = (X / d) (1 - exp(-d t / m))`` (and ``X / d`` at the end)."""
    vehicle = uvms.load_model("paper").vehicle_only().with_effects(added_mass=False, drag=False, buoyancy=False,
                                                                   gravity=False)
    vehicle = vehicle.replace(com=np.zeros((1, 3)))
    d, X = 40.0, 6.0
    model = with_parameters(vehicle, {"damping.linear.surge": d, "disturbance.surge": X})
    m = float(model.mass[0])
    result = uvms.simulate(model, duration=20.0 * m / d, step=0.01, record_period=0.1)
    t = np.asarray(result.time)
    surge = np.asarray(result.states)[:, 7 + 3]
    np.testing.assert_allclose(surge, X / d * (1.0 - np.exp(-d * t / m)), rtol=0, atol=1e-9 * X / d)
    assert surge[-1] == pytest.approx(X / d, rel=1e-8)
    np.testing.assert_allclose(np.asarray(result.states)[:, [7, 8, 9, 11, 12]], 0.0, atol=1e-12)


def _pair(model):
    """``model`` with the disturbance, and the model without it plus the same wrench held as an input."""
    return with_parameters(model, dict(zip([f"disturbance.{a}" for a in uvms.model.parameters.AXES], WRENCH))), \
        uvms.Inputs(body_wrench=WRENCH)


def _start(model):
    return uvms.State.zero(model).replace(q=np.full(model.n_joints, 0.2))


def test_simulate_and_rollout_honour_the_disturbance_as_a_held_body_wrench():
    base = uvms.load_model("paper")
    disturbed, held = _pair(base)
    a = uvms.simulate(disturbed, _start(base), duration=1.0, step=0.005, record_period=0.05)
    b = uvms.simulate(base, _start(base), duration=1.0, step=0.005, record_period=0.05, inputs=held)
    np.testing.assert_array_equal(np.asarray(a.states), np.asarray(b.states))
    assert np.abs(np.asarray(a.states)[-1, :3]).max() > 1e-3          # it moved the vehicle
    c = uvms.rollout(disturbed, [_start(base)], duration=1.0, step=0.005, record_period=0.05, threads=1)
    np.testing.assert_array_equal(np.asarray(c[0].states), np.asarray(a.states))


def test_the_step_api_honours_the_disturbance_beside_the_wrench_it_is_given():
    base = uvms.load_model("paper")
    disturbed, _ = _pair(base)
    a = uvms.Simulator(disturbed, _start(base), step=0.005)
    b = uvms.Simulator(base, _start(base), step=0.005)
    extra = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0])
    sa = a.step(0.5, body_wrench=extra)
    sb = b.step(0.5, body_wrench=extra + WRENCH)
    np.testing.assert_allclose(pack(sa), pack(sb), rtol=0, atol=1e-12)
    assert np.abs(sa.position).max() > 1e-3


def test_the_prescribed_joint_loop_honours_the_disturbance():
    base = uvms.load_model("paper")
    disturbed, held = _pair(base)
    t = np.linspace(0.0, 1.0, 21)
    motion = JointMotion.from_arrays(t, np.stack([0.2 + 0.3 * np.sin((j + 1) * 2.0 * t) for j in range(3)], 1))
    a = uvms.simulate(disturbed, _start(base), duration=1.0, step=0.005, inputs=uvms.Inputs(joint_motion=motion))
    b = uvms.simulate(base, _start(base), duration=1.0, step=0.005,
                      inputs=uvms.Inputs(joint_motion=motion, body_wrench=WRENCH))
    np.testing.assert_array_equal(np.asarray(a.states), np.asarray(b.states))


def test_a_zero_disturbance_leaves_a_run_bit_identical():
    base = uvms.load_model("paper")
    zero = base.replace(disturbance_wrench=np.zeros(6))
    a = uvms.simulate(base, _start(base), duration=0.5, step=0.005)
    b = uvms.simulate(zero, _start(base), duration=0.5, step=0.005)
    np.testing.assert_array_equal(np.asarray(a.states), np.asarray(b.states))


def test_the_same_disturbance_and_point_load_written_z_up_give_the_same_motion(tmp_path):
    """The paper model z down with a disturbance ``w`` and a foam block at ``r`` on the vehicle, against the same
    robot written z up by hand (``tests/sim/test_frame_equivalence.py``) with ``H6 w`` and ``H r``: the same
    motion to 1e-12 after the frame change (``p -> H p``, ``nu -> H6 nu``, ``q`` unchanged)."""
    import yaml

    from tests.sim.test_frame_equivalence import H, flip, write_paper_enu
    from uvms.model.load import resolve_model_path

    r = [0.12, 0.03, -0.1]
    ned_spec = yaml.safe_load(resolve_model_path("paper").read_text())
    ned_spec["disturbance_wrench"] = [float(v) for v in WRENCH]
    ned_spec["point_loads"] = [{"name": "foam", "body": "vehicle", "position": r, "buoyancy": 0.6}]
    (tmp_path / "ned.yaml").write_text(yaml.safe_dump(ned_spec, sort_keys=False))
    enu_spec = yaml.safe_load(write_paper_enu(tmp_path).read_text())
    enu_spec["disturbance_wrench"] = flip(WRENCH[:3]) + flip(WRENCH[3:])
    enu_spec["point_loads"] = [{"name": "foam", "body": "vehicle", "position": flip(r), "buoyancy": 0.6}]
    (tmp_path / "enu.yaml").write_text(yaml.safe_dump(enu_spec, sort_keys=False))
    ned, enu = uvms.load_model(tmp_path / "ned.yaml"), uvms.load_model(tmp_path / "enu.yaml")
    a = uvms.simulate(ned, _start(ned), duration=1.0, step=0.005, record_period=0.05)
    b = uvms.simulate(enu, _start(enu), duration=1.0, step=0.005, record_period=0.05)
    xa, xb = np.asarray(a.states), np.asarray(b.states)
    H6 = np.kron(np.eye(2), H)
    assert np.abs(xa[-1, :3]).max() > 1e-3
    np.testing.assert_allclose(xb[:, :3], xa[:, :3] @ H.T, rtol=0, atol=1e-12)
    np.testing.assert_allclose(xb[:, 7:13], xa[:, 7:13] @ H6.T, rtol=0, atol=1e-12)
    np.testing.assert_allclose(xb[:, 13:19], xa[:, 13:19], rtol=0, atol=1e-12)
    np.testing.assert_allclose(enu.disturbance_wrench, ned.in_frame("enu").disturbance_wrench, rtol=0, atol=0)
