"""``uvms.trim`` and ``uvms.analysis.trim``: the rest attitude and the levelling ballast against closed forms worked
out by hand (moment balances), and against the dynamics engine (RNEA for static moments, ABA for accelerations at the
trimmed state); no solution is one line."""

from __future__ import annotations

import math

import numpy as np
import pytest

import uvms
from uvms.analysis.trim import level_ballast, statics, trimmed_state, with_ballast
from uvms.errors import UvmsInputError

G = 9.81
RHO = 1000.0


@pytest.fixture(scope="module")
def vehicle():
    """The paper's vehicle alone, ideal actuation: m = m_f = 32 kg, CoM at the origin, CoB h = 0.0254 m above."""
    return uvms.load_model("paper").vehicle_only().replace(thrusters=())


def with_point_mass(vehicle, m_p, at):
    """The vehicle carrying a point mass ``m_p`` at ``at`` (composite body 0 written out by hand) and the same
    extra displaced fluid at the vehicle's centre of buoyancy, so that it stays neutral."""
    M, mf = float(vehicle.mass[0]), float(vehicle.buoyancy_mass[0])
    com = m_p * np.asarray(at, dtype=float) / (M + m_p)
    return vehicle.replace(mass=np.array([M + m_p]), com=com[None], buoyancy_mass=np.array([mf + m_p]))


@pytest.mark.parametrize("m_p, x_p", [(0.5, 0.2), (2.0, -0.25)])
def test_offset_point_mass_settles_at_atan_of_the_moment_ratio(vehicle, m_p, x_p):
    """Point mass m_p at (x_p, 0, 0), CoB h above the origin, neutral (m_f = M + m_p). At pitch theta, gravity in
    body axes is g (-sin theta, 0, cos theta); pitch moments about the origin: weight -m_p g x_p cos(theta),
    buoyancy -m_f g h sin(theta): they cancel at tan(theta) = -m_p x_p / (m_f h)."""
    h = 0.0254
    model = with_point_mass(vehicle, m_p, [x_p, 0.0, 0.0])
    mf = float(model.buoyancy_mass[0])
    result = uvms.trim(model)
    assert result.pitch_rad == pytest.approx(-math.atan(m_p * x_p / (mf * h)), rel=1e-12)
    assert result.roll_rad == pytest.approx(0.0, abs=1e-15)
    assert result.net_buoyancy_N == pytest.approx(0.0, abs=1e-12) and not result.level
    # the trimmed state is an equilibrium of the articulated-body algorithm: no angular acceleration
    state = trimmed_state(model, yaw=0.7)
    assert state.euler[1] == pytest.approx(result.pitch_rad, rel=1e-12)
    acc = uvms.forward_dynamics(model, state)
    np.testing.assert_allclose(acc.nu_dot, 0.0, atol=1e-12)


def test_sideways_point_mass_rolls_at_atan_of_the_moment_ratio(vehicle):
    """Point mass at (0, y_p, 0): roll moments m_p g y_p cos(phi) - m_f g h sin(phi): tan(phi) = m_p y_p / (m_f h)."""
    m_p, y_p, h = 1.0, 0.15, 0.0254
    model = with_point_mass(vehicle, m_p, [0.0, y_p, 0.0])
    result = uvms.trim(model)
    assert result.roll_rad == pytest.approx(math.atan(m_p * y_p / (33.0 * h)), rel=1e-12)
    assert result.pitch_rad == pytest.approx(0.0, abs=1e-15)


def nose_heavy(vehicle, a=0.01):
    """CoM at (a, 0, 0), CoB at (0, 0, -h), m = m_f = 32 kg: d = r_G - r_B = (a, 0, h)."""
    return vehicle.replace(com=np.array([[a, 0.0, 0.0]]))


