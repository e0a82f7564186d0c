"""Healey thruster: steady figures, four-quadrant symmetry, kernel against an independent evaluation, speed
dependence of the poles, steady inverse, RK4 stability limit, and the ``thruster-curve`` command."""

from __future__ import annotations

import argparse
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from uvms.thrusters.healey import (
    RECOMMENDED_MAX_STEP,
    RK4_STABILITY_LIMIT,
    HealeyParameters,
    healey_derivatives,
    healey_thrust_torque,
    linearised_eigenvalues,
    rise_time,
    rk4_stable_step,
    steady_state,
    step_response,
    voltage_for_thrust,
)

PARAMS = HealeyParameters()
P = PARAMS.as_array()
RISE = 1.0 - math.exp(-1.0)


def simulate(V: float, duration: float, y0=(0.0, 0.0)):
    """Fine reference solution of the state equations (Radau, tight tolerances) with dense output."""
    def rhs(t, y):
        return healey_derivatives(P, y[0], y[1], V)

    return solve_ivp(rhs, (0.0, duration), list(y0), method="Radau", rtol=1e-11, atol=1e-12, dense_output=True)


def reference_thrust_torque(Omega, U):
    """The conventions' blade formulas, written independently of the kernel (NumPy, named parameters)."""
    pr = PARAMS
    A = np.pi * pr.radius**2
    x = 0.7 * pr.radius * Omega
    theta = np.arctan2(U, x)
    alpha = pr.pitch - theta
    q = 0.5 * pr.density * np.hypot(U, x) ** 2 * A
    lift = q * pr.lift_max * np.sin(2 * alpha)
    drag = q * pr.drag_max * (1 - np.cos(2 * alpha))
    return lift * np.cos(theta) - drag * np.sin(theta), 0.7 * pr.radius * (lift * np.sin(theta) + drag * np.cos(theta))


def simulated_thrust(V: float, duration: float):
    """Times, Omega, U and thrust of a step from rest, sampled every 10 us."""
    sol = simulate(V, duration)
    t = np.linspace(0.0, duration, round(duration / 1e-5) + 1)
    Omega, U = sol.sol(t)
    return t, Omega, U, reference_thrust_torque(Omega, U)[0]


# --- steady state and rise time ------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def responses():
    # long enough to settle to 1e-9: the slow pole is -31.7 1/s at 24 V, -4.0 1/s at 1 V
    return {V: simulated_thrust(V, 8.0 if abs(V) < 2 else 2.0) for V in (24.0, -24.0, 12.0, -12.0, 1.0)}


def test_steady_thrust_at_24_and_12_volts(responses):
    assert responses[24.0][3][-1] == pytest.approx(51.8, rel=0.02)
    assert responses[12.0][3][-1] == pytest.approx(16.0, rel=0.05)


def test_steady_thrust_is_odd_in_voltage(responses):
    for V in (24.0, 12.0):
        positive, negative = responses[V][3][-1], responses[-V][3][-1]
        assert abs(negative + positive) <= 1e-9 * abs(positive)
    for V in np.linspace(0.5, 24.0, 7):
        assert steady_state(PARAMS, -V)[2] == pytest.approx(-steady_state(PARAMS, V)[2], rel=1e-12)


def test_closed_form_steady_state_matches_simulation(responses):
    for V in (24.0, 12.0, -12.0, 1.0):
        _, Omega, U, T = responses[V]
        Omega_s, U_s, T_s = steady_state(PARAMS, V)
        assert Omega[-1] == pytest.approx(Omega_s, rel=1e-6)
        assert U[-1] == pytest.approx(U_s, rel=1e-6)
        assert T[-1] == pytest.approx(T_s, rel=1e-6)


def test_rise_time_about_30_ms(responses):
    t, _, _, T = responses[24.0]
    assert rise_time(t, T, RISE) == pytest.approx(0.030, rel=0.20)


