"""Prescribed joint motion (``Inputs(joint_motion=...)``): the interpolant, whole runs against an independent
RK4 of the ordinary forward dynamics, momentum conservation, rollout, scenario files and bad inputs."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.dynamics.energy import spatial_momentum
from uvms.errors import UvmsInputError
from uvms.sim.integrate import unpack
from uvms.sim.joint_motion import JointMotion
from uvms.state import StateLayout


def sine_motion(n: int, duration: float = 1.0, rows: int = 41) -> JointMotion:
    t = np.linspace(0.0, duration, rows)
    return JointMotion.from_arrays(t, np.stack([0.4 * np.sin((j + 1) * 2.0 * t) + 0.2 * j for j in range(n)], 1))


def test_the_spline_reproduces_a_cubic_exactly_and_a_sine_to_spline_accuracy():
    t = np.linspace(0.0, 2.0, 21)
    cubic = JointMotion.from_arrays(t, 1.0 - 0.5 * t + 0.3 * t**2 - 0.2 * t**3)   # not-a-knot: exact for cubics
    s = np.linspace(0.0, 2.0, 401)
    q, qd, qdd = cubic(s)
    assert np.allclose(q[:, 0], 1.0 - 0.5 * s + 0.3 * s**2 - 0.2 * s**3, rtol=0, atol=1e-13)
    assert np.allclose(qd[:, 0], -0.5 + 0.6 * s - 0.6 * s**2, rtol=0, atol=1e-12)
    assert np.allclose(qdd[:, 0], 0.6 - 1.2 * s, rtol=0, atol=1e-11)
    h = t[1] - t[0]                                  # sine: exact at the knots, O(h^4) between (5/384 h^4 max|q''''|)
    sine = JointMotion.from_arrays(t, np.sin(3.0 * t), boundary="not-a-knot")
    assert np.allclose(sine(t)[0][:, 0], np.sin(3.0 * t), rtol=0, atol=1e-15)
    assert np.max(np.abs(sine(s)[0][:, 0] - np.sin(3.0 * s))) < 5 * (5 / 384) * h**4 * 3.0**4
    rates = JointMotion.from_arrays(t, np.sin(3.0 * t), rates=3.0 * np.cos(3.0 * t))   # Hermite: rates at knots
    assert np.allclose(rates(t)[1][:, 0], 3.0 * np.cos(3.0 * t), rtol=0, atol=1e-13)
    clamped = JointMotion.from_arrays(t, 1.0 - np.cos(t), boundary="clamped")
    assert clamped(0.0)[1][0] == 0.0 and abs(clamped(2.0)[1][0]) < 1e-15


def test_a_smoothing_spline_follows_the_signal_not_the_noise(rng):
    t = np.linspace(0.0, 3.0, 301)
    noisy = np.sin(2.0 * t) + rng.normal(scale=0.01, size=t.size)
    smooth = JointMotion.from_arrays(t, noisy, smoothing="gcv")
    error = smooth(t)[0][:, 0] - np.sin(2.0 * t)
    assert np.sqrt(np.mean(error**2)) < 0.5 * 0.01          # closer to the signal than the log is
    assert smooth.kind == "smoothing" and smooth.duration == pytest.approx(3.0)


def _independent_run(model, motion, duration, h, x0):
    """RK4 of the vehicle with the ordinary ABA (``uvms.forward_dynamics``) driven at every stage by the torques
    of the motion from the mass matrix and the Newton-Euler bias (``M [nu_dot; qdd] + h = [0; tau]``), the joints
    on the motion at each stage time: the same stage times and state update as the compiled loop."""
    n = model.n_joints
    lay = StateLayout(n, 0)

    def f(t, x):
        q, qd, qdd = motion(t)
        x = x.copy()
        x[lay.q], x[lay.qd] = q, qd
        s = unpack(x, n)
        M, bias = uvms.mass_matrix(model, s), uvms.bias_forces(model, s)
        nu_dot = np.linalg.solve(M[:6, :6], -bias[:6] - M[:6, 6:] @ qdd)
        tau = M[6:, :6] @ nu_dot + M[6:, 6:] @ qdd + bias[6:]
        acc = uvms.forward_dynamics(model, s, joint_torques=tau)
        assert np.allclose(acc.qdd, qdd, rtol=0, atol=1e-8 * max(1.0, np.abs(qdd).max()))
        w = x[lay.quaternion] / np.linalg.norm(x[lay.quaternion])
        om = x[lay.nu][:3]
        dx = np.zeros_like(x)
        dx[lay.position] = s.rotation @ x[lay.nu][3:]
        dx[lay.quaternion] = 0.5 * np.array([-w[1] * om[0] - w[2] * om[1] - w[3] * om[2],
                                             w[0] * om[0] + w[2] * om[2] - w[3] * om[1],
                                             w[0] * om[1] + w[3] * om[0] - w[1] * om[2],
                                             w[0] * om[2] + w[1] * om[1] - w[2] * om[0]])
        dx[lay.nu] = acc.nu_dot
        dx[lay.q], dx[lay.qd] = qd, qdd
        return dx

    x, out = x0.copy(), [x0.copy()]
    for k in range(int(round(duration / h))):
        t = k * h
        k1 = f(t, x)
        k2 = f(t + h / 2, x + h / 2 * k1)
        k3 = f(t + h / 2, x + h / 2 * k2)
        k4 = f(t + h, x + h * k3)
        x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        x[lay.quaternion] /= np.linalg.norm(x[lay.quaternion])
        x[lay.q], x[lay.qd] = motion((k + 1) * h)[:2]
        out.append(x.copy())
    return np.array(out)


def test_the_vehicle_moves_as_the_forward_dynamics_driven_by_the_inverse_dynamics_torques():
    """The acceptance test: a prescribed run's vehicle equals an RK4 of the ordinary ABA driven by the
    CRBA + RNEA torques of the same motion at the same stage times, to 1e-9 (hydrodynamics on)."""
    model = uvms.load_model("paper")
    motion = sine_motion(3, duration=0.3, rows=31)
    s0 = uvms.State.from_euler(model, euler=[0.1, -0.2, 0.3], nu=[0.1, 0.0, -0.1, 0.2, 0.0, 0.05])
    result = uvms.simulate(model, s0, duration=0.2, step=2e-3, inputs=uvms.Inputs(joint_motion=motion))
    q0, qd0, _ = motion(0.0)
    expected = _independent_run(model, motion, 0.2, 2e-3, uvms.sim.integrate.pack(s0.replace(q=q0, qd=qd0)))
    assert result.complete and result.states.shape == expected.shape
    assert np.max(np.abs(result.states - expected)) < 1e-9
    # the recorded torques are the inverse dynamics at each row
    for r in (0, 50, 100):
        s = unpack(result.states[r], 3)
        M, bias = uvms.mass_matrix(model, s), uvms.bias_forces(model, s)
        qdd = motion(result.time[r])[2]
        nu_dot = np.linalg.solve(M[:6, :6], -bias[:6] - M[:6, 6:] @ qdd)
        assert np.allclose(result.joint_torques[r], M[6:, :6] @ nu_dot + M[6:, 6:] @ qdd + bias[6:], rtol=1e-9,
                           atol=1e-12)


def test_recorded_joints_are_the_interpolant_and_the_torques_are_labelled():
    model = uvms.load_model("paper")
    motion = sine_motion(3)
    result = uvms.simulate(model, duration=1.0, step=1e-3, record_period=0.01, inputs=uvms.Inputs(joint_motion=motion))
    q, qd, _ = motion(result.time)
    assert np.array_equal(result.q, q) and np.array_equal(result.qd, qd)
    from uvms.sim.prescribed import motion_torques
    from uvms.sim.run import prepare

    plan = prepare(model, duration=1.0, step=1e-3, record_period=0.01, inputs=uvms.Inputs(joint_motion=motion))
    each = np.zeros_like(result.joint_torques)              # every row evaluated on its own, after the run
    motion_torques(plan.plant, plan.held, plan.motion, result.time, result.states, each)
    assert np.allclose(result.joint_torques, each, rtol=1e-13, atol=1e-14)
    columns = result.columns()
    assert np.array_equal(columns[f"tau_{model.joint_names[0]}_Nm"], result.joint_torques[:, 0])
    assert np.abs(result.joint_torques).max() > 0.01 and result.metadata["joint_motion"] is True


@pytest.mark.parametrize("added_mass", [False, True], ids=["rigid", "added-mass"])
def test_momentum_is_conserved_while_the_arm_follows_a_motion(added_mass):
    """No gravity, buoyancy, drag, current: the total momentum (vehicle + links, about the world origin, from each
    body's spatial inertia and velocity; with added mass the body-plus-fluid impulse) stays constant."""
    model = uvms.load_model("paper").with_effects(added_mass=added_mass, drag=False, buoyancy=False, gravity=False,
                                                  current=False)
    motion = sine_motion(3, duration=2.0, rows=81)
    s0 = uvms.State.from_euler(model, nu=[0.05, -0.02, 0.1, 0.1, 0.0, -0.05])
    result = uvms.simulate(model, s0, duration=2.0, step=1e-3, record_period=0.05,
                           inputs=uvms.Inputs(joint_motion=motion))
    h = np.array([spatial_momentum(model, unpack(x, 3), include_added_mass=added_mass) for x in result.states])
    assert np.linalg.norm(result.nu[-1] - result.nu[0]) > 0.01          # the arm did push the vehicle
    assert np.max(np.linalg.norm(h - h[0], axis=1)) / np.linalg.norm(h[0]) < 1e-8


def test_rollout_trials_with_their_own_motions_equal_their_simulate_runs():
    model = uvms.load_model("paper")
    motions = [sine_motion(3), JointMotion.from_arrays(np.linspace(0, 1, 11), np.zeros((11, 3)) + [0.3, -0.2, 0.1])]
    batch = uvms.rollout(model, [uvms.Trial(joint_motion=m) for m in motions], duration=0.5, threads=2)
    for m, r in zip(motions, batch):
        alone = uvms.simulate(model, duration=0.5, inputs=uvms.Inputs(joint_motion=m))
        assert np.array_equal(r.states, alone.states) and np.array_equal(r.joint_torques, alone.joint_torques)


def test_named_columns_and_a_csv_table(tmp_path):
    model = uvms.load_model("paper")
    names = model.joint_names
    t = np.linspace(0.0, 1.0, 21)
    angles = np.stack([0.1 * t, -0.2 * t**2, 0.3 * np.sin(t)], 1)
    path = tmp_path / "log.csv"
    lines = ["stamp,a,b,c,extra"] + [f"{10 + ti:.17g},{a:.17g},{b:.17g},{c:.17g},x" for ti, (a, b, c) in zip(t, angles)]
    path.write_text("\n".join(lines) + "\n")
    table = JointMotion.from_csv(path, time="stamp", columns={names[2]: "c", names[0]: "a", names[1]: "b"})
    in_order = JointMotion.from_arrays(t, angles)
    r1 = uvms.simulate(model, duration=1.0, step=1e-2, joint_motion=table)
    r2 = uvms.simulate(model, duration=1.0, step=1e-2, joint_motion=in_order)
    assert np.allclose(r1.states, r2.states, rtol=0, atol=1e-12)


def test_bad_inputs_are_one_line_errors(tmp_path):
    model = uvms.load_model("paper")
    motion = sine_motion(3)
    cases = [
        (lambda: JointMotion.from_arrays([0, 1, 1], np.zeros((3, 3))), "times: expected increasing times"),
        (lambda: JointMotion.from_arrays([0, 1, 2], [[0, 0, 0], [0, np.nan, 0], [0, 0, 0]]), "angles: expected"),
        (lambda: uvms.simulate(model, duration=0.1, joint_motion=JointMotion.from_arrays(
            [0, 1], np.zeros((2, 3)), joints=("joint1", "joint2", "elbow"))), "unknown joint 'elbow'"),
        (lambda: uvms.simulate(model, duration=0.1, joint_motion=JointMotion.from_arrays(
            [0, 1], np.zeros((2, 2)), joints=("joint1", "joint2"))), "missing 'joint3'"),
        (lambda: uvms.simulate(model, duration=2.0, joint_motion=motion), "no longer than the motion's table"),
        (lambda: uvms.simulate(model, duration=0.1, joint_motion=motion, joint_torques=[1, 0, 0]), "not both"),
        (lambda: uvms.simulate(model, duration=0.1, joint_motion=motion, integrator="DOP853"), "rk4 integrator"),
    ]
    path = tmp_path / "t.csv"
    path.write_text("t,a\n0,1\n1,\n")
    cases += [(lambda: JointMotion.from_csv(path, time="t", columns={"joint1": "b"}), "no column 'b'"),
              (lambda: JointMotion.from_csv(path, time="t", columns={"joint1": "a"}), "row 2: expected a finite")]
    for call, words in cases:
        with pytest.raises(UvmsInputError) as info:
            call()
        assert words in str(info.value) and "\n" not in str(info.value), str(info.value)


SCENARIO = """
model: paper
duration: 0.5
inputs:
  joint_motion: {joint_motion}
outputs: {{record_period: 0.01}}
"""


def test_scenario_files_inline_and_table(tmp_path):
    from uvms.sim.scenario import load_scenario, run_scenario

    t = np.linspace(0.0, 1.0, 11)
    angles = np.stack([0.2 * np.sin(2 * t), 0.1 * t, -0.1 * t], 1)
    (tmp_path / "logs").mkdir()
    (tmp_path / "logs" / "trial.csv").write_text(
        "time_s,j1,j2,j3\n" + "".join(f"{a:.17g},{b:.17g},{c:.17g},{d:.17g}\n" for a, (b, c, d) in zip(t, angles)))
    table = tmp_path / "table.yaml"
    table.write_text(SCENARIO.format(joint_motion="{file: logs/trial.csv, time: time_s, columns: "
                                                  "{joint1: j1, joint2: j2, joint3: j3}}"))
    inline = tmp_path / "inline.yaml"
    inline.write_text(SCENARIO.format(joint_motion="{times: %s, angles: %s}" % (t.tolist(), angles.tolist())))
    r1, r2 = run_scenario(load_scenario(table)), run_scenario(load_scenario(inline))
    assert np.allclose(r1.states, r2.states, rtol=0, atol=1e-12)
    assert np.array_equal(r1.q, JointMotion.from_arrays(t, angles)(r1.time)[0])
    bad = {"missing column": ("{file: logs/trial.csv, time: time_s, columns: {joint1: j9, joint2: j2, joint3: j3}}",
                              "no column 'j9'"),
           "unknown joint": ("{file: logs/trial.csv, time: time_s, columns: {joint1: j1, joint2: j2, wrist: j3}}",
                             "unknown joint 'wrist'"),
           "both forms": ("{file: logs/trial.csv, times: [0, 1], angles: [[0, 0, 0], [0, 0, 0]]}", "either file"),
           "times": ("{times: [0, 1, 0.5], angles: [[0, 0, 0], [0, 0, 0], [0, 0, 0]]}", "increasing times"),
           "short": ("{times: [0, 0.2], angles: [[0, 0, 0], [0, 0, 0]]}", "covering the duration"),
           "outside": ("{file: ../trial.csv, time: time_s, columns: {joint1: j1, joint2: j2, joint3: j3}}",
                       "is outside"),
           "absolute": (f"{{file: {tmp_path / 'logs' / 'trial.csv'}, time: time_s, columns: {{joint1: j1}}}}",
                        "relative to")}
    for name, (text, words) in bad.items():
        path = tmp_path / f"{name.replace(' ', '_')}.yaml"
        path.write_text(SCENARIO.format(joint_motion=text))
        with pytest.raises(UvmsInputError) as info:
            load_scenario(path)
        message = str(info.value)
        assert words in message and "joint_motion" in message and "\n" not in message, message