def test_least_point_mass_that_levels_it(vehicle):
    """Level needs r_G,x' = r_B,x = 0: M a + m_b c_x = 0, so the least mass goes to the aft end of the box
    (c_x = -L): m_b = M a / L; at that mass the largest righting arm puts it at the bottom (z = +Z), and
    d'_z = (m_b Z) / (M + m_b) + h. Checked independently: the RNEA's static moment of the ballasted model
    vanishes when level and pushes back on either side."""
    a, L, Z, h, M = 0.01, 0.3, 0.1, 0.0254, 32.0
    model = nose_heavy(vehicle, a)
    result = uvms.trim(model, region=[[-L, -0.2, -Z], [L, 0.2, Z]])
    b = result.ballast
    assert result.pitch_rad == pytest.approx(-math.atan(a / h), rel=1e-12)
    assert b.kind == "mass" and b.amount == pytest.approx(M * a / L, rel=1e-9)
    np.testing.assert_allclose(b.position_m, [-L, 0.0, Z], atol=1e-9)
    assert b.righting_arm_after_m == pytest.approx(b.amount * Z / (M + b.amount) + h, rel=1e-9)
    assert b.net_buoyancy_after_N == pytest.approx(-b.amount * G, rel=1e-12)
    ballasted = with_ballast(model, b)
    assert uvms.trim(ballasted).level
    moment = lambda pitch: -uvms.bias_forces(ballasted, uvms.State.from_euler(ballasted, euler=[0, pitch, 0]))[:3]
    # sinking slightly now, so take the moment about the centre of mass: r_G' is on the vertical through the CoB
    r_G = ballasted.com[0]
    assert abs(r_G[0]) < 1e-12 and abs(r_G[1]) < 1e-12
    np.testing.assert_allclose(moment(0.0), 0.0, atol=1e-10)
    assert moment(+0.05)[1] < 0 < moment(-0.05)[1]


def test_least_foam_that_levels_it(vehicle):
    """Massless foam of volume V at c lifts rho V g there; level needs r_B' on the vertical through r_G = (a, 0, 0):
    m_f r_B,x + rho V c_x = (m_f + rho V) a, so with r_B,x = 0 the least foam sits at the far end c_x = +L:
    V = m_f a / (rho (L - a)), at the top (z = -Z) for the largest righting arm."""
    a, L, Z, mf = 0.01, 0.3, 0.1, 32.0
    model = nose_heavy(vehicle, a)
    result = uvms.trim(model, ballast="foam", region=[[-L, -0.2, -Z], [L, 0.2, Z]])
    b = result.ballast
    assert b.kind == "foam" and b.amount == pytest.approx(mf * a / (RHO * (L - a)), rel=1e-9)
    np.testing.assert_allclose(b.position_m, [L, 0.0, -Z], atol=1e-9)
    assert b.mass_kg == 0.0 and b.displaced_mass_kg == pytest.approx(RHO * b.amount, rel=1e-12)
    assert b.net_buoyancy_after_N == pytest.approx(RHO * b.amount * G, rel=1e-12)
    ballasted = with_ballast(model, b)
    after = uvms.trim(ballasted)
    assert after.level and abs(after.pitch_rad) < 1e-12


def test_foam_with_a_density_levels_the_bundled_vehicle():
    """BlueROV2 Heavy + Alpha 5 with the arm stretched out (q = 0) rests nose-up; the foam found (any density below
    the water's) levels it exactly, checked by the trim of the ballasted model."""
    model = uvms.load_model("bluerov2_heavy_alpha5")
    result = uvms.trim(model, ballast="foam", foam_density=350.0)
    assert result.pitch_rad > math.radians(1.0)
    b = result.ballast
    assert b.mass_kg == pytest.approx(350.0 * b.amount) and b.displaced_mass_kg == pytest.approx(1025.0 * b.amount,
                                                                                                rel=0.03)
    after = uvms.trim(with_ballast(model, b))
    assert abs(after.roll_rad) < 1e-9 and abs(after.pitch_rad) < 1e-9
    assert after.center_of_buoyancy_m[2] < after.center_of_mass_m[2] - 0.001


def test_level_model_needs_no_ballast():
    """The paper model: links neutral with CoM = CoB, vehicle CoB straight above its CoM: level in any arm pose."""
    result = uvms.trim(uvms.load_model("paper"), q={"joint2": 1.0, "joint3": 0.5})
    assert result.level and result.ballast is None and result.pitch_rad == pytest.approx(0.0, abs=1e-15)
    assert "level already" in result.table()


