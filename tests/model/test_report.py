"""``uvms.analysis.report.model_report``: statics, trim, thrust available per axis, layout rank and the sliding-mode
``b``-bounds check, against closed forms worked out by hand (moment balances, small linear programs) and against
the dynamics engine (RNEA and ABA), never against the report's own output."""

from __future__ import annotations

import math

import numpy as np
import pytest

import uvms
from uvms.analysis.report import AXES, model_report
from uvms.errors import UvmsInputError
from uvms.thrusters.healey import HealeyParameters
from uvms.thrusters.ideal import IdealParameters
from uvms.thrusters.layouts import Thruster

G = 9.81


@pytest.fixture(scope="module")
def paper():
    return uvms.load_model("paper")


@pytest.fixture(scope="module")
def vehicle(paper):
    return paper.vehicle_only()


def ideal(name, position, direction, max_thrust):
    return Thruster(name, position, direction, "ideal", IdealParameters(max_thrust=max_thrust))


def axis(report, name):
    j = AXES.index(name)
    return report.thrust_forward_N[j], report.thrust_reverse_N[j]


# --------------------------------------------------------------------------------------- mass and buoyancy


def test_paper_is_neutral_and_rights_itself_to_level(paper):
    """Appendix: m = m_f = 32 + 3 x 1 kg; the links' CoM and CoB coincide, the vehicle's CoB is 0.0254 m above
    its CoM, so the righting moment amplitude is m_f0 g h = 32 x 9.81 x 0.0254 N m and the trim is level."""
    report = model_report(paper)
    assert report.mass_kg == pytest.approx(35.0) and report.displaced_mass_kg == pytest.approx(35.0)
    assert report.net_buoyancy_N == pytest.approx(0.0, abs=1e-12)
    assert report.righting_moment_Nm == pytest.approx(32 * G * 0.0254, rel=1e-12)
    assert report.trim_roll_rad == pytest.approx(0.0, abs=1e-12)
    assert report.trim_pitch_rad == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(report.static_moment_Nm, 0.0, atol=1e-12)
    # links at 0.11, 0.33, 0.55 m along x with the arm stretched out (q = 0): r_G,x = 0.99 / 35 m
    np.testing.assert_allclose(report.center_of_mass_m, [0.99 / 35, 0, 0], atol=1e-12)
    np.testing.assert_allclose(report.center_of_buoyancy_m, [0.99 / 35, 0, -32 * 0.0254 / 35], atol=1e-12)


def test_net_buoyancy_sign_is_up(vehicle):
    report = model_report(vehicle.replace(buoyancy_mass=np.array([33.0])))
    assert report.net_buoyancy_N == pytest.approx(+G)          # 1 kg more fluid than mass: rises


@pytest.mark.parametrize("a", [0.01, -0.03])
def test_nose_heavy_vehicle_pitches_by_atan_of_the_moment_ratio(vehicle, a):
    """CoM at (a, 0, 0), CoB at (0, 0, -h), m = m_f. At pitch theta, g_body = g(-sin theta, 0, cos theta); the
    pitch moments are -a m g cos(theta) (weight) and -h m g sin(theta) (buoyancy): zero at
    tan(theta) = -a / h. Roll stays 0."""
    h = 0.0254
    report = model_report(vehicle.replace(com=np.array([[a, 0.0, 0.0]])))
    assert report.trim_pitch_rad == pytest.approx(-math.atan(a / h), rel=1e-12)
    assert report.trim_roll_rad == pytest.approx(0.0, abs=1e-12)
    # at rest and level only the weight's lever acts: M = r_G x m g e_z = (0, -a m g, 0)
    np.testing.assert_allclose(report.static_moment_Nm, [0.0, -a * 32 * G, 0.0], atol=1e-12)
    assert report.righting_moment_Nm == pytest.approx(32 * G * math.hypot(a, h), rel=1e-12)


def test_starboard_heavy_vehicle_rolls_to_starboard(vehicle):
    """CoM at (0, b, 0): roll moments b m g cos(phi) - h m g sin(phi): tan(phi) = b / h (starboard down, > 0)."""
    b, h = 0.02, 0.0254
    report = model_report(vehicle.replace(com=np.array([[0.0, b, 0.0]])))
    assert report.trim_roll_rad == pytest.approx(math.atan(b / h), rel=1e-12)
    assert report.trim_pitch_rad == pytest.approx(0.0, abs=1e-12)


@pytest.fixture(scope="module")
def heavy_tip(paper):
    """Paper model whose third link displaces no fluid (a 1 kg point-like mass at its CoM, 0.55 m ahead of the
    vehicle origin at q = 0), the lost 1 kg of buoyancy moved to the vehicle (33 kg at (0, 0, -0.0254))."""
    return paper.replace(buoyancy_mass=np.array([33.0, 1.0, 1.0, 0.0]))


