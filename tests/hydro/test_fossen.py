"""Fossen's damping form: SNAME names, the force against the formula written out, dissipation, bad input."""

from __future__ import annotations

import numpy as np
import pytest

from uvms.errors import UvmsInputError
from uvms.hydro.fossen import damping_matrices, diagonal_damping, fossen_damping_force, sname_index

# A BlueROV2-like set in SNAME (derivative) signs, Fossen's order u v w p q r.
LINEAR = {"X_u": -4.03, "Y_v": -6.22, "Z_w": -5.18, "K_p": -0.07, "M_q": -0.07, "N_r": -0.07}
QUADRATIC = {"X_u|u|": -18.18, "Y_v|v|": -21.66, "Z_w|w|": -36.99, "K_p|p|": -1.55, "M_q|q|": -1.55,
             "N_r|r|": -1.55}


def force(D_l, D_q, point, nu):
    out = np.zeros(6)
    fossen_damping_force(D_l, D_q, np.asarray(point, float), np.asarray(nu, float), out)
    return out


@pytest.mark.parametrize("name,expected", [
    ("K_p", ("linear", 0, 0)), ("M_q", ("linear", 1, 1)), ("N_r", ("linear", 2, 2)),
    ("X_u", ("linear", 3, 3)), ("Y_v", ("linear", 4, 4)), ("Z_w", ("linear", 5, 5)),
    ("Y_r", ("linear", 4, 2)), ("N_v", ("linear", 2, 4)), ("Xu", ("linear", 3, 3)),
    ("X_u|u|", ("quadratic", 3, 3)), ("X_|u|u", ("quadratic", 3, 3)), ("N_r|r|", ("quadratic", 2, 2)),
    ("M_w|w|", ("quadratic", 1, 5)),
])
def test_sname_names_map_to_angular_first_indices(name, expected):
    assert sname_index(name) == expected


def test_diagonal_force_equals_fossens_formula_written_out(rng):
    """tau = -(D_l + D_n |nu|) nu with D_l = -diag(X_u, Y_v, Z_w, K_p, M_q, N_r), Fossen's order, by hand."""
    D_l, D_q = damping_matrices({**LINEAR, **QUADRATIC})
    for _ in range(20):
        u, v, w, p, q, r = rng.normal(size=6)
        X = LINEAR["X_u"] * u + QUADRATIC["X_u|u|"] * u * abs(u)
        Y = LINEAR["Y_v"] * v + QUADRATIC["Y_v|v|"] * v * abs(v)
        Z = LINEAR["Z_w"] * w + QUADRATIC["Z_w|w|"] * w * abs(w)
        K = LINEAR["K_p"] * p + QUADRATIC["K_p|p|"] * p * abs(p)
        M = LINEAR["M_q"] * q + QUADRATIC["M_q|q|"] * q * abs(q)
        N = LINEAR["N_r"] * r + QUADRATIC["N_r|r|"] * r * abs(r)
        np.testing.assert_allclose(force(D_l, D_q, np.zeros(3), [p, q, r, u, v, w]), [K, M, N, X, Y, Z],
                                   rtol=1e-14, atol=1e-15)


def test_coupling_terms_and_the_magnitude_convention(rng):
    """Off-diagonal names land where written (N_v: yaw moment from sway); 'magnitude' reads the entry itself."""
    D_l, D_q = damping_matrices({"N_v": -2.0, "Y_r": -3.0, "M_w|w|": -5.0})
    u, v, w, p, q, r = rng.normal(size=6)
    f = force(D_l, D_q, np.zeros(3), [p, q, r, u, v, w])
    np.testing.assert_allclose(f, [0.0, -5.0 * w * abs(w), -2.0 * v, 0.0, -3.0 * r, 0.0], rtol=1e-14)
    D_l2, D_q2 = damping_matrices({"N_v": 2.0, "Y_r": 3.0, "M_w|w|": 5.0}, convention="magnitude")
    np.testing.assert_array_equal(D_l2, D_l)
    np.testing.assert_array_equal(D_q2, D_q)
    assert D_l[2, 4] == 2.0 and D_q[1, 5] == 5.0
    Dl, Dq = diagonal_damping([1, 2, 3, 4, 5, 6], None)
    np.testing.assert_array_equal(Dl, np.diag([1.0, 2, 3, 4, 5, 6]))
    np.testing.assert_array_equal(Dq, 0.0)


def test_coefficients_about_a_point_are_moved_to_the_origin_by_hand():
    """Coefficients identified about c = (0.1, 0, 0.2): the point moves with v + omega x c; the force there
    F = -(d_l + d_q |v_c|) v_c (per axis) acts at c, so the origin sees the extra moment c x F."""
    c = np.array([0.1, 0.0, 0.2])
    D_l, D_q = damping_matrices({**LINEAR, **QUADRATIC})
    nu = np.array([0.3, -0.5, 0.8, 0.6, -0.2, 0.1])
    w, v = nu[:3], nu[3:]
    vc = np.array([v[0] + w[1] * c[2] - w[2] * c[1], v[1] + w[2] * c[0] - w[0] * c[2],
                   v[2] + w[0] * c[1] - w[1] * c[0]])
    lin = [LINEAR["X_u"], LINEAR["Y_v"], LINEAR["Z_w"]]
    quad = [QUADRATIC["X_u|u|"], QUADRATIC["Y_v|v|"], QUADRATIC["Z_w|w|"]]
    F = np.array([lin[i] * vc[i] + quad[i] * vc[i] * abs(vc[i]) for i in range(3)])
    rot = [LINEAR["K_p"], LINEAR["M_q"], LINEAR["N_r"]]
    rq = [QUADRATIC["K_p|p|"], QUADRATIC["M_q|q|"], QUADRATIC["N_r|r|"]]
    Mc = np.array([rot[i] * w[i] + rq[i] * w[i] * abs(w[i]) for i in range(3)])
    expected = np.concatenate([Mc + np.cross(c, F), F])
    np.testing.assert_allclose(force(D_l, D_q, c, nu), expected, rtol=1e-14, atol=1e-15)


def test_damping_only_removes_energy(rng):
    """Symmetric PSD D_l and non-negative diagonal D_q: the power f . nu is never positive (any point)."""
    for _ in range(200):
        A = rng.normal(size=(6, 6))
        D_l = A @ A.T * rng.uniform(0, 5)
        D_q = np.diag(rng.uniform(0, 30, 6))
        point = rng.normal(scale=0.3, size=3)
        nu = rng.normal(size=6) * rng.uniform(0.01, 3)
        assert force(D_l, D_q, point, nu) @ nu <= 1e-12 * (1 + np.abs(nu).max() ** 3)


@pytest.mark.parametrize("coefficients,field,message", [
    ({"X_q": 1.0, "Q_u": 1.0}, "Q_u", "not a SNAME"),
    ({"Y_|v|r": -1.0}, "Y_|v|r", "mixed"),
    ({"X_u": "fast"}, "X_u", "expected a number"),
    ({"X_u": float("nan")}, "X_u", "finite"),
    ({"X_u|u|": -1.0, "X_|u|u": -2.0}, "X_|u|u", "same coefficient"),
])
def test_bad_coefficients_are_one_line_input_errors(coefficients, field, message):
    with pytest.raises(UvmsInputError) as info:
        damping_matrices(coefficients, source="rov.yaml")
    text = str(info.value)
    assert "\n" not in text and text.startswith(f"rov.yaml: {field}: ") and message in text


def test_unknown_convention_is_refused():
    with pytest.raises(UvmsInputError, match="convention"):
        damping_matrices(LINEAR, convention="positive")
