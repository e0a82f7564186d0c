"""The bundled ``hinsdale_bluerov2_alpha5`` against Kolano et al.'s published parameters, written out here from
hkolano/UVMS-SysID-with-EAs at commit 18d9b2f (MIT, Copyright (c) 2023 Hannah Kolano) and combined by their own
equations (``src/julia-sim/HydroCalc.jl``: a weight and a buoyancy force per body at its centres, the extras at
theirs, the vehicle drag ``-d_lin .* vel - d_nonlin .* vel .* abs(vel)`` on ``vel = [omega; v]``, link drag at the
centre of buoyancy), the arm placed by the URDF's joint origins composed here with rotations written out. Never
against the model's own output."""

from __future__ import annotations

import math

import numpy as np
import pytest

import uvms
from uvms.analysis.report import model_report
from uvms.analysis.trim import trim
from uvms.cli import main

G, RHO = 9.81, 997.0                                   # MagicNumBlueROVHardware.jl:21 (9.81), ConstMagicNums.jl:4
# weights [N] and where they act, each in its body's frame (MagicNumBlueROVHardware.jl, MagicNumAlpha.jl)
VEHICLE_WEIGHT, VEHICLE_COM = 13.17 * G, (0.0, 0.0, 0.0)                           # :21, :19
VEHICLE_BUOYANCY, VEHICLE_COB = 13.082 * G, (0.0074, 0.0, 0.02)                    # :12, :8
EXTRAS_WEIGHT = {"weightCA": (3.24, (-0.20, 0.165, -0.075)), "weightBL": (1.62, (-0.0975, 0.1275, -0.1325)),
                 "weightBR": (1.62, (-0.0975, -0.1275, -0.1325)), "dvl": (0.69, (-0.1887, 0.0439, -0.1095 + 0.05)),
                 "dvlbracket": (1.01, (-0.1887 + 0.0345, 0.0439, -0.1295 + 0.05))}  # :28-32, :42-46
EXTRAS_BUOYANCY = {"foamL": (8.46, (0.0, 0.11, 0.027)), "foamR": (8.66 + 0.2, (0.0, -0.11, 0.027))}  # :39-40, :47-48
LINK_MASS = {"shoulder": 0.194, "upperarm": 0.429, "elbow": 0.115, "wrist": 0.333, "armbase": 0.341, "jaw": 0.05}
LINK_VOLUME_L = {"shoulder": 0.018, "upperarm": 0.203, "elbow": 0.025, "wrist": 0.155, "armbase": 0.202, "jaw": 0.02}
LINK_COM = {"shoulder": (0.005, -0.001, 0.016), "upperarm": (0.073, 0.0, 0.0), "elbow": (0.017, -0.026, -0.002),
            "wrist": (0.0, 0.0, -0.098), "armbase": (-0.075, -0.006, -0.003), "jaw": (0.0, 0.0, -0.19)}
LINK_COB = {"shoulder": (-0.001, -0.003, 0.032), "upperarm": (0.073, 0.0, -0.002), "elbow": (0.003, 0.001, -0.017),
            "wrist": (0.0, 0.0, -0.098), "armbase": (-0.075, -0.006, -0.003), "jaw": (0.0, 0.0, -0.19)}
# (jaw: in the wrist frame, MagicNumAlpha.jl:18; armbase: its CoM is its CoB, UVMSsetup.jl:88)
LINK_DRAG = {"shoulder": (0.26, 0.26, 0.3), "upperarm": (0.3, 1.6, 1.6), "elbow": (0.26, 0.3, 0.26),
             "wrist": (1.8, 1.8, 0.3)}                                               # MagicNumAlpha.jl:50-53
D_LIN = (4.03, 6.22, 5.18, 0.07, 0.07, 0.07)                                         # MagicNumBlueROVHardware.jl:53
D_NONLIN = (18.18, 21.66, 36.99, 1.55, 1.55, 1.55)                                   # :54
# urdf/blue_rov_hardware_fixedjaw.urdf: joint origins (xyz, rpy), all axes z; inertial masses ("actual + added")
ARMBASE = (0.25, -0.10965, 0.005)                                                    # line 91
JOINTS = {"base": ((0, 0, 0), (0, 0, 0)), "shoulder": ((0.020, 0, 0.046), (1.57075, 1.3, 0)),
          "elbow": ((0.15, 0, 0), (3.1415, 0, 1.3)), "wrist": ((0.020, 0, 0), (-1.57075, 0.0, 0))}  # 126, 162, 203, 237
