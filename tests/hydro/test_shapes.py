"""Hydrodynamic shapes against closed forms, Lamb's published table and independent quadrature."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import dblquad, quad

from uvms.hydro.buoyancy import buoyancy_force
from uvms.hydro.drag import box_rotational_drag_by_strips, box_rotational_drag_coefficient
from uvms.hydro.shapes import (Box, Cylinder, Ellipsoid, Sphere, added_mass, buoyancy, drag_table,
                               drag_workspace, ellipsoid_added_mass_coefficients, ellipsoid_inertia_integrals,
                               lamb_k_factors, local_added_mass, rectangle_drag_integrals, rotation_from_axis,
                               shapes_drag_force, spheroid, total_added_mass, transform_added_mass, volume)
from uvms.rotations import rotation_from_euler
from uvms.spatial import roty, rotz

RHO = 1000.0


def drag(shapes, nu):
    out = np.zeros(6)
    shapes_drag_force(drag_table(shapes, RHO), np.asarray(nu, dtype=float), out, drag_workspace())
    return out


def block(Q):
    return np.block([[Q, np.zeros((3, 3))], [np.zeros((3, 3)), Q]])


# ---------------------------------------------------------------------------------------------- volumes


def test_volumes_are_the_closed_forms():
    assert volume(Sphere(0.1)) == pytest.approx(4.0 / 3.0 * math.pi * 1e-3, rel=1e-15)
    assert volume(Box((0.2, 0.3, 0.5))) == pytest.approx(0.03, rel=1e-15)
    assert volume(Cylinder(0.05, 0.4)) == pytest.approx(math.pi * 0.0025 * 0.4, rel=1e-15)
    assert volume(Ellipsoid((0.3, 0.1, 0.2))) == pytest.approx(4.0 / 3.0 * math.pi * 0.006, rel=1e-15)
    assert volume(spheroid(1.6, 0.19)) == pytest.approx(math.pi / 6 * 1.6 * 0.19**2, rel=1e-14)


def test_buoyancy_of_several_shapes_is_rho_g_total_volume_at_the_volume_weighted_centre():
    """The sum of every shape's own buoyancy spatial force equals rho g sum(V) applied at sum(V_i p_i)/sum(V_i)."""
    shapes = [Sphere(0.1, position=[0.3, 0.0, -0.1]), Box((0.2, 0.3, 0.5), position=[-0.2, 0.1, 0.05]),
              Cylinder(0.05, 0.4, rotation=rotation_from_axis([0, 1, 1]), position=[0.0, -0.3, 0.2]),
              spheroid(0.8, 0.2, position=[0.1, 0.2, 0.3])]
    g = np.array([0.0, 0.3, 9.81])                   # gravity in body axes (a tilted body)
    zero = np.zeros(3)
    total = np.zeros(6)
    f = np.zeros(6)
    for s in shapes:
        buoyancy_force(RHO * volume(s), s.position, g, zero, f)
        total += f
    V, cob = buoyancy(shapes)
    V_hand = 4 / 3 * math.pi * 1e-3 + 0.03 + math.pi * 0.0025 * 0.4 + math.pi / 6 * 0.8 * 0.04
    assert V == pytest.approx(V_hand, rel=1e-14)
    buoyancy_force(RHO * V, cob, g, zero, f)
    np.testing.assert_allclose(f, total, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(f[3:], -RHO * V_hand * g, rtol=1e-12)


# ------------------------------------------------------------------------------------------- added mass


def test_sphere_added_mass_is_half_the_displaced_mass_with_no_rotational_part():
    M = added_mass(Sphere(0.2), RHO)
    half = 0.5 * RHO * 4 / 3 * math.pi * 0.2**3
    np.testing.assert_array_equal(M, np.diag([0, 0, 0, half, half, half]))


def test_offset_sphere_gets_the_parallel_axis_coupling_derived_by_hand():
    """Sphere at p = (0, 0, h) (any orientation): its centre moves with v + omega x p, so
    T = m/2 |v + omega x p|^2 with m = rho V / 2: M[q,q] = M[p,p] = m h^2, M[r,r] = 0, and
    omega x p = (h q, -h p, 0) couples q with u (+m h) and p with v (-m h)."""
    h = 0.3
    m = 0.5 * RHO * 4 / 3 * math.pi * 0.1**3
    M = added_mass(Sphere(0.1, rotation=rotation_from_euler([0.3, -0.2, 1.0]), position=[0, 0, h]), RHO)
    expected = np.zeros((6, 6))
    expected[0, 0] = expected[1, 1] = m * h * h
    expected[3, 3] = expected[4, 4] = expected[5, 5] = m
    expected[1, 3] = expected[3, 1] = m * h
    expected[0, 4] = expected[4, 0] = -m * h
    np.testing.assert_allclose(M, expected, rtol=1e-12, atol=1e-15)


def test_transform_added_mass_preserves_kinetic_energy(rng):
    """0.5 nu_b^T M_b nu_b = 0.5 nu_s^T M6 nu_s with nu_s = [R^T w; R^T (v + w x p)] written out."""
    for _ in range(20):
        A = rng.normal(size=(6, 6))
        M6 = A @ A.T
        R = rotation_from_euler(rng.uniform(-3, 3, 3))
        p = rng.normal(size=3)
        Mb = transform_added_mass(M6, R, p)
        nu = rng.normal(size=6)
        w, v = nu[:3], nu[3:]
        nu_s = np.concatenate([R.T @ w, R.T @ (v + np.cross(w, p))])
        assert 0.5 * nu @ Mb @ nu == pytest.approx(0.5 * nu_s @ M6 @ nu_s, rel=1e-12)
        np.testing.assert_allclose(Mb, Mb.T, atol=1e-12)


# Lamb, "The inertia-coefficients of an ellipsoid moving in fluid", ARC R&M 623 (1918), table (reprinted in
# Lamb, Hydrodynamics, 1932): length/breadth ratio, k1 (end-on), k2 (broadside), k' (rotation).
LAMB_1918 = [
    (1.50, 0.305, 0.621, 0.094), (2.00, 0.209, 0.702, 0.240), (2.51, 0.156, 0.763, 0.367),
    (2.99, 0.122, 0.803, 0.465), (3.99, 0.082, 0.860, 0.608), (4.99, 0.059, 0.895, 0.701),
    (6.01, 0.045, 0.918, 0.764), (6.97, 0.036, 0.933, 0.805), (8.01, 0.029, 0.945, 0.840),
    (9.02, 0.024, 0.954, 0.865), (9.97, 0.021, 0.960, 0.883),
]


@pytest.mark.parametrize("ratio,k1,k2,kp", LAMB_1918)
def test_spheroid_coefficients_match_lambs_table(ratio, k1, k2, kp):
    """Lamb's hand-computed 1918 table (3 decimals) agrees with the exact values within 2.2e-3."""
    c1, c2, cp = lamb_k_factors(ratio, 1.0)
    assert c1 == pytest.approx(k1, abs=2.5e-3)
    assert c2 == pytest.approx(k2, abs=2.5e-3)
    assert cp == pytest.approx(kp, abs=2.5e-3)


@pytest.mark.parametrize("ratio", [1.2, 2.0, 5.0, 10.0, 30.0])
def test_elliptic_integrals_agree_with_lambs_closed_form_for_a_spheroid(ratio):
    k_lin, k_rot = ellipsoid_added_mass_coefficients(ratio, 1.0, 1.0)
    k1, k2, kp = lamb_k_factors(ratio, 1.0)
    np.testing.assert_allclose(k_lin, [k1, k2, k2], rtol=1e-11)
    np.testing.assert_allclose(k_rot, [0.0, kp, kp], rtol=1e-10, atol=1e-14)


def test_ellipsoid_integrals_sum_to_two_and_a_sphere_has_two_thirds(rng):
    """Lamb 1932: alpha0 + beta0 + gamma0 = 2; for a sphere each is 2/3 and k = 1/2."""
    np.testing.assert_allclose(ellipsoid_inertia_integrals(0.7, 0.7, 0.7), [2 / 3] * 3, rtol=1e-13)
    for _ in range(20):
        assert sum(ellipsoid_inertia_integrals(*rng.uniform(0.05, 2.0, 3))) == pytest.approx(2.0, rel=1e-12)
    k_lin, k_rot = ellipsoid_added_mass_coefficients(0.4, 0.4, 0.4)
    np.testing.assert_allclose(k_lin, 0.5, rtol=1e-13)
    np.testing.assert_array_equal(k_rot, 0.0)


def test_spheroid_added_mass_matrix_uses_k_factors_on_displaced_mass_and_fluid_inertia():
    a, b = 0.8, 0.095                                # Remus-like hull: L = 1.6 m, D = 0.19 m
    k1, k2, kp = lamb_k_factors(a, b)
    m = RHO * 4 / 3 * math.pi * a * b * b
    I_y = m * (a * a + b * b) / 5
    M = local_added_mass(spheroid(2 * a, 2 * b), RHO)
    np.testing.assert_allclose(M, np.diag([0.0, kp * I_y, kp * I_y, k1 * m, k2 * m, k2 * m]), rtol=1e-10)


def test_ellipsoid_rotational_coefficient_is_symmetric_in_the_two_other_axes():
    """Swapping b and c swaps the y and z coefficients and leaves the x ones (Lamb's rotational form is symmetric)."""
    k_lin1, k_rot1 = ellipsoid_added_mass_coefficients(0.5, 0.2, 0.3)
    k_lin2, k_rot2 = ellipsoid_added_mass_coefficients(0.5, 0.3, 0.2)
    np.testing.assert_allclose(k_lin1, k_lin2[[0, 2, 1]], rtol=1e-12)
    np.testing.assert_allclose(k_rot1, k_rot2[[0, 2, 1]], rtol=1e-12)
    assert np.all(k_rot1 > 0)


def test_cylinder_strip_added_mass_about_its_centre(rng):
    """rho pi r^2 per unit length: 0.5 nu^T M nu = 0.5 m' int_{-L/2}^{L/2} |v_n(s)|^2 ds (independent quad)."""
    r, L = 0.04, 0.5
    ma = RHO * math.pi * r * r
    M = local_added_mass(Cylinder(r, L, axial_added_mass="none"), RHO)
    np.testing.assert_allclose(np.diag(M), [0, ma * L**3 / 12, ma * L**3 / 12, 0, ma * L, ma * L], rtol=1e-12)
    assert np.abs(M - np.diag(np.diag(M))).max() < 1e-15
    for _ in range(10):
        nu = rng.normal(size=6)
        vn2 = lambda s: (nu[4] + nu[2] * s) ** 2 + (nu[5] - nu[1] * s) ** 2  # noqa: E731
        assert 0.5 * nu @ M @ nu == pytest.approx(0.5 * ma * quad(vn2, -L / 2, L / 2)[0], rel=1e-12)
    with_axial = local_added_mass(Cylinder(r, L), RHO)
    k1, _, _ = lamb_k_factors(L / 2, r)
    assert with_axial[3, 3] == pytest.approx(k1 * RHO * 4 / 3 * math.pi * (L / 2) * r * r, rel=1e-12)


def test_cylinder_along_y_is_the_x_cylinder_rotated(rng):
    """Pose (Q, Q p) with Q = Rz(90 deg) and velocity (Q w, Q v) gives the x-cylinder's force rotated by Q."""
    Q = rotz(math.pi / 2)
    p = np.array([0.1, -0.2, 0.05])
    a = Cylinder(0.03, 0.35, drag_coefficient=1.1, axial_drag_coefficient=0.8, position=p)
    b = Cylinder(0.03, 0.35, drag_coefficient=1.1, axial_drag_coefficient=0.8,
                 rotation=rotation_from_axis([0, 1, 0]), position=Q @ p)
    np.testing.assert_allclose(b.rotation, Q, atol=1e-15)
    np.testing.assert_allclose(added_mass(b, RHO), block(Q) @ added_mass(a, RHO) @ block(Q).T, atol=1e-14)
    for _ in range(10):
        nu = rng.normal(size=6)
        np.testing.assert_allclose(drag([b], block(Q) @ nu), block(Q) @ drag([a], nu), rtol=1e-12, atol=1e-12)


def test_several_shapes_add_up():
    shapes = [Sphere(0.1, 0.5, position=[0.2, 0, 0]), Box((0.3, 0.2, 0.1), (1, 1.1, 1.2), position=[0, 0.1, 0]),
              Cylinder(0.02, 0.3, 1.0, rotation=rotation_from_axis([0, 0, 1]), position=[0, 0, 0.2])]
    M = sum(added_mass(s, RHO) for s in shapes)
    np.testing.assert_allclose(total_added_mass(shapes, RHO), M, rtol=1e-15)
    nu = np.array([0.3, -0.2, 0.5, 0.4, -0.1, 0.2])
    np.testing.assert_allclose(drag(shapes, nu), sum(drag([s], nu) for s in shapes), rtol=1e-13)


# ------------------------------------------------------------------------------------------------- drag


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_cube_rotational_drag_is_the_papers_eq4(axis):
    a, Cd = 0.596, 1.0
    w = np.zeros(6)
    w[axis] = -1.7
    M = drag([Box((a, a, a), (Cd, Cd, Cd))], w)
    expected = -box_rotational_drag_coefficient(RHO, Cd, a) * w[axis] * abs(w[axis])
    assert M[axis] == pytest.approx(expected, rel=1e-13)
    assert M[axis] == pytest.approx(box_rotational_drag_by_strips(RHO, Cd, a, w[axis]), rel=1e-6)
    assert np.abs(np.delete(M, axis)).max() < 1e-12 * abs(expected)


def test_box_translational_drag_is_the_papers_eq3_per_axis():
    size = (0.5, 0.3, 0.2)
    cd = (0.9, 1.1, 1.3)
    areas = (0.3 * 0.2, 0.5 * 0.2, 0.5 * 0.3)
    v = np.array([0.7, -0.4, 0.25])
    F = drag([Box(size, cd)], np.concatenate([np.zeros(3), v]))
    np.testing.assert_allclose(F[3:], [-0.5 * RHO * cd[j] * areas[j] * v[j] * abs(v[j]) for j in range(3)],
                               rtol=1e-13)
    np.testing.assert_allclose(F[:3], 0.0, atol=1e-13)


def test_rectangle_integrals_are_exact_against_adaptive_quadrature(rng):
    for _ in range(15):
        c, al, be = rng.normal(size=3)
        u0, w0 = -rng.uniform(0.1, 1, 2)
        u1, w1 = rng.uniform(0.1, 1, 2)
        g = lambda w, u, k: (u if k == 1 else w if k == 2 else 1.0) * (c + al * u + be * w) * abs(  # noqa: E731
            c + al * u + be * w)
        got = rectangle_drag_integrals(c, al, be, u0, u1, w0, w1)
        for k in range(3):
            ref = dblquad(g, u0, u1, w0, w1, args=(k,), epsabs=1e-13, epsrel=1e-12)[0]
            assert got[k] == pytest.approx(ref, rel=1e-9, abs=1e-12)


def test_posed_box_drag_matches_face_integrals_in_body_axes(rng):
    """Each projected face's dF = -k_j v_n |v_n| n dA, dM = r x dF, integrated in body coordinates by dblquad."""
    size = np.array([0.4, 0.25, 0.15])
    cd = np.array([0.8, 1.0, 1.2])
    R = rotation_from_euler([0.4, -0.3, 0.9])
    p = np.array([0.2, -0.1, 0.3])
    box = Box(size, cd, rotation=R, position=p)
    nu = rng.normal(size=6)
    w, v = nu[:3], nu[3:]
    ref = np.zeros(6)
    for j in range(3):
        k, l = (j + 1) % 3, (j + 2) % 3
        n, ek, el = R[:, j], R[:, k], R[:, l]

        def dF(y, x, comp):
            r = p + x * ek + y * el
            vn = (v + np.cross(w, r)) @ n
            f = -0.5 * RHO * cd[j] * vn * abs(vn) * n
            return np.concatenate([np.cross(r, f), f])[comp]

        for comp in range(6):
            ref[comp] += dblquad(dF, -size[k] / 2, size[k] / 2, -size[l] / 2, size[l] / 2, args=(comp,),
                                 epsabs=1e-12, epsrel=1e-11)[0]
    np.testing.assert_allclose(drag([box], nu), ref, rtol=1e-8, atol=1e-10)


def _strip_reference(p, e, L, k_of_s, nu, axial_k=0.0, width_is_elliptic=None):
    """Cross-flow drag of strips along the unit axis e through p, s in [-L/2, L/2], in body coordinates."""
    w, v = nu[:3], nu[3:]

    def dF(s, comp):
        r = p + s * e
        vel = v + np.cross(w, r)
        vn = vel - (vel @ e) * e
        f = -k_of_s(s) * np.linalg.norm(vn) * vn
        return np.concatenate([np.cross(r, f), f])[comp]

    # the kink of |v_n| (where it is smallest) as an extra break point for quad
    a0 = (v + np.cross(w, p))
    a0 = a0 - (a0 @ e) * e
    b0 = np.cross(w, e)
    b0 = b0 - (b0 @ e) * e
    s_min = -(a0 @ b0) / (b0 @ b0) if b0 @ b0 > 0 else 0.0
    pts = [s_min] if -L / 2 < s_min < L / 2 else None
    ref = np.array([quad(dF, -L / 2, L / 2, args=(c,), points=pts, epsabs=1e-13, epsrel=1e-12, limit=200)[0]
                    for c in range(6)])
    u = (v + np.cross(w, p)) @ e
    fa = -axial_k * u * abs(u) * e
    ref += np.concatenate([np.cross(p, fa), fa])
    return ref


def test_posed_cylinder_drag_matches_strip_quadrature(rng):
    """Eq. 6 in any pose plus the axial term, against adaptive quadrature in body coordinates (the link
    drag's 8-point Gauss rule on each side of the kink is within 1e-4, ``docs/conventions.md`` decision 3)."""
    r, L, cd, cda = 0.03, 0.45, 1.1, 0.9
    for _ in range(10):
        R = rotation_from_euler(rng.uniform(-3, 3, 3))
        p = rng.normal(scale=0.3, size=3)
        cyl = Cylinder(r, L, cd, cda, rotation=R, position=p)
        nu = rng.normal(size=6)
        ref = _strip_reference(p, R[:, 0], L, lambda s: 0.5 * RHO * cd * 2 * r, nu,
                               axial_k=0.5 * RHO * cda * math.pi * r * r)
        got = drag([cyl], nu)
        assert np.abs(got - ref).max() <= 1e-4 * np.abs(ref).max()


def test_posed_spheroid_drag_matches_strip_quadrature(rng):
    a, b, cd, cda = 0.4, 0.08, 1.0, 0.2
    for _ in range(10):
        R = rotation_from_euler(rng.uniform(-3, 3, 3))
        p = rng.normal(scale=0.3, size=3)
        body = Ellipsoid((a, b, b), cd, cda, rotation=R, position=p)
        nu = rng.normal(size=6)
        ref = _strip_reference(p, R[:, 0], 2 * a, lambda s: 0.5 * RHO * cd * 2 * b * math.sqrt(1 - (s / a) ** 2),
                               nu, axial_k=0.5 * RHO * cda * math.pi * b * b)
        got = drag([body], nu)
        assert np.abs(got - ref).max() <= 1e-4 * np.abs(ref).max()


def test_ellipsoid_crossflow_width_depends_on_the_flow_direction():
    """Flow along y sees the height 2c of each section, flow along z the width 2b: F = -k v|v| pi a c (or b)."""
    a, b, c, cd = 0.5, 0.1, 0.2, 1.0
    body = Ellipsoid((a, b, c), cd)
    Fy = drag([body], [0, 0, 0, 0, 0.6, 0])[4]
    Fz = drag([body], [0, 0, 0, 0, 0, 0.6])[5]
    # int_{-a}^{a} 2 c sqrt(1 - s^2/a^2) ds = pi a c (the ellipse's area in the x-z plane)
    assert Fy == pytest.approx(-0.5 * RHO * cd * math.pi * a * c * 0.36, rel=1e-6)
    assert Fz == pytest.approx(-0.5 * RHO * cd * math.pi * a * b * 0.36, rel=1e-6)


def test_sphere_drag_acts_at_its_centre():
    p = np.array([0.1, 0.2, -0.3])
    nu = np.array([0.2, -0.1, 0.4, 0.5, 0.1, -0.2])
    vc = nu[3:] + np.cross(nu[:3], p)
    F = -0.5 * RHO * 0.47 * math.pi * 0.15**2 * np.linalg.norm(vc) * vc
    np.testing.assert_allclose(drag([Sphere(0.15, 0.47, position=p)], nu), np.concatenate([np.cross(p, F), F]),
                               rtol=1e-13)


def test_drag_never_does_positive_work(rng):
    shapes = [Sphere(0.1, 0.5, position=[0.2, 0, 0]),
              Box((0.3, 0.2, 0.1), (1, 1.1, 1.2), rotation=rotation_from_euler([0.1, 0.2, 0.3])),
              Cylinder(0.02, 0.3, 1.0, 0.8, rotation=rotation_from_axis([1, 1, 0]), position=[0, 0, 0.2]),
              spheroid(0.6, 0.1, drag_coefficient=0.9, axial_drag_coefficient=0.1, position=[-0.2, 0, 0])]
    table = drag_table(shapes, RHO)
    out = np.zeros(6)
    work = drag_workspace()
    for _ in range(200):
        nu = rng.normal(size=6) * rng.uniform(0.01, 3)
        shapes_drag_force(table, nu, out, work)
        assert out @ nu <= 0.0


def test_shapes_refuse_bad_geometry():
    with pytest.raises(ValueError, match="radius"):
        Sphere(-0.1)
    with pytest.raises(ValueError, match="rotation"):
        Box((1, 1, 1), rotation=np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(ValueError, match="size"):
        Box((1, 0, 1))
    with pytest.raises(ValueError, match="axial_added_mass"):
        Cylinder(0.1, 1.0, axial_added_mass="slender")
    with pytest.raises(ValueError):
        rotation_from_axis([0, 0, 0])


def test_rotation_from_axis_is_a_rotation_with_the_axis_first(rng):
    for _ in range(10):
        e = rng.normal(size=3)
        R = rotation_from_axis(e)
        np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-14)
        assert np.linalg.det(R) == pytest.approx(1.0)
        np.testing.assert_allclose(R[:, 0], e / np.linalg.norm(e), atol=1e-14)
    np.testing.assert_allclose(rotation_from_axis([2, 0, 0]), np.eye(3), atol=1e-15)
    np.testing.assert_allclose(rotation_from_axis([0, 1, 0]), rotz(math.pi / 2), atol=1e-15)
    np.testing.assert_allclose(rotation_from_axis([0, 0, 1]), roty(-math.pi / 2), atol=1e-15)
