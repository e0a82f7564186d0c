"""Healey et al. (1995) thruster: DC motor, blade lift and drag at 0.7 R, axial duct flow (paper Eqs. 9-10).

States: propeller speed ``Omega`` [rad/s] and axial inflow ``U`` [m/s]; input: armature voltage ``V`` [V];
output: thrust ``T`` [N] along the thruster axis and shaft torque ``Q`` [N m]::

    motor   J dOmega/dt = Kt i - Kf Omega - Q,               i = (V - Ke Omega) / Ra
    duct    rho A L_d gamma dU/dt + rho A dbeta |U| U = T,    A = pi R^2
    blade   x = 0.7 R Omega,   V_p^2 = U^2 + x^2,   theta = atan2(U, x),   alpha = p - theta
            L = 0.5 rho V_p^2 A CLmax sin(2 alpha)
            D = 0.5 rho V_p^2 A CDmax (1 - cos(2 alpha))
            T = L cos(theta) - D sin(theta)
            Q = 0.7 R (L sin(theta) + D cos(theta))

Four quadrants. ``theta`` is the full-circle ``atan2`` angle of the flow seen by the blade section, so
every sign combination of ``Omega`` and ``U`` is covered by the same formulas and no case split is
needed. Reversing both velocities turns ``theta`` into ``theta +/- pi``; the sinusoidal lift and drag
curves have period ``pi`` in ``alpha`` (``sin 2 alpha``, ``cos 2 alpha``), so ``L`` and ``D`` are unchanged while
``cos(theta)`` and ``sin(theta)`` change sign: ``T(-Omega, -U) = -T(Omega, U)`` and
``Q(-Omega, -U) = -Q(Omega, U)`` exactly (up to the rounding of ``atan2``). The motor and duct
equations are odd as well, so the whole model is odd in ``V`` and the formulas are used **as written**:
the blade "sees the flow relative to its rotation direction" automatically through ``atan2``. Checks of
the other quadrants: bollard reverse (``Omega < 0, U = 0``) gives ``theta = pi``, ``T = -L`` and a torque
opposing the rotation; a locked rotor in positive inflow (``Omega = 0, U > 0``) gives ``theta = pi/2``,
``T = -D`` (the blades brake the duct flow) and a torque that windmills the rotor forward.

Steady state (closed form). With ``dU/dt = 0`` both sides of the duct balance scale with ``V_p^2``, so the
flow angle at equilibrium is a constant ``theta*`` (root of ``0.5 f(theta) = dbeta sin^2 theta`` with
``f = CLmax sin 2a cos(theta) - CDmax (1 - cos 2a) sin(theta)``, ``a = p - theta``), independent of the speed. Hence
``U = 0.7 R tan(theta*) Omega``, ``T = k_T Omega |Omega|``, ``Q = k_Q Omega |Omega|`` and the motor balance
``V = (Ke + Ra Kf / Kt) Omega + (Ra k_Q / Kt) Omega |Omega|`` is a quadratic in ``Omega``. Both directions
(voltage -> thrust, thrust -> inflow -> speed -> voltage) are explicit.

Default parameters (``docs/conventions.md``; the paper gives none) give 51.80 N at 24 V, 16.03 N at 12 V
and a 63 % thrust rise time of 31.3 ms after a 24 V step from rest. Near zero thrust the response is
slower: the slow (duct) pole goes to zero with the speed, so a 1 V step rises in 33.5 ms, overshoots by 65 %
and settles in about 250 ms (time constant). The largest stable explicit RK4 step is 30.1 ms, set by the full-thrust
equilibrium (:data:`RK4_STABILITY_LIMIT`); use at most :data:`RECOMMENDED_MAX_STEP` = 10 ms. See
``docs/thrusters.md``.

The compiled kernels take the flat parameter array of :meth:`HealeyParameters.as_array` (order given by
the ``P_*`` index constants) and are scalar code without allocation, meant to be called inside a compiled
integration loop.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, fields

import numpy as np
from numba import njit

# Index of each parameter in the flat array passed to the kernels.
P_RADIUS, P_PITCH, P_LIFT, P_DRAG, P_DUCT_LENGTH, P_GAMMA, P_DBETA = 0, 1, 2, 3, 4, 5, 6
P_KT, P_KE, P_RESISTANCE, P_FRICTION, P_INERTIA, P_VMAX, P_DENSITY = 7, 8, 9, 10, 11, 12, 13
N_PARAMETERS = 14

RK4_STABILITY_LIMIT = 0.0301
"""Largest stable explicit RK4 step [s] for the Healey states of the default thruster. The fastest pole
(-92.5 1/s, with -31.7 1/s) is at the full-thrust equilibrium (+/-24 V); the poles shrink towards zero
thrust, and no state reached with |V| <= 24 V (random bang-bang sequences, reversals) has faster ones.
Fixed-step RK4 converges at 29 ms and does not at 30.5 ms. States that voltage alone cannot reach
(|Omega| = 330 rad/s against a 2.7 m/s inflow) would need 19.8 ms."""

RECOMMENDED_MAX_STEP = 0.01
"""Integration step [s] recommended for the Healey states with RK4: a third of the stability limit; the
thrust of a 24 V step response from rest is then within 0.06 % of full scale (``docs/thrusters.md``)."""


@dataclass(frozen=True)
class HealeyParameters:
    """Parameters of one Healey thruster (SI units; defaults from ``docs/conventions.md``).

    Attributes:
        radius: propeller radius ``R`` [m].
        pitch: blade pitch angle ``p`` at 0.7 R [rad].
        lift_max: maximum lift coefficient ``CLmax`` [-].
        drag_max: maximum drag coefficient ``CDmax`` [-].
        duct_length: duct length ``L_d`` [m].
        gamma: effective added-mass ratio of the duct fluid ``gamma`` [-].
        delta_beta: momentum-flux coefficient ``dbeta`` [-].
        torque_constant: motor torque constant ``Kt`` [N m/A].
        back_emf_constant: back-EMF constant ``Ke`` [V s/rad].
        resistance: armature resistance ``Ra`` [ohm].
        friction: viscous friction ``Kf`` [N m s].
        inertia: rotor and propeller inertia ``J`` [kg m^2].
        max_voltage: supply limit ``Vmax`` [V].
        density: water density ``rho`` [kg/m^3].
    """

    radius: float = 0.05
    pitch: float = math.radians(24.4)
    lift_max: float = 0.30
    drag_max: float = 0.50
    duct_length: float = 0.10
    gamma: float = 1.0
    delta_beta: float = 1.0
    torque_constant: float = 0.0588
    back_emf_constant: float = 0.0588
    resistance: float = 0.29
    friction: float = 2e-5
    inertia: float = 5e-4
    max_voltage: float = 24.0
    density: float = 1000.0

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if not math.isfinite(value):
                raise ValueError(f"HealeyParameters.{f.name} must be finite, got {value}")
            if f.name != "friction" and value <= 0.0:
                raise ValueError(f"HealeyParameters.{f.name} must be positive, got {value}")
        if self.friction < 0.0:
            raise ValueError(f"HealeyParameters.friction must be non-negative, got {self.friction}")
        if self.pitch >= math.pi / 2:
            raise ValueError(f"HealeyParameters.pitch must be below pi/2, got {self.pitch}")

    def as_array(self) -> np.ndarray:
        """(N_PARAMETERS,) flat array for the kernels, in the order of the ``P_*`` constants."""
        return np.array([getattr(self, f.name) for f in fields(self)], dtype=np.float64)

    @property
    def disk_area(self) -> float:
        """``A = pi R^2`` [m^2]."""
        return math.pi * self.radius**2

    @property
    def max_thrust(self) -> float:
        """Steady thrust at ``+Vmax`` [N] (the thrust limit used for allocation)."""
        return steady_state(self, self.max_voltage)[2]


@njit(cache=True)
def healey_thrust_torque(p: np.ndarray, Omega: float, U: float) -> tuple[float, float]:
    """Thrust ``T`` [N] and shaft torque ``Q`` [N m] at speed ``Omega`` [rad/s] and inflow ``U`` [m/s]."""
    R = p[P_RADIUS]
    rho = p[P_DENSITY]
    A = math.pi * R * R
    x = 0.7 * R * Omega
    Vp2 = U * U + x * x
    theta = math.atan2(U, x)
    alpha = p[P_PITCH] - theta
    L = 0.5 * rho * Vp2 * A * p[P_LIFT] * math.sin(2.0 * alpha)
    D = 0.5 * rho * Vp2 * A * p[P_DRAG] * (1.0 - math.cos(2.0 * alpha))
    c = math.cos(theta)
    s = math.sin(theta)
    T = L * c - D * s
    Q = 0.7 * R * (L * s + D * c)
    return T, Q


@njit(cache=True)
def healey_derivatives(p: np.ndarray, Omega: float, U: float, V: float) -> tuple[float, float]:
    """State derivatives ``(dOmega/dt [rad/s^2], dU/dt [m/s^2])`` at voltage ``V`` [V] (applied as given)."""
    T, Q = healey_thrust_torque(p, Omega, U)
    R = p[P_RADIUS]
    rho = p[P_DENSITY]
    A = math.pi * R * R
    i = (V - p[P_KE] * Omega) / p[P_RESISTANCE]
    dOmega = (p[P_KT] * i - p[P_FRICTION] * Omega - Q) / p[P_INERTIA]
    dU = (T - rho * A * p[P_DBETA] * abs(U) * U) / (rho * A * p[P_DUCT_LENGTH] * p[P_GAMMA])
    return dOmega, dU


@njit(cache=True)
def healey_bank_derivatives(params: np.ndarray, Omega: np.ndarray, U: np.ndarray, V: np.ndarray,
                            dOmega_out: np.ndarray, dU_out: np.ndarray, thrust_out: np.ndarray) -> None:
    """Derivatives and thrusts of ``m`` thrusters at once, written into the ``*_out`` (m,) arrays.

    ``params`` (m, N_PARAMETERS) stacks each thruster's :meth:`HealeyParameters.as_array`; ``Omega``, ``U``
    and ``V`` are (m,). No allocation: meant for the compiled integration loop.
    """
    for h in range(Omega.shape[0]):
        p = params[h]
        dOmega_out[h], dU_out[h] = healey_derivatives(p, Omega[h], U[h], V[h])
        thrust_out[h] = healey_thrust_torque(p, Omega[h], U[h])[0]


@njit(cache=True)
def healey_rk4_step(p: np.ndarray, Omega: float, U: float, V: float, h: float) -> tuple[float, float]:
    """One classical RK4 step of length ``h`` [s] at constant voltage ``V``; returns ``(Omega, U)``."""
    k1w, k1u = healey_derivatives(p, Omega, U, V)
    k2w, k2u = healey_derivatives(p, Omega + 0.5 * h * k1w, U + 0.5 * h * k1u, V)
    k3w, k3u = healey_derivatives(p, Omega + 0.5 * h * k2w, U + 0.5 * h * k2u, V)
    k4w, k4u = healey_derivatives(p, Omega + h * k3w, U + h * k3u, V)
    Omega_next = Omega + h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w)
    U_next = U + h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u)
    return Omega_next, U_next


@njit(cache=True)
def _simulate(p: np.ndarray, Omega0: float, U0: float, V: float, n_samples: int, dt: float, substeps: int,
              out: np.ndarray) -> None:
    """Fill ``out`` (n_samples, 3) with ``[Omega, U, T]`` every ``dt``, RK4 with ``substeps`` steps per sample."""
    Omega = Omega0
    U = U0
    h = dt / substeps
    for k in range(n_samples):
        if k > 0:
            for _ in range(substeps):
                Omega, U = healey_rk4_step(p, Omega, U, V, h)
        T, _Q = healey_thrust_torque(p, Omega, U)
        out[k, 0] = Omega
        out[k, 1] = U
        out[k, 2] = T


@njit(cache=True)
def healey_voltage_for_thrust(p: np.ndarray, coefficients: np.ndarray, T: float) -> float:
    """Steady-state voltage [V] for thrust ``T`` [N], clipped to ``+/-Vmax`` (compiled).

    ``coefficients`` is :func:`steady_coefficients` ``(params)``: ``[k_T, k_Q, U/Omega]``.
    """
    Omega = math.copysign(math.sqrt(abs(T) / coefficients[0]), T)
    V = ((p[P_KE] + p[P_RESISTANCE] * p[P_FRICTION] / p[P_KT]) * Omega
         + p[P_RESISTANCE] * coefficients[1] / p[P_KT] * Omega * abs(Omega))
    vmax = p[P_VMAX]
    return min(max(V, -vmax), vmax)


def _steady_flow_angle(params: HealeyParameters) -> float:
    """``theta*`` in (0, p): root of ``0.5 f(theta) - dbeta sin^2(theta)`` by bisection (machine precision)."""
    p, CL, CD, db = params.pitch, params.lift_max, params.drag_max, params.delta_beta

    def g(theta: float) -> float:
        a = p - theta
        f = CL * math.sin(2 * a) * math.cos(theta) - CD * (1 - math.cos(2 * a)) * math.sin(theta)
        return 0.5 * f - db * math.sin(theta) ** 2

    lo, hi = 0.0, p  # g(0) = 0.5 CL sin 2p > 0, g(p) = -dbeta sin^2 p < 0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if g(mid) > 0.0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@functools.lru_cache(maxsize=64)
def _steady_coefficients(params: HealeyParameters) -> tuple[float, float, float]:
    inflow_per_speed = 0.7 * params.radius * math.tan(_steady_flow_angle(params))
    k_T, k_Q = healey_thrust_torque(params.as_array(), 1.0, inflow_per_speed)
    return k_T, k_Q, inflow_per_speed


def steady_coefficients(params: HealeyParameters) -> np.ndarray:
    """``[k_T, k_Q, U/Omega]`` of the steady state: ``T = k_T Omega|Omega|``, ``Q = k_Q Omega|Omega|``.

    Units: N s^2, N m s^2, m/rad. Cached per parameter set (the parameters are frozen).
    """
    return np.array(_steady_coefficients(params))


def steady_state(params: HealeyParameters, V: float) -> tuple[float, float, float]:
    """Equilibrium ``(Omega [rad/s], U [m/s], T [N])`` at constant voltage ``V`` [V] (not clipped).

    Solves ``a Omega|Omega| + b Omega = V`` with ``a = Ra k_Q / Kt``, ``b = Ke + Ra Kf / Kt`` in the
    cancellation-free form ``Omega = 2 V / (b + sqrt(b^2 + 4 a |V|))``.
    """
    k_T, k_Q, inflow_per_speed = steady_coefficients(params)
    a = params.resistance * k_Q / params.torque_constant
    b = params.back_emf_constant + params.resistance * params.friction / params.torque_constant
    V = float(V)
    Omega = 2.0 * V / (b + math.sqrt(b * b + 4.0 * a * abs(V)))
    return Omega, inflow_per_speed * Omega, k_T * Omega * abs(Omega)


def voltage_for_thrust(params: HealeyParameters, T: float | np.ndarray) -> float | np.ndarray:
    """Steady-state voltage [V] giving thrust ``T`` [N], clipped to ``+/-Vmax``.

    Thrust -> inflow ``U = sign(T) sqrt(|T| / (rho A dbeta))`` -> speed ``Omega = U / (0.7 R tan theta*)`` ->
    voltage from the motor balance (``docs/conventions.md``). Accepts a scalar or an array.
    """
    p = params.as_array()
    c = steady_coefficients(params)
    if np.ndim(T) == 0:
        return healey_voltage_for_thrust(p, c, float(T))
    T = np.asarray(T, dtype=float)
    return np.array([healey_voltage_for_thrust(p, c, t) for t in T.ravel()]).reshape(T.shape)


@dataclass(frozen=True, eq=False)
class StepResponse:
    """Response to a voltage step, sampled every ``dt``.

    Attributes:
        voltage: applied voltage [V].
        time: (n,) sample times [s], from 0.
        omega: (n,) propeller speed [rad/s].
        inflow: (n,) axial inflow [m/s].
        thrust: (n,) thrust [N].
    """

    voltage: float
    time: np.ndarray
    omega: np.ndarray
    inflow: np.ndarray
    thrust: np.ndarray


def step_response(params: HealeyParameters, V: float, duration: float, dt: float, *,
                  initial_omega: float = 0.0, initial_inflow: float = 0.0,
                  max_substep: float = 1e-4) -> StepResponse:
    """Response to a voltage step ``V`` [V] applied at t = 0 from ``(initial_omega, initial_inflow)``.

    Integrated by compiled RK4 with sub-steps no longer than ``max_substep`` [s] (well inside the stability
    limit; the error at 1e-4 s is far below plotting resolution), sampled every ``dt`` [s] for ``duration`` [s].
    """
    if duration <= 0 or dt <= 0 or max_substep <= 0:
        raise ValueError("duration, dt and max_substep must be positive")
    n_samples = round(duration / dt) + 1
    substeps = max(1, math.ceil(dt / max_substep - 1e-9))
    out = np.empty((n_samples, 3))
    _simulate(params.as_array(), float(initial_omega), float(initial_inflow), float(V), n_samples, float(dt),
              substeps, out)
    return StepResponse(float(V), np.arange(n_samples) * dt, out[:, 0].copy(), out[:, 1].copy(),
                        out[:, 2].copy())


def rise_time(time: np.ndarray, signal: np.ndarray, fraction: float = 1.0 - math.exp(-1.0),
              final: float | None = None) -> float:
    """First time [s] at which ``signal`` reaches ``fraction`` of its change to ``final`` (default: last sample).

    Linear interpolation between samples; ``nan`` if the level is never reached or there is no change.
    """
    time, signal = np.asarray(time, dtype=float), np.asarray(signal, dtype=float)
    start = signal[0]
    change = (signal[-1] if final is None else final) - start
    if change == 0.0:
        return math.nan
    progress = (signal - start) / change
    above = np.nonzero(progress >= fraction)[0]
    if above.size == 0:
        return math.nan
    k = above[0]
    if k == 0:
        return float(time[0])
    t0, t1, s0, s1 = time[k - 1], time[k], progress[k - 1], progress[k]
    return float(t0 + (fraction - s0) / (s1 - s0) * (t1 - t0))


def linearised_eigenvalues(params: HealeyParameters, Omega: float, U: float, V: float = 0.0,
                           relative_step: float = 1e-6) -> np.ndarray:
    """(2,) eigenvalues [1/s] of the central-difference Jacobian of ``(dOmega, dU)`` at ``(Omega, U, V)``."""
    p = params.as_array()
    x = np.array([Omega, U], dtype=float)
    jacobian = np.empty((2, 2))
    for k in range(2):
        h = relative_step * max(1.0, abs(x[k]))
        xp, xm = x.copy(), x.copy()
        xp[k] += h
        xm[k] -= h
        jacobian[:, k] = (np.array(healey_derivatives(p, xp[0], xp[1], V))
                          - np.array(healey_derivatives(p, xm[0], xm[1], V))) / (2 * h)
    return np.linalg.eigvals(jacobian)


def rk4_stable_step(eigenvalues: np.ndarray) -> float:
    """Largest ``h`` [s] with ``|R(h lambda)| <= 1`` on ``[0, h]`` for every eigenvalue with negative real part.

    ``R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24`` is the RK4 amplification factor. Each ray ``h lambda`` is scanned
    for its first exit from the stability region (which lies within ``|z| < 3``), then refined by bisection.
    Eigenvalues with non-negative real part do not bound the step and are skipped.
    """
    def amplification(z: complex) -> float:
        return abs(1 + z + z * z / 2 + z**3 / 6 + z**4 / 24)

    limit = math.inf
    for lam in np.asarray(eigenvalues, dtype=complex).ravel():
        if not lam.real < 0.0:
            continue
        grid = np.linspace(0.0, 3.0 / abs(lam), 3001)[1:]
        outside = np.nonzero(np.abs(1 + grid * lam + (grid * lam) ** 2 / 2 + (grid * lam) ** 3 / 6
                                    + (grid * lam) ** 4 / 24) > 1.0)[0]
        if outside.size == 0:
            continue
        k = outside[0]
        lo, hi = (grid[k - 1] if k > 0 else 0.0), grid[k]
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            if amplification(mid * lam) <= 1.0:
                lo = mid
            else:
                hi = mid
        limit = min(limit, lo)
    return limit