INERTIAL_MASS = 25.14 + 0.53 + 0.226 + 0.630 + 0.147 + 0.559 + 0.01 + 0.05 + 0.05  # lines 40, 117, 153, 194, 227, 261, 270, 301, 325
# the arm at rest: the first sample of data/hinsdale-data-2023/baseline1_joint_states.csv, shifted as
# MainPitchValidation.jl:115-118 (base = axis_e - 3.07, wrist = axis_b - 2.879)
Q_REST = (3.100966215133667 - 3.07, 0.07819706946611404, 0.027431892231106758, 1.6100327968597412 - 2.879)


def rpy(r, p, y):
    """URDF's fixed-axis roll-pitch-yaw: Rz(y) Ry(p) Rx(r)."""
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    Rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    Ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    Rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def link_frames(q):
    """Each arm body's (R, p) in the vehicle frame (the chain armbase -> base -> shoulder -> elbow -> wrist)."""
    frames = {}
    R, p = np.eye(3), np.array(ARMBASE)
    frames["armbase"] = (R, p)
    for (joint, (xyz, angles)), body, qi in zip(JOINTS.items(), ("shoulder", "upperarm", "elbow", "wrist"), q):
        p = p + R @ np.array(xyz, dtype=float)
        R = R @ rpy(*angles) @ rpy(0.0, 0.0, qi)          # joint origin, then the turn about its z axis
        frames[body] = (R, p)
    frames["jaw"] = frames["wrist"]
    return frames


def hand_statics(q):
    """Their totals: weight W and buoyancy B [N], and the points they act through (vehicle frame) [m]."""
    frames = link_frames(q)
    weights = [(VEHICLE_WEIGHT, np.array(VEHICLE_COM))] + [(F, np.array(r)) for F, r in EXTRAS_WEIGHT.values()]
    buoys = [(VEHICLE_BUOYANCY, np.array(VEHICLE_COB))] + [(F, np.array(r)) for F, r in EXTRAS_BUOYANCY.values()]
    for name, m in LINK_MASS.items():
        R, p = frames[name]
        weights.append((m * G, p + R @ np.array(LINK_COM[name])))                   # MagicNumAlpha.jl:40
        buoys.append((LINK_VOLUME_L[name] * RHO * G * 0.001, p + R @ np.array(LINK_COB[name])))   # :29
    W = sum(F for F, _ in weights)
    B = sum(F for F, _ in buoys)
    return W, B, sum(F * r for F, r in weights) / W, sum(F * r for F, r in buoys) / B


@pytest.fixture(scope="module")
def model():
    return uvms.load_model("hinsdale_bluerov2_alpha5")


def test_bodies_joints_and_their_order(model):
    assert model.body_names == ("vehicle", "shoulder", "upperarm", "elbow", "wrist")
    assert model.joint_names == ("base", "shoulder", "elbow", "wrist")
    assert model.gravity.tolist() == [0.0, 0.0, -G] and model.density == RHO
    assert model.mass.sum() == pytest.approx(INERTIAL_MASS, rel=1e-14)
    assert not model.thrusters and not model.added_mass.any()


def test_totals_and_centres_at_the_rest_pose(model):
    W, B, r_G, r_B = hand_statics(Q_REST)
    report = model_report(model, q=list(Q_REST))
    assert report.mass_kg == pytest.approx(W / G, rel=1e-13)
    assert report.displaced_mass_kg == pytest.approx(B / G, rel=1e-13)
    assert report.net_buoyancy_N == pytest.approx(B - W, abs=1e-11)
    assert B - W == pytest.approx(0.0278, abs=1e-4)       # near neutral, as they trimmed the vehicle
    np.testing.assert_allclose(report.center_of_mass_m, r_G, rtol=0, atol=1e-14)
    np.testing.assert_allclose(report.center_of_buoyancy_m, r_B, rtol=0, atol=1e-14)