def test_offset_point_mass_on_the_arm_trims_at_atan_of_the_moment_ratio(heavy_tip):
    """Pitch moments: -0.55 x 1 x g cos(theta) (link 3) - 0.0254 x 33 x g sin(theta) (vehicle buoyancy; the other
    links are neutral with CoM = CoB and the vehicle's weight acts at the origin): tan(theta) = -0.55 / 0.8382."""
    report = model_report(heavy_tip)
    assert report.net_buoyancy_N == pytest.approx(0.0, abs=1e-12)
    assert report.trim_pitch_rad == pytest.approx(-math.atan(0.55 / (0.0254 * 33)), rel=1e-12)
    assert report.trim_roll_rad == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(report.static_moment_Nm, [0.0, -0.55 * G, 0.0], atol=1e-12)


def test_static_moment_and_trim_agree_with_the_rnea(heavy_tip):
    """Independent check through the dynamics: at rest, bias_forces h = -(weight and buoyancy wrench), so the
    vehicle moment is -h[:3]; it equals the static moment when level, vanishes at the trim attitude and pushes
    back towards it on either side (stable)."""
    q = [0.4, -0.7, 0.3]
    report = model_report(heavy_tip, q=q)
    level = uvms.bias_forces(heavy_tip, uvms.State.from_euler(heavy_tip, q=q))
    np.testing.assert_allclose(report.static_moment_Nm, -level[:3], atol=1e-10)
    roll, pitch = report.trim_roll_rad, report.trim_pitch_rad
    assert abs(roll) > 1e-3 and abs(pitch) > 1e-3      # a non-trivial pose: both angles matter

    def moment(dr=0.0, dp=0.0):
        s = uvms.State.from_euler(heavy_tip, q=q, euler=[roll + dr, pitch + dp, 0.0])
        return -uvms.bias_forces(heavy_tip, s)[:3]

    np.testing.assert_allclose(moment(), 0.0, atol=1e-10)
    assert moment(dp=+0.05)[1] < 0 < moment(dp=-0.05)[1]
    assert moment(dr=+0.05)[0] < 0 < moment(dr=-0.05)[0]


def test_coinciding_centres_have_no_stable_attitude(vehicle):
    report = model_report(vehicle.replace(cob=np.zeros((1, 3))))
    assert report.trim_roll_rad is None and report.trim_pitch_rad is None
    assert "coincide" in report.trim_note and report.righting_moment_Nm == 0.0
    assert "no stable attitude" in report.table()


def test_no_buoyancy_no_stable_attitude(vehicle):
    report = model_report(vehicle.replace(buoyancy_mass=np.zeros(1)))
    assert report.trim_roll_rad is None and "no displaced fluid" in report.trim_note
    assert np.all(np.isnan(report.center_of_buoyancy_m)) and report.net_buoyancy_N == pytest.approx(-32 * G)
    import json

    data = json.loads(json.dumps(report.to_dict(), allow_nan=False))      # no NaN in the JSON: null instead
    assert data["center_of_buoyancy_m"] == [None, None, None] and data["trim"] is None


# ------------------------------------------------------------------------------------------------- thrust


def test_hand_computed_layout(vehicle):
    """Surge pair A, B at y = -/+0.2 (10 N each), sway pair C, D at x = +/-0.3 (5 N each), heave E (20 N).
    Surge with yaw 0: A = B = 10 -> 20 N. Sway with yaw 0: C = D = 5 -> 10 N. Heave: 20 N.
    Yaw with X = Y = 0: A = -B, C = -D, N = 0.4 A + 0.6 C -> 0.4 x 10 + 0.6 x 5 = 7 N m. No roll or pitch."""
    layout = (ideal("A", (0, -0.2, 0), (1, 0, 0), 10.0), ideal("B", (0, 0.2, 0), (1, 0, 0), 10.0),
              ideal("C", (0.3, 0, 0), (0, 1, 0), 5.0), ideal("D", (-0.3, 0, 0), (0, 1, 0), 5.0),
              ideal("E", (0, 0, 0), (0, 0, 1), 20.0))
    report = model_report(vehicle.replace(thrusters=layout))
    expected = {"surge": 20.0, "sway": 10.0, "heave": 20.0, "roll": 0.0, "pitch": 0.0, "yaw": 7.0}
    for name, value in expected.items():
        fwd, rev = axis(report, name)
        assert fwd == pytest.approx(value, abs=1e-9) and rev == pytest.approx(value, abs=1e-9), name
    assert report.allocation_rank == 4 and report.missing_axes == ("roll", "pitch")
    assert report.n_thrusters == 5 and "linear programming" in report.thrust_method