def test_small_step_rises_slower_than_full_step(responses):
    full = rise_time(*responses[24.0][::3], RISE)
    small = rise_time(*responses[1.0][::3], RISE)
    assert small > 1.03 * full


def test_zero_thrust_at_rest():
    T, Q = healey_thrust_torque(P, 0.0, 0.0)
    assert T == 0.0 and Q == 0.0
    assert healey_derivatives(P, 0.0, 0.0, 0.0) == (0.0, 0.0)


def test_compiled_step_response_matches_reference():
    response = step_response(PARAMS, 24.0, 0.2, 1e-3)
    sol = simulate(24.0, 0.2)
    Omega, U = sol.sol(response.time)
    np.testing.assert_allclose(response.omega, Omega, rtol=0, atol=1e-6 * 314.0)
    np.testing.assert_allclose(response.inflow, U, rtol=0, atol=1e-6 * 2.6)


# --- four quadrants -----------------------------------------------------------------------------------------

def test_quadrant_signs():
    T, Q = healey_thrust_torque(P, -300.0, 0.0)  # bollard, reverse spin
    assert T < 0 and Q < 0  # reverse thrust; the torque opposes the (negative) rotation
    T, Q = healey_thrust_torque(P, 0.0, 2.0)  # locked rotor in forward inflow
    assert T < 0  # the blades brake the duct flow
    assert Q < 0  # and drive the rotor forward (windmilling): J dOmega/dt = -Q > 0
    T_fwd, _ = healey_thrust_torque(P, 300.0, 2.0)
    T_against, _ = healey_thrust_torque(P, 300.0, -2.0)
    assert T_against > T_fwd > 0  # inflow against the thrust raises the angle of attack


def reference_derivatives(Omega, U, V):
    """The conventions' state equations, written independently of the kernel."""
    pr = PARAMS
    A = np.pi * pr.radius**2
    thrust, torque = reference_thrust_torque(Omega, U)
    current = (V - pr.back_emf_constant * Omega) / pr.resistance
    motor = np.array([pr.torque_constant * current, -pr.friction * Omega, -torque])
    duct = np.array([thrust, -pr.density * A * pr.delta_beta * np.abs(U) * U])
    return (motor.sum() / pr.inertia, duct.sum() / (pr.density * A * pr.duct_length * pr.gamma),
            np.abs(motor).sum() / pr.inertia, np.abs(duct).sum() / (pr.density * A * pr.duct_length * pr.gamma))


speed = st.floats(0.0, 400.0, allow_nan=False)
inflow = st.floats(0.0, 4.0, allow_nan=False)
sign = st.sampled_from([-1.0, 1.0])


@settings(max_examples=300, deadline=None)
@given(speed, inflow, sign, sign, st.floats(-24.0, 24.0))
def test_kernel_matches_independent_evaluation(Omega, U, s_Omega, s_U, V):
    Omega, U = s_Omega * Omega, s_U * U
    dOmega, dU = healey_derivatives(P, Omega, U, V)
    ref_dOmega, ref_dU, scale_Omega, scale_U = reference_derivatives(Omega, U, V)
    # 1e-12 relative to the size of the terms summed (the sum itself may cancel near equilibrium)
    assert abs(dOmega - ref_dOmega) <= 1e-12 * max(scale_Omega, 1e-300)
    assert abs(dU - ref_dU) <= 1e-12 * max(scale_U, 1e-300)


@settings(max_examples=200, deadline=None)
@given(speed, inflow, sign, sign, st.floats(-24.0, 24.0))
def test_model_is_odd(Omega, U, s_Omega, s_U, V):
    Omega, U = s_Omega * Omega, s_U * U
    T, Q = healey_thrust_torque(P, Omega, U)
    Tm, Qm = healey_thrust_torque(P, -Omega, -U)
    scale = 0.5 * 1000 * np.pi * 0.05**2 * (U * U + (0.035 * Omega) ** 2) + 1e-300
    assert abs(T + Tm) <= 1e-12 * scale and abs(Q + Qm) <= 1e-12 * scale
    d = healey_derivatives(P, Omega, U, V)
    dm = healey_derivatives(P, -Omega, -U, -V)
    assert d[0] == pytest.approx(-dm[0], rel=1e-9, abs=1e-9) and d[1] == pytest.approx(-dm[1], rel=1e-9, abs=1e-9)