def test_vehicle_drag_as_their_code_applies_it(model):
    """HydroCalc.jl:125-128: the first three coefficients on omega, the last three on v (as coded)."""
    nu = np.array([0.3, -0.2, 0.1, 0.4, -0.5, 0.25])
    state = uvms.State.from_euler(model, nu=nu, q=list(Q_REST))
    drag = uvms.hydrodynamic_wrenches(model, state).wrenches["drag"][0]
    expected = -np.array(D_LIN) * nu - np.array(D_NONLIN) * nu * np.abs(nu)
    np.testing.assert_allclose(drag, expected, rtol=1e-13, atol=1e-15)


@pytest.mark.parametrize("body", ["shoulder", "upperarm", "elbow", "wrist"])
def test_link_drag_is_quadratic_at_the_centre_of_buoyancy(model, body):
    """HydroCalc.jl:137-147: F = -c .* |v_B| .* v_B with v_B the CoB's velocity in link axes, moment r_B x F."""
    state = uvms.State.from_euler(model, nu=[0.3, -0.2, 0.5, 0.4, -0.3, 0.2], q=list(Q_REST), qd=[0.2, -0.3, 0.4, 0.5])
    out = uvms.hydrodynamic_wrenches(model, state)
    i = model.body_names.index(body)
    w, v = out.relative_velocity[i, :3], out.relative_velocity[i, 3:]
    r = np.array(LINK_COB[body])
    v_B = v + np.cross(w, r)
    F = -np.array(LINK_DRAG[body]) * np.abs(v_B) * v_B
    np.testing.assert_allclose(out.wrenches["drag"][i], np.concatenate([np.cross(r, F), F]), rtol=1e-12, atol=1e-15)


def test_validate_cli(capsys):
    assert main(["validate", "hinsdale_bluerov2_alpha5", "--q", *(str(x) for x in Q_REST)]) == 0
    out, err = capsys.readouterr()
    assert "hinsdale_bluerov2_alpha5: valid" in out and "joint order (q):      base, shoulder, elbow, wrist" in out


def test_two_seconds_at_rest_stay_at_trim(model):
    """Released at its trim attitude with the arm held at rest (a computed-torque hold: the arm alone has no stable
    rest without its servos, their PID, ``PIDCtlr.jl``), the vehicle keeps its
    attitude and the arm its pose, and rises under its small net buoyancy F as a mass with the linear drag d:
    ``z(t) = (F/d) (t - tau (1 - exp(-t/tau)))``, ``tau = m/d`` (m the inertial mass, d = 0.07 N s/m as coded)."""
    W, B, r_G, r_B = hand_statics(Q_REST)
    rest = trim(model, list(Q_REST))
    start = uvms.State.from_euler(model, euler=[rest.roll_rad, rest.pitch_rad, 0.0], q=list(Q_REST))
    # z up: at rest the centre of buoyancy is straight above the centre of gravity
    np.testing.assert_allclose(start.rotation @ (r_B - r_G) / np.linalg.norm(r_B - r_G), [0.0, 0.0, 1.0], atol=1e-12)
    from uvms.control.arm import ComputedTorqueArm, JointTrajectory

    hold = ComputedTorqueArm(model, JointTrajectory(times=np.array([0.0]), angles=np.array([Q_REST])))
    result = uvms.simulate(model, start, duration=2.0, step=2e-3, joint_torques=hold)
    end = result.state(-1)
    np.testing.assert_allclose(end.euler[:2], start.euler[:2], atol=2e-4)
    np.testing.assert_allclose(end.q, Q_REST, atol=2e-4)
    F, d, t = B - W, D_LIN[3], 2.0
    tau = INERTIAL_MASS / d
    rise = F / d * (t - tau * (1.0 - math.exp(-t / tau)))
    assert end.position[2] == pytest.approx(rise, rel=2e-3)
    assert np.all(np.abs(end.position[:2]) < 0.01 * rise)