def test_coupled_thruster_limits_the_pure_axis(vehicle):
    """One sway thruster ahead of the origin (x = 0.3) and a yaw pair: a pure sway force needs the pair to cancel
    the 0.3 Y yaw moment. Pair P/S at y = -/+0.25 along x (8 N): yaw up to 0.5 x 8 = 4 N m, so sway
    Y <= 4 / 0.3 = 13.33 N although the sway thruster gives 30 N (a sum of projections would say 30)."""
    layout = (ideal("bow", (0.3, 0, 0), (0, 1, 0), 30.0), ideal("P", (0, -0.25, 0), (1, 0, 0), 8.0),
              ideal("S", (0, 0.25, 0), (1, 0, 0), 8.0))
    report = model_report(vehicle.replace(thrusters=layout))
    assert axis(report, "sway") == pytest.approx((4 / 0.3, 4 / 0.3), rel=1e-9)
    assert axis(report, "surge") == pytest.approx((16.0, 16.0), rel=1e-9)
    # yaw with X = Y = 0: bow must stay 0, so the pair alone: 4 N m
    assert axis(report, "yaw") == pytest.approx((4.0, 4.0), rel=1e-9)
    assert report.allocation_rank == 3 and report.missing_axes == ("heave", "roll", "pitch")


def test_layout_without_sway_is_rank_5_and_names_sway(vehicle):
    """Surge pair (X, N) and four vertical thrusters at (+/-0.2, 0, 0), (0, +/-0.2, 0) (Z, K, M): no Y."""
    layout = (ideal("sp", (0, -0.2, 0), (1, 0, 0), 10.0), ideal("ss", (0, 0.2, 0), (1, 0, 0), 10.0),
              ideal("vf", (0.2, 0, 0), (0, 0, 1), 10.0), ideal("va", (-0.2, 0, 0), (0, 0, 1), 10.0),
              ideal("vp", (0, -0.2, 0), (0, 0, 1), 10.0), ideal("vs", (0, 0.2, 0), (0, 0, 1), 10.0))
    report = model_report(vehicle.replace(thrusters=layout))
    assert report.allocation_rank == 5 and report.missing_axes == ("sway",)
    assert axis(report, "sway") == (0.0, 0.0)
    # roll: vp, vs with -0.2 vp + 0.2 vs... r x e for (0, y, 0) x (0, 0, 1) = (y, 0, 0): K = 0.2 (vs - vp),
    # Z = vp + vs = 0 -> 0.2 x 20 = 4 N m; pitch likewise from vf, va: M = -x along z -> 4 N m
    assert axis(report, "roll") == pytest.approx((4.0, 4.0)) and axis(report, "pitch") == pytest.approx((4.0, 4.0))
    assert "cannot push in: sway" in report.table()


def test_paper_layouts(paper):
    """Bundled paper model: two 51.8 N Healey surge thrusters at y = -/+0.15, heave and sway at the origin:
    surge 2 T, sway T, heave T, yaw 0.3 T; no roll or pitch. The paper's own three: no sway either."""
    T = HealeyParameters().max_thrust
    assert T == pytest.approx(51.8, abs=0.05)        # the steady thrust at 24 V (docs, thrusters/first_order.py)
    report = model_report(paper)
    for name, value in {"surge": 2 * T, "sway": T, "heave": T, "roll": 0, "pitch": 0, "yaw": 0.3 * T}.items():
        assert axis(report, name) == pytest.approx((value, value), abs=1e-9), name
    assert report.allocation_rank == 4 and report.missing_axes == ("roll", "pitch")
    three = model_report(paper.replace(thrusters=paper.thrusters[:3]))
    assert three.allocation_rank == 3 and three.missing_axes == ("sway", "roll", "pitch")


def test_no_thrusters_and_unlimited_thrusters(vehicle):
    none = model_report(vehicle.replace(thrusters=()))
    assert none.allocation_rank == 0 and none.missing_axes == AXES and not np.any(none.thrust_forward_N)
    assert "no thrusters (ideal actuation" in none.table()
    free = model_report(vehicle.replace(thrusters=(ideal("x", (0, 0, 0), (1, 0, 0), math.inf),)))
    assert axis(free, "surge") == (math.inf, math.inf)
    assert free.to_dict()["thrust"]["forward_N_or_Nm"]["surge"] is None


# ------------------------------------------------------------------------------------- the controller's b