# --- speed dependence of the poles ---------------------------------------------------------------------------

def test_poles_grow_with_speed():
    voltages = [0.5, 1.0, 3.0, 6.0, 12.0, 18.0, 24.0]
    for direction in (1.0, -1.0):
        mags = []
        for V in voltages:
            Omega, U, _ = steady_state(PARAMS, direction * V)
            eig = linearised_eigenvalues(PARAMS, Omega, U, direction * V)
            assert np.all(eig.real < 0)
            mags.append(np.sort(np.abs(eig)))
        mags = np.array(mags)
        assert np.all(np.diff(mags[:, 0]) > 0) and np.all(np.diff(mags[:, 1]) > 0)
    # near rest the duct pole vanishes: the slow mode's time constant is far longer than at full thrust
    assert mags[0, 0] < 0.1 * mags[-1, 0]


# --- steady inverse -------------------------------------------------------------------------------------------

def test_voltage_thrust_round_trip():
    for V in np.linspace(-24.0, 24.0, 97):
        T = steady_state(PARAMS, V)[2]
        assert voltage_for_thrust(PARAMS, T) == pytest.approx(V, abs=1e-6)
    grid = np.linspace(-24.0, 24.0, 9)
    thrusts = np.array([steady_state(PARAMS, V)[2] for V in grid])
    np.testing.assert_allclose(voltage_for_thrust(PARAMS, thrusts), grid, atol=1e-6)


def test_voltage_is_clipped():
    assert voltage_for_thrust(PARAMS, 500.0) == 24.0
    assert voltage_for_thrust(PARAMS, -500.0) == -24.0
    assert voltage_for_thrust(PARAMS, 0.0) == 0.0


def test_voltage_for_thrust_follows_inflow_then_speed():
    T = 20.0
    A = np.pi * PARAMS.radius**2
    U = math.sqrt(T / (PARAMS.density * A * PARAMS.delta_beta))  # duct balance
    Omega, U_s, T_s = steady_state(PARAMS, voltage_for_thrust(PARAMS, T))
    assert T_s == pytest.approx(T, rel=1e-10) and U_s == pytest.approx(U, rel=1e-10)
    dOmega, dU = healey_derivatives(P, Omega, U_s, voltage_for_thrust(PARAMS, T))
    assert abs(dOmega) < 1e-8 and abs(dU) < 1e-8


# --- RK4 stability ---------------------------------------------------------------------------------------------

def test_rk4_limit_is_set_by_full_thrust():
    Omega, U, _ = steady_state(PARAMS, 24.0)
    limit = rk4_stable_step(linearised_eigenvalues(PARAMS, Omega, U, 24.0))
    assert limit == pytest.approx(RK4_STABILITY_LIMIT, rel=0.01)
    # no state of a full reversal needs a smaller step
    reversal = step_response(PARAMS, -24.0, 0.3, 2e-3, initial_omega=Omega, initial_inflow=U)
    for w, u in zip(reversal.omega, reversal.inflow):
        assert rk4_stable_step(linearised_eigenvalues(PARAMS, w, u, -24.0)) >= 0.999 * RK4_STABILITY_LIMIT
    assert RECOMMENDED_MAX_STEP < RK4_STABILITY_LIMIT


@pytest.mark.parametrize("factor, converges", [(0.95, True), (1.1, False)])
def test_fixed_step_rk4_stability(factor, converges):
    h = factor * RK4_STABILITY_LIMIT
    Omega, U, T = steady_state(PARAMS, 24.0)
    r = step_response(PARAMS, 24.0, 400 * h, h, max_substep=h, initial_omega=0.9 * Omega, initial_inflow=U)
    error = abs(r.thrust[-1] - T)
    assert (error < 1e-3) == converges


