"""The water (uvms.hydro.flow) and the forces it makes, against closed forms written out here independently.

References: linear (Airy) wave kinematics, DNV-RP-C205 ch. 3 and Faltinsen (1990) ch. 2; the dispersion relation
is solved here with scipy's brentq (not with uvms); Morison's equation for a fixed cylinder; the equation of
motion of a neutrally buoyant body without drag, m a = rho V a_f + m_a (a_f - a) + (rho V - m) g, whose
solution is a = a_f.
"""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.optimize import brentq

import uvms
from uvms.errors import UvmsInputError
from uvms.hydro.flow import Flow

G = 9.81


def dispersion_k(omega: float, h: float) -> float:
    """Wave number of omega^2 = g k tanh(k h) (independent root finder)."""
    if math.isinf(h):
        return omega**2 / G
    return brentq(lambda k: G * k * math.tanh(k * h) - omega**2, 1e-9, 1e3)


def waves(a, omega, h, direction=0.0, phase=0.0):
    a, omega = np.atleast_1d(a).astype(float), np.atleast_1d(omega).astype(float)
    k = np.array([dispersion_k(w, h) for w in omega])
    return SimpleNamespace(amplitude=a, omega=omega, wavenumber=k, direction=np.full(a.size, direction),
                           phase=np.full(a.size, phase), water_depth=h)


def airy_gradient(a, w, k, h, beta, phi, t, x, y, zeta, step=1e-6):
    """d u_r / d(x, y, zeta)_c of the closed form, by central differences (independent of uvms' gradient)."""
    J = np.zeros((3, 3))
    for c in range(3):
        e = np.zeros(3)
        e[c] = step
        up_ = airy(a, w, k, h, beta, phi, t, x + e[0], y + e[1], zeta + e[2])[0]
        down = airy(a, w, k, h, beta, phi, t, x - e[0], y - e[1], zeta - e[2])[0]
        J[:, c] = (up_ - down) / (2 * step)
    return J


def airy(a, w, k, h, beta, phi, t, x, y, zeta):
    """Closed-form finite-depth kinematics, z up from the mean surface: (u (3), du/dt (3))."""
    theta = k * (x * math.cos(beta) + y * math.sin(beta)) - w * t + phi
    if math.isinf(h):
        ch = sh = math.exp(k * zeta)
    else:
        ch = math.cosh(k * (zeta + h)) / math.sinh(k * h)
        sh = math.sinh(k * (zeta + h)) / math.sinh(k * h)
    uh = a * w * ch * math.cos(theta)
    uz = a * w * sh * math.sin(theta)
    ah = a * w**2 * ch * math.sin(theta)
    az = -a * w**2 * sh * math.cos(theta)
    return (np.array([uh * math.cos(beta), uh * math.sin(beta), uz]),
            np.array([ah * math.cos(beta), ah * math.sin(beta), az]))


# ------------------------------------------------------------------------------------------------ kinematics