def test_effective_inertia_matches_aba_response_to_a_unit_wrench(paper):
    """Independent of the CRBA: with gravity, buoyancy, drag and friction off and the system at rest, a unit
    wrench on axis j alone gives nu_dot_j = (M^-1)_jj by the articulated-body algorithm."""
    q = [0.2, -0.5, 0.9]
    report = model_report(paper, q=q)
    quiet = paper.with_effects(drag=False, buoyancy=False, gravity=False, current=False, joint_friction=False)
    state = uvms.State.from_euler(quiet, q=q)
    for j, row in enumerate((3, 4, 5, 0, 1, 2)):
        wrench = np.zeros(6)
        wrench[row] = 1.0
        acc = uvms.forward_dynamics(quiet, state, body_wrench=wrench).nu_dot[row]
        assert report.effective_inertia[j] == pytest.approx(1.0 / acc, rel=1e-10), AXES[j]


def test_paper_effective_mass_is_outside_the_b_bounds(paper):
    """The paper model's surge/sway effective mass (~48-53 kg over its runs) is outside [36, 44.44] kg."""
    report = model_report(paper)
    surge, sway = report.effective_inertia[0], report.effective_inertia[1]
    assert 47.8 <= surge <= 53 and 47.8 <= sway <= 53
    assert len(report.warnings) == 1
    assert "surge effective mass" in report.warnings[0] and "[36, 44.44] kg" in report.warnings[0]
    assert "sway effective mass" in report.warnings[0] and "yaw" not in report.warnings[0]
    assert report.b_bounds == {"surge": (36.0, 44.44), "sway": (36.0, 44.44), "yaw": (1.287, 1.5889)}


def test_model_scaled_to_fit_has_no_warning(paper):
    """The paper's controller model (added mass x 0.4): surge ~41 kg, sway ~40 kg, yaw ~1.35 kg m^2, inside."""
    report = model_report(paper.with_hydrodynamics_scaled(added_mass=0.4))
    assert report.warnings == ()
    assert 36 <= report.effective_inertia[0] <= 44.44 and 1.287 <= report.effective_inertia[5] <= 1.5889


def test_custom_controller_bounds(paper):
    from uvms.control.smc import SlidingModeParameters

    report = model_report(paper, controller=SlidingModeParameters(b_surge=(45.0, 55.0), b_sway=(45.0, 55.0)))
    assert report.warnings == ()


# -------------------------------------------------------------------------------------------- bad input


@pytest.mark.parametrize("q, message", [([0.0, 0.0], "expected 3 joint values"),
                                        ([0.0, math.nan, 0.0], "finite"),
                                        ([0.0, math.inf, 0.0], "finite"),
                                        ("abc", "expected 3")])
def test_bad_q_is_one_line_input_error(paper, q, message):
    with pytest.raises(UvmsInputError, match=message) as info:
        model_report(paper, q=q)
    assert "\n" not in str(info.value) and info.value.path == "q"


def test_report_is_frozen_and_json_ready(paper):
    import json

    report = model_report(paper, q=[0.1, 0.2, 0.3])
    with pytest.raises(AttributeError):
        report.mass_kg = 1.0
    with pytest.raises(ValueError):
        report.static_moment_Nm[0] = 1.0
    data = json.loads(json.dumps(report.to_dict(), allow_nan=False))
    assert data["q"] == {"joint1": 0.1, "joint2": 0.2, "joint3": 0.3}
    assert data["total_mass_kg"] == 35.0 and data["trim"]["roll_rad"] == pytest.approx(0.0, abs=1e-12)


def test_asymmetric_limits_from_a_datasheet_table():
    """A table thruster has its own reverse limit (``min_thrust``): a surge pair at y = -/+0.1 with [-30, 40] N
    gives +80 / -60 N in surge and, with X = 0 (T1 = -T2), yaw 0.1 T1 - 0.1 T2 = 0.2 T1 limited by
    T1 <= 40 and -T1 >= -30: +6 / -6 N m."""
    from types import SimpleNamespace

    from uvms.analysis.report import available_thrust, thruster_limits
    from uvms.thrusters.allocation import allocation_matrix

    table = SimpleNamespace(parameters=SimpleNamespace(max_thrust=40.0, min_thrust=-30.0))
    assert thruster_limits(table) == (-30.0, 40.0)
    assert thruster_limits(SimpleNamespace(parameters=IdealParameters(max_thrust=12.0))) == (-12.0, 12.0)
    Lambda = allocation_matrix(np.array([[0, -0.1, 0], [0, 0.1, 0]]), np.array([[1.0, 0, 0], [1.0, 0, 0]]))
    forward, reverse = available_thrust(Lambda, np.array([-30.0, -30.0]), np.array([40.0, 40.0]))
    assert forward[0] == pytest.approx(80.0) and reverse[0] == pytest.approx(60.0)
    assert forward[5] == pytest.approx(6.0) and reverse[5] == pytest.approx(6.0)