def test_recommended_step_is_accurate():
    h = RECOMMENDED_MAX_STEP
    coarse = step_response(PARAMS, 24.0, 0.3, h, max_substep=h)
    sol = simulate(24.0, 0.3)
    Omega, U = sol.sol(coarse.time)
    exact = np.array([healey_thrust_torque(P, w, u)[0] for w, u in zip(Omega, U)])
    assert np.max(np.abs(coarse.thrust - exact)) < 1e-3 * 51.8


# --- parameters and the command ----------------------------------------------------------------------------------

def test_parameters_validate_and_flatten():
    from uvms.thrusters import healey

    flat = PARAMS.as_array()
    assert flat.shape == (healey.N_PARAMETERS,)
    for index, value in [(healey.P_RADIUS, 0.05), (healey.P_PITCH, math.radians(24.4)), (healey.P_LIFT, 0.30),
                         (healey.P_DRAG, 0.50), (healey.P_DUCT_LENGTH, 0.10), (healey.P_GAMMA, 1.0),
                         (healey.P_DBETA, 1.0), (healey.P_KT, 0.0588), (healey.P_KE, 0.0588),
                         (healey.P_RESISTANCE, 0.29), (healey.P_FRICTION, 2e-5), (healey.P_INERTIA, 5e-4),
                         (healey.P_VMAX, 24.0), (healey.P_DENSITY, 1000.0)]:
        assert flat[index] == pytest.approx(value, rel=1e-12)
    with pytest.raises(ValueError):
        HealeyParameters(radius=-1.0)
    with pytest.raises(ValueError):
        HealeyParameters(pitch=2.0)


def test_thruster_curve_command(tmp_path, capsys):
    from uvms.commands import thruster_curve

    parser = argparse.ArgumentParser()
    thruster_curve.add_arguments(parser)
    figure = tmp_path / "curve.png"
    args = parser.parse_args(["--step", "6", "--plot", str(figure)])
    assert thruster_curve.NAME == "thruster-curve"
    assert thruster_curve.run(args) == 0
    out = capsys.readouterr().out
    assert "+51.80" in out and "-51.80" in out
    row = next(line for line in out.splitlines() if "+24.0" in line)     # the 24 V row: its 63 % rise time
    rise_ms = float(row.replace("│", " ").split()[-1])
    assert 24.0 <= rise_ms <= 36.0                                       # conventions: ~30 ms within 20 %
    assert figure.stat().st_size > 10_000


@pytest.mark.parametrize("argv, message", [
    (["--step", "1e-9"], "--step: expected a voltage step from 0.024 to 24 V, found 1e-09"),
    (["--step", "inf"], "--step: expected a voltage step from 0.024 to 24 V, found inf"),
    (["--plot", "curve.txt"], "curve.txt: --plot: expected a .png, .pdf, .svg or .jpg file name"),
])
def test_thruster_curve_bad_values_are_one_line(tmp_path, monkeypatch, capsys, argv, message):
    from uvms.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(["thruster-curve", *argv]) == 2
    assert capsys.readouterr().err == f"uvms: error: {message}\n"
    assert list(tmp_path.iterdir()) == []


def test_bank_matches_single_thruster_kernels():
    from uvms.thrusters.healey import healey_bank_derivatives

    rng = np.random.default_rng(3)
    other = HealeyParameters(radius=0.06, inertia=8e-4)
    params = np.stack([P, other.as_array(), P])
    Omega, U, V = rng.uniform(-300, 300, 3), rng.uniform(-2, 2, 3), rng.uniform(-24, 24, 3)
    dOmega, dU, thrust = np.empty(3), np.empty(3), np.empty(3)
    healey_bank_derivatives(params, Omega, U, V, dOmega, dU, thrust)
    for h in range(3):
        assert (dOmega[h], dU[h]) == healey_derivatives(params[h], Omega[h], U[h], V[h])
        assert thrust[h] == healey_thrust_torque(params[h], Omega[h], U[h])[0]