def test_b_bounds_warning_uses_the_effective_mass():
    """The paper's b bounds do not contain the BlueROV's effective masses (about 21 kg in surge): one line naming
    every axis, and the controllers that use the bounds."""
    result = uvms.trim(uvms.load_model("bluerov2_heavy_alpha5"))
    assert len(result.warnings) == 1 and result.warnings[0].startswith("sliding-mode controller: the paper's b bounds")
    assert "surge effective mass 21.19 kg outside [36, 44.44] kg" in result.warnings[0]
    assert "sway effective mass 21.43 kg outside [36, 44.44] kg" in result.warnings[0]
    assert "yaw effective inertia 0.6374 kg m^2 outside [1.287, 1.5889] kg m^2" in result.warnings[0]
    assert "used by smc-ab, smc-ne, smc-vehicle with b_source: fixed; not by pid, lqr" in result.warnings[0]


def test_no_solution_is_one_line(vehicle):
    model = nose_heavy(vehicle, 0.01)
    with pytest.raises(UvmsInputError, match="cannot float level") as info:
        uvms.trim(model, max_amount=0.5)          # needs 32 x 0.01 / 0.298 = 1.07 kg in the default box
    assert info.value.path == "ballast" and "\n" not in str(info.value)
    with pytest.raises(UvmsInputError, match="cannot float level"):
        uvms.trim(model, region=[[0.0, -0.1, 0.0], [0.3, 0.1, 0.1]])     # only ahead of the CoB: pitches it more
    with pytest.raises(UvmsInputError, match="foam_density"):
        uvms.trim(model, ballast="foam", foam_density=2000.0)
    with pytest.raises(UvmsInputError, match="no stable rest attitude"):
        trimmed_state(vehicle.replace(cob=np.zeros((1, 3))))


def test_coinciding_centres_are_levelled_with_a_righting_arm(vehicle):
    """CoB on the CoM (no righting moment): the least ballast gives the required arm min_arm exactly: a point mass
    m_b at depth Z below gives d'_z = m_b Z / (M + m_b) = min_arm, m_b = M min_arm / (Z - min_arm)."""
    model = vehicle.replace(cob=np.zeros((1, 3)))
    s = statics(model, np.zeros(0))
    Z = 0.1
    b = level_ballast(model, s, region=[[-0.2, -0.2, -Z], [0.2, 0.2, Z]], min_arm=0.002)
    assert b.amount == pytest.approx(32.0 * 0.002 / (Z - 0.002), rel=1e-9)
    assert b.righting_arm_after_m == pytest.approx(0.002, rel=1e-9)


@pytest.mark.parametrize("options, path, words", [
    ({"max_amount": -1.0}, "max_amount", "expected a finite number >= 0, found -1.0"),
    ({"max_amount": "1"}, "max_amount", "expected a finite number >= 0, found '1'"),
    ({"region": [[math.nan, 0, 0], [1, 1, 1]]}, "region", "expected finite corners"),
    ({"region": [[0.1, 0, 0], [0.0, 1, 1]]}, "region", "expected the lower corner first (x0 <= x1)"),
    ({"region": [[0, 0, 0.2], [1, 1, 0.1]]}, "region", "expected the lower corner first (z0 <= z1)"),
    ({"region": "box"}, "region", "expected two corners"),
    ({"ballast": "foam", "foam_density": 1100.0}, "foam_density", "lighter than the water"),
    ({"foam_density": math.inf}, "foam_density", "lighter than the water"),
    ({"min_arm": math.nan}, "min_arm", "expected a finite number >= 0, found nan"),
    ({"ballast": "lead"}, "ballast", "expected one of mass, foam, found 'lead'"),
])
def test_every_option_is_checked_even_when_no_ballast_is_needed(vehicle, options, path, words, monkeypatch):
    """The paper's vehicle rests level (no ballast to compute), yet a bad option is one line naming it, refused
    before any statics are computed."""
    import time

    import uvms.analysis.trim as trim_module

    assert uvms.trim(vehicle).level and uvms.trim(vehicle).ballast is None
    monkeypatch.setattr(trim_module, "statics", lambda *a, **k: pytest.fail("statics computed before the checks"))
    tic = time.perf_counter()
    with pytest.raises(UvmsInputError) as info:
        uvms.trim(vehicle, **options)
    assert time.perf_counter() - tic < 1.0
    assert info.value.path == path and words in info.value.message and "\n" not in str(info.value)