@pytest.mark.parametrize("h", [8.0, 20.0, math.inf])
@pytest.mark.parametrize("convention", ["enu", "ned"])
def test_finite_depth_kinematics_match_the_closed_form(h, convention):
    w = waves([0.3, 0.1], [1.2, 2.1], h, direction=0.4, phase=0.7)
    flow = Flow.constant(waves=w)
    up = 1.0 if convention == "enu" else -1.0
    rng = np.random.default_rng(1)
    for _ in range(5):
        x, y = rng.uniform(-30, 30, 2)
        zeta = -rng.uniform(0.0, 7.9)
        t = rng.uniform(0, 50)
        v, a = flow.at(t, [x, y, up * zeta], convention)
        expected_v, local, J = np.zeros(3), np.zeros(3), np.zeros((3, 3))
        for i in range(2):
            args = (w.amplitude[i], w.omega[i], w.wavenumber[i], h, 0.4, 0.7, t, x, y, zeta)
            vi, ai = airy(*args)
            expected_v += vi
            local += ai
            J += airy_gradient(*args)
        expected_a = local + J @ expected_v             # material acceleration du/dt + (u . grad) u (z up)
        flip = np.array([1.0, 1.0, up])                 # z down in ned: the vertical components change sign
        np.testing.assert_allclose(v[0], flip * expected_v, rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(a[0], flip * expected_a, rtol=1e-7, atol=1e-10)
        _, _, grad = flow.kinematics(t, [x, y, up * zeta], convention)
        np.testing.assert_allclose(grad[0], flip[:, None] * J * flip[None, :], rtol=1e-6, atol=1e-9)


def test_deep_water_limit():
    """k h >> 1: u = a w e^{k z} cos(theta), w_z = a w e^{k z} sin(theta), k = w^2 / g."""
    a, omega, h = 0.2, 2.0, 200.0                      # k h = 81
    w = waves(a, omega, h)
    k = omega**2 / G
    np.testing.assert_allclose(w.wavenumber[0], k, rtol=1e-12)
    flow = Flow.constant(waves=w)
    for t, x, z in [(0.3, 1.0, -2.0), (4.1, -3.0, -6.0), (9.0, 12.0, -0.5)]:
        theta = k * x - omega * t
        v, acc = flow.at(t, [x, 0.0, z], "enu")
        e = math.exp(k * z)
        np.testing.assert_allclose(v[0], [a * omega * e * math.cos(theta), 0, a * omega * e * math.sin(theta)],
                                   rtol=1e-12, atol=1e-15)
        convective = k * (a * omega * e) ** 2            # (u . grad) u = grad |u|^2 / 2, |u| = a w e^{kz}, upward
        np.testing.assert_allclose(acc[0], [a * omega**2 * e * math.sin(theta), 0,
                                            -a * omega**2 * e * math.cos(theta) + convective], rtol=1e-12,
                                   atol=1e-15)


def test_shallow_water_limit():
    """k h << 1: w^2 = g h k^2; u = a sqrt(g / h) cos(theta) at every depth, w_z = a w (1 + z / h) sin(theta)."""
    a, T, h = 0.1, 30.0, 2.0
    omega = 2 * math.pi / T
    w = waves(a, omega, h)
    k = w.wavenumber[0]
    assert k * h < 0.1
    np.testing.assert_allclose(omega / k, math.sqrt(G * h), rtol=2e-3)     # long-wave celerity sqrt(g h)
    flow = Flow.constant(waves=w)
    t, x = 3.0, 5.0
    theta = k * x - omega * t
    for z in (-0.1, -1.0, -1.9):
        v, _ = flow.at(t, [x, 0.0, z], "enu")
        np.testing.assert_allclose(v[0, 0], a * math.sqrt(G / h) * math.cos(theta), rtol=5e-3)
        np.testing.assert_allclose(v[0, 2], a * omega * (1 + z / h) * math.sin(theta), rtol=5e-3, atol=1e-6)


def test_material_acceleration_is_local_plus_convective():
    """a_f = du/dt (central difference in time) + grad u (central differences in space) u."""
    prof = SimpleNamespace(depth=np.array([0.0, 10.0]), velocity=np.array([[0.3, 0.1, 0.05], [0.0, 0.0, 0.0]]))
    flow = Flow.constant(profile=prof, waves=waves([0.3, 0.2], [0.9, 1.7], 15.0, direction=1.0))
    p, t, d = np.array([2.0, -1.0, 4.0]), 3.0, 1e-5          # ned: 4 m deep
    v, a, grad = flow.kinematics(t, p)
    local = (flow.at(t + d, p)[0][0] - flow.at(t - d, p)[0][0]) / (2 * d)
    J = np.column_stack([(flow.at(t, p + e)[0][0] - flow.at(t, p - e)[0][0]) / (2 * d) for e in np.eye(3) * d])
    np.testing.assert_allclose(grad[0], J, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(a[0], local + J @ v[0], rtol=1e-6, atol=1e-9)


def test_above_the_mean_surface_the_kinematics_are_held_at_it():
    flow = Flow.constant(waves=waves(0.5, 1.5, 20.0), surface=1.0)
    at_surface = flow.kinematics(2.0, [1.0, 0.0, 1.0], "enu")
    just_above = flow.kinematics(2.0, [1.0, 0.0, 1.0 + 1e-9], "enu")
    np.testing.assert_array_equal(just_above[2][:, :, 2], 0.0)        # held: no vertical derivatives
    np.testing.assert_array_equal(just_above[2][:, :, :2], at_surface[2][:, :, :2])
    for z in (1.2, 1.5, 3.0):
        above = flow.kinematics(2.0, [1.0, 0.0, z], "enu")
        np.testing.assert_array_equal(above[0], at_surface[0])        # the surface's velocity
        for got, held in zip(above, just_above):
            np.testing.assert_array_equal(got, held)
    below = flow.at(2.0, [1.0, 0.0, 0.5], "enu")          # the surface at z = 1: 0.5 m is submerged
    assert abs(below[0][0, 0]) < abs(at_surface[0][0, 0])


def test_parts_superpose():
    prof = SimpleNamespace(depth=np.array([0.0, 10.0]), velocity=np.array([[0.4, 0.0, 0.0], [0.0, 0.2, 0.0]]))
    w = waves(0.2, 1.3, 30.0)
    p, t = [3.0, 1.0, 4.0], 2.5
    total = Flow([0.0, 10.0], [[0.1, 0, 0], [0.3, 0, 0]], [[0.02, 0, 0], [0.02, 0, 0]], profile=prof, waves=w)
    table = Flow([0.0, 10.0], [[0.1, 0, 0], [0.3, 0, 0]], [[0.02, 0, 0], [0.02, 0, 0]])
    v, a, J = total.kinematics(t, p)
    parts = [f.kinematics(t, p) for f in (table, Flow.constant(profile=prof), Flow.constant(waves=w))]
    np.testing.assert_allclose(v, sum(q[0] for q in parts), rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(J, sum(q[2] for q in parts), rtol=1e-14, atol=1e-15)
    local = sum(q[1][0] - q[2][0] @ q[0][0] for q in parts)          # each part's du/dt
    np.testing.assert_allclose(a[0], local + J[0] @ v[0], rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(parts[0][0][0], [0.15, 0, 0], rtol=1e-14)    # the table: linear in time
    np.testing.assert_array_equal(parts[0][2], 0.0)                          # and uniform
    np.testing.assert_array_equal(parts[1][1], 0.0)      # a steady horizontal profile does not accelerate


# ---------------------------------------------------------------------------------------- profiles and fields


@pytest.mark.parametrize("convention,sign", [("ned", 1.0), ("enu", -1.0)])
def test_depth_profile_is_linear_in_depth_and_held_beyond(convention, sign):
    prof = SimpleNamespace(depth=np.array([0.0, 5.0, 20.0]),
                           velocity=np.array([[1.0, 0.0, 0.0], [0.5, 0.5, 0.0], [0.0, 0.0, 0.0]]))
    flow = Flow.constant(profile=prof)
    z = lambda depth: sign * depth                          # noqa: E731  (world z of a depth)
    v, _ = flow.at(0.0, [[0, 0, z(2.5)], [0, 0, z(12.5)], [0, 0, z(-3.0)], [0, 0, z(40.0)]], convention)
    np.testing.assert_allclose(v, [[0.75, 0.25, 0], [0.25, 0.25, 0], [1.0, 0, 0], [0, 0, 0]], rtol=1e-14,
                               atol=1e-15)


G_FIELD = np.array([[0.01, 0.02, 0.0], [0.0, -0.03, 0.01], [0.02, 0, 0.01]])


def linear_field(outside="hold"):
    """u = c + G p + d t on a coarse grid (trilinear interpolation reproduces a linear function exactly)."""
    x, y, z, t = np.array([-2.0, 0.0, 3.0]), np.array([-1.0, 1.0]), np.array([0.0, 2.0, 5.0]), np.array([0.0, 4.0])
    c, Gm, d = np.array([0.1, -0.2, 0.05]), G_FIELD, np.array([0.01, 0.0, -0.02])
    V = np.zeros((t.size, z.size, y.size, x.size, 3))
    for it, tt in enumerate(t):
        for iz, zz in enumerate(z):
            for iy, yy in enumerate(y):
                for ix, xx in enumerate(x):
                    V[it, iz, iy, ix] = c + Gm @ np.array([xx, yy, zz]) + d * tt
    field = SimpleNamespace(x=x, y=y, z=z, t=t, velocity=V, outside=outside)
    return field, (lambda p, tt: c + Gm @ np.asarray(p) + d * tt), d


def test_field_is_trilinear_in_space_and_linear_in_time():
    field, exact, d = linear_field()
    flow = Flow.constant(field=field)
    rng = np.random.default_rng(3)
    for _ in range(10):
        p = [rng.uniform(-2, 3), rng.uniform(-1, 1), rng.uniform(0, 5)]
        t = rng.uniform(0, 4)
        v, a, grad = flow.kinematics(t, p)
        np.testing.assert_allclose(v[0], exact(p, t), rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(grad[0], G_FIELD, rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(a[0], d + G_FIELD @ exact(p, t), rtol=1e-12, atol=1e-14)    # du/dt + (u . grad) u
    v, a = flow.at(9.0, [0.0, 0.0, 1.0])                 # after the last time: held, no local acceleration
    np.testing.assert_allclose(v[0], exact([0.0, 0.0, 1.0], 4.0), rtol=1e-12)
    np.testing.assert_allclose(a[0], G_FIELD @ v[0], rtol=1e-12, atol=1e-15)


def test_field_outside_policies():
    outside_point = [10.0, 0.0, 1.0]
    field, exact, _ = linear_field("hold")
    v, _ = Flow.constant(field=field).at(1.0, outside_point)
    np.testing.assert_allclose(v[0], exact([3.0, 0.0, 1.0], 1.0), rtol=1e-12)       # the nearest face's value
    field, _, _ = linear_field("zero")
    v, a = Flow.constant([0.1, 0, 0], field=field).at(1.0, outside_point)
    np.testing.assert_allclose(v[0], [0.1, 0, 0])                                     # the uniform part only
    field, _, _ = linear_field("error")
    with pytest.raises(UvmsInputError, match="current.field.outside"):
        Flow.constant(field=field).at(1.0, outside_point)


def test_field_with_single_value_axes_is_constant_along_them():
    V = np.zeros((1, 1, 1, 2, 3))
    V[0, 0, 0, :, 0] = [0.0, 1.0]
    field = SimpleNamespace(x=np.array([0.0, 10.0]), y=np.array([0.0]), z=np.array([0.0]), t=np.array([0.0]),
                            velocity=V, outside="error")
    v, a = Flow.constant(field=field).at(5.0, [2.5, 0.0, 0.0])
    np.testing.assert_allclose(v[0], [0.25, 0, 0])
    v_off, _ = Flow.constant(field=field).at(5.0, [2.5, 7.0, -3.0])     # constant along y and z: never outside
    np.testing.assert_array_equal(v_off, v)
    with pytest.raises(UvmsInputError):
        Flow.constant(field=field).at(5.0, [12.5, 0.0, 0.0])        # beyond x: outside


@pytest.mark.parametrize("bad,match", [
    (dict(times=[0.0, 0.0]), "flow.times"),
    (dict(profile=SimpleNamespace(depth=np.array([1.0, 0.5]), velocity=np.zeros((2, 3)))), "profile.depth"),
    (dict(field=SimpleNamespace(x=np.array([0.0, np.nan]), y=np.zeros(1), z=np.zeros(1), t=np.zeros(1),
                                velocity=np.zeros((1, 1, 1, 2, 3)), outside="hold")), "field.x"),
    (dict(field=SimpleNamespace(x=np.zeros(1), y=np.zeros(1), z=np.zeros(1), t=np.zeros(1),
                                velocity=np.zeros((1, 1, 1, 1, 3)), outside="wrap")), "field.outside"),
    (dict(waves=SimpleNamespace(amplitude=np.ones(1), omega=np.ones(1), wavenumber=np.ones(1),
                                direction=np.zeros(1), phase=np.zeros(1), water_depth=-1.0)), "water_depth"),
])
def test_bad_flow_arguments_name_the_field(bad, match):
    args = dict(times=[0.0], velocity=[[0, 0, 0]], acceleration=[[0, 0, 0]])
    args.update(bad)
    n = len(args["times"])
    args["velocity"], args["acceleration"] = np.zeros((n, 3)), np.zeros((n, 3))
    with pytest.raises(UvmsInputError, match=match):
        Flow(**args)


# ------------------------------------------------------------------------------------------------ the forces


def particle_model(added_mass: float):
    """The paper's vehicle alone, neutrally buoyant (m_f = m, b = r_G), without drag, with a diagonal added
    mass of ``added_mass`` kg on every linear axis (and 0.1 of it on every angular one)."""
    base = uvms.load_model("paper").vehicle_only().with_effects(drag=False)
    I_A = np.zeros((1, 6, 6))
    I_A[0, :3, :3] = 0.1 * added_mass * np.eye(3)
    I_A[0, 3:, 3:] = added_mass * np.eye(3)
    return base.replace(buoyancy_mass=base.mass.copy(), cob=base.com.copy(), added_mass=I_A)


@pytest.mark.parametrize("added_mass", [0.0, 40.0, 400.0])
def test_neutral_body_without_drag_follows_the_water_particle(added_mass):
    """a = a_f whatever the added mass; in regular deep-water waves the orbit radius is a e^{k z}."""
    model = particle_model(added_mass)
    a, T = 0.1, 4.0
    omega = 2 * math.pi / T
    w = waves(a, omega, math.inf)
    k = w.wavenumber[0]
    depth = 3.0
    flow = Flow.constant(waves=w)
    expected = a * math.exp(-k * depth)
    p0 = np.array([0.0, 0.0, depth - expected])              # ned: the particle of mean depth 3 m, at its crest
    u0, _ = flow.at(0.0, p0)                                 # moving with the water there
    state = uvms.State.zero(model).replace(position=p0, nu=np.concatenate([np.zeros(3), u0[0]]))
    result = uvms.simulate(model, state, duration=10 * T, step=0.01, flow=flow)
    t = np.asarray(result.time)
    p = np.asarray(result.position)
    drift = np.polyval(np.polyfit(t, p[:, 0], 1), t)       # Stokes drift ~ w k a^2 e^{2kz}: second order
    for r in range(10):                                     # each period's half peak-to-peak, both axes
        period = (t >= r * T) & (t < (r + 1) * T)
        horizontal = np.ptp(p[period, 0] - drift[period]) / 2
        vertical = np.ptp(p[period, 2]) / 2
        assert abs(horizontal / expected - 1.0) < 0.01, (r, horizontal, expected)
        assert abs(vertical / expected - 1.0) < 0.01, (r, vertical, expected)
    assert np.max(np.abs(p[:, 1])) < 1e-9                   # no motion across the waves


def fixed_cylinder(D: float, L: float, Ca: float, Cd: float):
    """A vertical circular cylinder as the vehicle: displaced mass rho pi D^2 L / 4, added mass Ca of it
    across the axis (x, y), drag 0.5 rho Cd D L across, nothing along the axis."""
    base = uvms.load_model("paper").vehicle_only().with_effects(drag=False)
    rho = base.density
    V = math.pi * D**2 / 4 * L
    I_A = np.zeros((1, 6, 6))
    I_A[0, 3, 3] = I_A[0, 4, 4] = Ca * rho * V
    return base.replace(buoyancy_mass=np.array([rho * V]), cob=np.zeros((1, 3)), added_mass=I_A,
                        vehicle_drag_area=np.array([D * L, D * L, 0.0]),
                        vehicle_drag_coefficient=np.array([Cd, Cd, 0.0])), rho, V


def test_morison_force_on_a_fixed_cylinder_in_regular_waves():
    """f = rho V (1 + C_a) Du/Dt + 1/2 rho C_d D L u |u| (Morison), u and Du/Dt = du/dt + u du/dx + w du/dz the
    Airy kinematics at the cylinder (closed forms written out here)."""
    from uvms.dynamics.inspect import hydrodynamic_wrenches_in

    D, L, Ca, Cd = 0.3, 0.5, 1.0, 1.2
    model, rho, V = fixed_cylinder(D, L, Ca, Cd)
    h, a, T, depth = 12.0, 0.4, 5.0, 2.0
    w = waves(a, 2 * math.pi / T, h)
    flow = Flow.constant(waves=w)
    state = uvms.State.zero(model).replace(position=np.array([1.5, 0.0, depth]))
    for t in np.linspace(0.0, T, 9):
        out = hydrodynamic_wrenches_in(model, state, flow, t, fixed_base=True)
        force = sum(out.wrenches[c][0, 3:] for c in ("fluid_acceleration", "drag", "added_mass_velocity"))
        om, k = w.omega[0], w.wavenumber[0]
        theta = k * 1.5 - om * t
        ch = math.cosh(k * (h - depth)) / math.sinh(k * h)
        sh = math.sinh(k * (h - depth)) / math.sinh(k * h)
        u, uz = a * om * ch * math.cos(theta), a * om * sh * math.sin(theta)
        du_dt = a * om**2 * ch * math.sin(theta)
        du_dx, du_dz = -a * om * k * ch * math.sin(theta), a * om * k * sh * math.cos(theta)
        Du = du_dt + u * du_dx + uz * du_dz                 # the water's material acceleration
        expected_x = rho * V * (1 + Ca) * Du + 0.5 * rho * Cd * D * L * u * abs(u)
        np.testing.assert_allclose(force[0], expected_x, rtol=1e-10, atol=1e-10)


def test_a_body_drifting_with_the_local_current_feels_no_drag():
    """Drag acts on the velocity relative to the local water: moving with it, none (uniform and profile)."""
    from uvms.dynamics.inspect import hydrodynamic_wrenches, hydrodynamic_wrenches_in

    model = uvms.load_model("paper").vehicle_only()
    current = np.array([0.3, -0.2, 0.05])
    state = uvms.State.from_euler(model, euler=[0.1, -0.2, 0.7], position=[0, 0, 4.0])
    drifting = state.replace(nu=np.concatenate([np.zeros(3), state.rotation.T @ current]))
    uniform = hydrodynamic_wrenches(model, drifting, current=current)
    np.testing.assert_allclose(uniform.wrenches["drag"], 0.0, atol=1e-15)
    prof = SimpleNamespace(depth=np.array([0.0, 10.0]), velocity=np.array([[0.5, 0.0, 0.0], [0.0, 0.0, 0.0]]))
    flow = Flow.constant(profile=prof)
    b = model.cob[0]
    local = flow.at(0.0, state.position + state.rotation @ b)[0][0]            # the water at the buoyancy centre
    assert local[0] > 0.2
    drifting = state.replace(nu=np.concatenate([np.zeros(3), state.rotation.T @ local]))
    in_profile = hydrodynamic_wrenches_in(model, drifting, flow)
    np.testing.assert_allclose(in_profile.wrenches["drag"], 0.0, atol=1e-15)
    at_rest = hydrodynamic_wrenches_in(model, state, flow)
    assert np.abs(at_rest.wrenches["drag"][0, 3:]).max() > 1.0


def test_every_body_sees_the_water_at_its_own_buoyancy_centre():
    """The relative velocity of each body at rest is -R_i^T u_f(p_i + R_i b_i), poses from uvms.frame_poses."""
    from uvms.dynamics.inspect import hydrodynamic_wrenches_in
    from uvms.dynamics.poses import forward_kinematics

    model = uvms.load_model("bluerov2_heavy_alpha5")
    n = model.n_joints
    state = uvms.State.from_euler(model, euler=[0.2, -0.1, 0.8], position=[1.0, 2.0, 3.0], q=np.full(n, 0.4))
    prof = SimpleNamespace(depth=np.array([2.0, 4.0]), velocity=np.array([[0.6, 0.1, 0.0], [-0.2, 0.3, 0.1]]))
    flow = Flow([0.0], [[0.05, 0, 0]], [[0.0, 0.01, 0]], profile=prof, waves=waves([0.3], [1.4], 15.0, 0.5))
    out = hydrodynamic_wrenches_in(model, state, flow, 1.7)
    poses = forward_kinematics(model, state)
    for i in range(model.n_bodies):
        R, p = poses.rotation[i], poses.position[i]
        u, _ = flow.at(1.7, p + R @ model.cob[i])
        np.testing.assert_allclose(out.relative_velocity[i, 3:], -R.T @ u[0], rtol=1e-10, atol=1e-12)
    world = [poses.rotation[i] @ out.relative_velocity[i, 3:] for i in range(model.n_bodies)]
    assert np.ptp(np.array(world)[:, 0]) > 0.05          # the bodies do see different water


def test_a_uniform_flow_gives_the_uniform_current_results():
    """simulate(flow=Flow of a current table) is simulate(current=the same table), to the last bit."""
    from uvms.sim.inputs import CurrentTable, paper_torques

    model = uvms.load_model("paper")
    table = CurrentTable([0.0, 1.0, 2.0], [[0, 0, 0], [0.2, 0.1, 0], [0.2, 0.3, 0.1]],
                         [[0.2, 0.1, 0], [0.0, 0.2, 0.1], [0, 0, 0]])
    flow = Flow(table.times, table.velocity, table.acceleration)
    by_table = uvms.simulate(model, duration=2.0, step=1e-3, joint_torques=paper_torques(), current=table)
    by_flow = uvms.simulate(model, duration=2.0, step=1e-3, joint_torques=paper_torques(), flow=flow)
    np.testing.assert_array_equal(np.asarray(by_flow.position), np.asarray(by_table.position))
    np.testing.assert_array_equal(np.asarray(by_flow.q), np.asarray(by_table.q))


def test_flow_and_current_together_are_refused():
    model = uvms.load_model("paper")
    with pytest.raises(UvmsInputError, match="flow"):
        uvms.simulate(model, duration=0.01, current=[0.1, 0, 0], flow=Flow.constant())


def test_the_surface_moves_with_the_water_of_the_inputs_side():
    """Linear kinematic surface condition, w(z = 0) = d eta / dt, between uvms.hydro.waves' elevation and
    irregular components (the inputs side of issue 27) and this module's velocities (the fluid side)."""
    from uvms.hydro.waves import Spectrum, elevation, irregular_waves, jonswap

    spectrum = Spectrum(density=lambda w: jonswap(w, 0.5, 4.0), peak=2 * math.pi / 4.0, frequency_range=(0.8, 4.0))
    sea = irregular_waves(spectrum, components=30, seed=4, water_depth=20.0, spreading=2.0)
    flow = Flow.constant(waves=sea)
    d = 1e-5
    for t, x, y in [(1.0, 0.0, 0.0), (7.3, 4.0, -2.0), (20.0, -9.0, 3.0)]:
        v, _ = flow.at(t, [x, y, 0.0], "enu")
        eta_dot = (elevation(sea, t + d, x, y) - elevation(sea, t - d, x, y)) / (2 * d)
        np.testing.assert_allclose(v[0, 2], eta_dot, rtol=1e-7, atol=1e-10)


def test_the_bundled_wave_scenario_runs_in_its_water():
    from uvms.sim.run import simulate
    from uvms.sim.scenario import load_scenario

    path = Path(uvms.__file__).parent / "scenarios" / "bluerov2_heavy_alpha5_waves.yaml"
    options = load_scenario(str(path)).simulate_options()
    assert isinstance(options["flow"], Flow) and options["current"] is None
    options["duration"] = 0.2
    result = simulate(**options)
    assert result.complete
