"""The bundled controllers' laws as they were written in Python before they were compiled (issue 14): the
independent reference the compiled kernels (:mod:`uvms.control.kernels`, :mod:`uvms.control.arm`) are checked
against, update by update, on recorded states.

Written out with numpy from the equations (paper Eqs. 24-30 as corrected in ``docs/conventions.md``; the
controllers' module docstrings), with the controller models' accelerations from the public Python API
(:func:`uvms.forward_dynamics`, :func:`uvms.dynamics.api.inverse_dynamics`, :func:`uvms.dynamics.api.mass_matrix`),
not from the kernels under test. ``b_source = "model"`` takes ``(I^-1)_jj`` from the response of the model's
``nu_dot`` to a unit body wrench on axis ``j`` (forward dynamics are affine in the wrench), not from the
articulated inertia the kernel reads.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from uvms.dynamics.api import forward_dynamics, inverse_dynamics, mass_matrix
from uvms.state import State

AXES = ("surge", "sway", "heave", "roll", "pitch", "yaw")
INDEX = {"surge": 3, "sway": 4, "heave": 5, "roll": 0, "pitch": 1, "yaw": 2}
"""Where each axis sits in ``nu``, ``nu_dot`` and the wrench ``[K M N X Y Z]``."""


def wrap(angle: float) -> float:
    return -((-angle + math.pi) % (2.0 * math.pi) - math.pi)


def kinematics(state: State, desired: np.ndarray) -> dict[str, np.ndarray]:
    """Per axis (dicts keyed by axis name): error, its exact rate, the body velocity; ``desired`` = world
    ``(x, y, z, roll, pitch, yaw)``. Position error in body axes ``e = R^T (p - p_d)``, ``e_dot = v - omega x e``;
    Euler errors ``wrap(phi - phi_d)``, ``theta - theta_d``, ``wrap(psi - psi_d)`` with the rates of Eq. 1's ``T2``."""
    R = state.rotation
    omega, v = np.asarray(state.nu[:3]), np.asarray(state.nu[3:])
    e = R.T @ (np.asarray(state.position) - desired[:3])
    e_dot = v - np.cross(omega, e)
    phi, theta, psi = state.euler
    p, q, r = omega
    psi_dot = (math.sin(phi) * q + math.cos(phi) * r) / math.cos(theta)
    theta_dot = math.cos(phi) * q - math.sin(phi) * r
    phi_dot = p + psi_dot * math.sin(theta)
    error = dict(surge=e[0], sway=e[1], heave=e[2], roll=wrap(phi - desired[3]), pitch=theta - desired[4],
                 yaw=wrap(psi - desired[5]))
    rate = dict(surge=e_dot[0], sway=e_dot[1], heave=e_dot[2], roll=phi_dot, pitch=theta_dot, yaw=psi_dot)
    velocity = dict(surge=v[0], sway=v[1], heave=v[2], roll=p, pitch=q, yaw=r)
    return dict(error=error, rate=rate, velocity=velocity, e=e, e_dot=e_dot, omega=omega, euler=(phi, theta, psi))


def surface_accelerations(kin, nu_dot) -> dict[str, float]:
    """Time derivatives of the error-rate surface's ``vel`` (``e_ddot``, ``phi_ddot``, ``theta_ddot``, ``psi_ddot``)."""
    a_omega, a_v = np.asarray(nu_dot[:3]), np.asarray(nu_dot[3:])
    e_ddot = a_v - np.cross(a_omega, kin["e"]) - np.cross(kin["omega"], kin["e_dot"])
    phi, theta, _ = kin["euler"]
    p, q, r = kin["omega"]
    psi_dot, theta_dot, phi_dot = kin["rate"]["yaw"], kin["rate"]["pitch"], kin["rate"]["roll"]
    psi_ddot = ((math.sin(phi) * a_omega[1] + math.cos(phi) * a_omega[2]) / math.cos(theta)
                + phi_dot * theta_dot / math.cos(theta) + theta_dot * math.tan(theta) * psi_dot)
    theta_ddot = math.cos(phi) * a_omega[1] - math.sin(phi) * a_omega[2] - (math.sin(phi) * q + math.cos(phi) * r) * phi_dot
    phi_ddot = a_omega[0] + math.cos(theta) * theta_dot * psi_dot + math.sin(theta) * psi_ddot
    return dict(surge=e_ddot[0], sway=e_ddot[1], heave=e_ddot[2], roll=phi_ddot, pitch=theta_ddot, yaw=psi_ddot)


def input_gain(kin, axis: str, surface: str) -> float:
    if surface == "body_velocity" or axis in ("surge", "sway", "heave", "roll"):
        return 1.0
    phi, theta, _ = kin["euler"]
    return math.cos(phi) / math.cos(theta) if axis == "yaw" else math.cos(phi)


def slotine(error, rate, f_hat, bandwidth, eta, phi, uncertainty, b_hat, beta, error_rate):
    """Eqs. 26-29: ``(s, k, command)``."""
    s = rate + bandwidth * error
    u_hat = -f_hat - bandwidth * error_rate
    k = beta * (uncertainty + eta) + (beta - 1.0) * abs(u_hat)
    return s, k, b_hat * (u_hat - k * min(1.0, max(-1.0, s / phi)))


class ReferenceImu:
    """The simulated IMU as written before compilation (delay line, bias, seeded noise, finite differences)."""

    def __init__(self, noise=0.0, bias=(0.0,) * 6, delay=0, seed=0, mode="acceleration", period=0.01):
        self.noise, self.delay, self.seed, self.mode, self.period = noise, delay, seed, mode, period
        self.bias = np.broadcast_to(np.asarray(bias, dtype=float), (6,)).copy()
        self.reset()

    def reset(self):
        self._rng = np.random.default_rng(self.seed)
        self._buffer: deque = deque(maxlen=self.delay + 1)
        self._last_nu = None

    def measure(self, state: State, nu_dot_true) -> np.ndarray:
        nu = np.array(state.nu, dtype=float)
        if self.mode == "acceleration":
            raw = np.array(nu_dot_true, dtype=float)
        else:
            raw = np.zeros(6) if self._last_nu is None else (nu - self._last_nu) / self.period
        self._last_nu = nu
        if not self._buffer:
            self._buffer.extend([raw] * (self.delay + 1))
        else:
            self._buffer.append(raw)
        out = self._buffer[0] + self.bias
        if self.noise > 0:
            out = out + self._rng.normal(0.0, self.noise, 6)
        return out


def set_point(controller, t, state) -> np.ndarray:
    """The first update captures the pose (position and yaw unless given; roll and pitch default level); from
    each waypoint's time on its pose is held."""
    par = controller.par
    if controller.desired is None:
        pos = (np.array(par.desired_position, dtype=float) if par.desired_position is not None
               else np.array(state.position, dtype=float))
        yaw = par.desired_yaw if par.desired_yaw is not None else float(state.euler[2])
        controller.desired = np.array([*pos, par.desired_roll, par.desired_pitch, yaw])
    current = controller.desired
    for row in par.waypoints:
        if row[0] <= t:
            current = np.array(row[1:])
    return current


def _vehicle_state(state: State) -> State:
    return State(position=np.array(state.position), quaternion=np.array(state.quaternion), nu=np.array(state.nu),
                 q=np.zeros(0), qd=np.zeros(0))


class ReferenceSlidingMode:
    """``smc-ab`` (``predictor="ab"``), ``smc-vehicle`` (``"vehicle"``) or ``smc-ne`` (``"ne"``) with a parameter
    object of the controller class (:class:`uvms.control.smc.SlidingModeParameters` or its IMU extension)."""

    def __init__(self, predictor: str, model, par, period=0.01):
        self.predictor, self.par, self.period, self.axes = predictor, par, period, tuple(par.axes)
        scale = par.hydro_scale
        self.system = model.with_hydrodynamics_scaled(added_mass=scale, drag=scale)
        self.vehicle = self.system.vehicle_only()
        limits = {a: getattr(par, f"b_{a}") for a in self.axes}      # None: b_hat from the model
        self.from_model = {a: par.b_source == "model" or limits[a] is None for a in self.axes}
        self.b = {a: None if limits[a] is None else math.sqrt(limits[a][0] * limits[a][1]) for a in self.axes}
        self.beta = {a: None if limits[a] is None else math.sqrt(limits[a][1] / limits[a][0]) for a in self.axes}
        self.gains = {a: dict(bandwidth=par.bandwidth[j], eta=par.eta[j], phi=par.boundary_layer[j],
                              uncertainty=par.uncertainty[j]) for j, a in enumerate(self.axes)}
        if predictor == "ne":
            self.imu = ReferenceImu(par.imu_noise, par.imu_bias, par.imu_delay, par.imu_seed, par.imu_mode, period)
        self.reset()

    def reset(self):
        self.desired = None
        if self.predictor == "ne":
            self.imu.reset()

    def _response(self, model, state, tau, wrench):
        return forward_dynamics(model, state, joint_torques=tau, body_wrench=wrench).nu_dot

    def predict(self, state, tau, nu_dot_true):
        """``nu_dot`` at ``f_0 = 0`` and the per-axis ``(I^-1)_jj`` of the controller's model."""
        zero = np.zeros(6)
        if self.predictor == "ab":
            model, st, t, wrench = self.system, state, tau, zero
        else:
            model, st, t = self.vehicle, _vehicle_state(state), None
            wrench = zero
            if self.predictor == "ne":
                a0 = self.imu.measure(state, nu_dot_true)
                self.last_acceleration = a0
                wrench = self.arm_reaction(state, tau, a0)
        nu_dot = self._response(model, st, t, wrench)
        inverse_diagonal = {}
        for a in self.axes:
            unit = wrench.copy()
            unit[INDEX[a]] += 1.0
            inverse_diagonal[a] = (self._response(model, st, t, unit) - nu_dot)[INDEX[a]]
        return nu_dot, inverse_diagonal

    def arm_reaction(self, state, tau, a0):
        """``RNEA_0(vehicle; a0) - RNEA_0(system; a0, qdd)`` with ``qdd = M_qq^-1 (tau - RNEA_q(a0, 0))``."""
        n = self.system.n_joints
        _, tau0 = inverse_dynamics(self.system, state, nu_dot=a0, qdd=np.zeros(n))
        M = mass_matrix(self.system, state)
        qdd = np.linalg.solve(M[6:, 6:], tau - tau0) if n else np.zeros(0)
        f_system, _ = inverse_dynamics(self.system, state, nu_dot=a0, qdd=qdd)
        f_vehicle, _ = inverse_dynamics(self.vehicle, _vehicle_state(state), nu_dot=a0, qdd=np.zeros(0))
        return f_vehicle - f_system

    def update(self, t, state: State, tau, nu_dot_true=None):
        par = self.par
        kin = kinematics(state, set_point(self, t, state))
        nu_dot_hat, inverse_diagonal = self.predict(state, np.asarray(tau, dtype=float), nu_dot_true)
        body = par.surface == "body_velocity"
        acc = ({a: nu_dot_hat[INDEX[a]] for a in AXES} if body else surface_accelerations(kin, nu_dot_hat))
        wrench = np.zeros(6)
        signals = {}
        for a in self.axes:
            if self.from_model[a]:
                b_hat, beta = 1.0 / inverse_diagonal[a], par.b_margin
            else:
                b_hat, beta = self.b[a], self.beta[a]
            rate = kin["velocity"][a] if body else kin["rate"][a]
            g = self.gains[a]
            s, k, command = slotine(kin["error"][a], rate, acc[a], g["bandwidth"], g["eta"], g["phi"],
                                    g["uncertainty"], b_hat, beta, kin["rate"][a])
            force = command / input_gain(kin, a, par.surface)
            wrench[INDEX[a]] = force
            signals.update({f"s_{a}": s, f"k_{a}": k, f"f_hat_{a}": acc[a], f"command_{a}": force,
                            f"e_{a}": kin["error"][a]})
            if par.b_source == "model":
                signals[f"b_hat_{a}"] = b_hat
        signals["Phi"] = par.boundary_layer[0]
        if self.predictor == "ne":
            for a in self.axes:
                signals[f"imu_{a}"] = float(self.last_acceleration[INDEX[a]])
        return wrench, signals


class ReferencePid:
    """The PID baseline with clamping anti-windup, as written before compilation (numpy, per axis)."""

    def __init__(self, par, period=0.01):
        self.par, self.period, self.axes = par, period, tuple(par.axes)
        self.reset()

    def reset(self):
        self.integral = np.zeros(len(self.axes))
        self.desired = None

    def update(self, t, state, tau=None, nu_dot_true=None):
        par = self.par
        kin = kinematics(state, set_point(self, t, state))
        e = np.array([kin["error"][a] for a in self.axes])
        e_dot = np.array([kin["rate"][a] for a in self.axes])
        kp, ki, kd, limit = (np.array(x) for x in (par.kp, par.ki, par.kd, par.limit))
        unclamped = -(kp * e + ki * self.integral + kd * e_dot)
        saturated = np.abs(unclamped) >= limit
        pushing = np.sign(unclamped) == -np.sign(e)
        advance = ~(saturated & pushing)
        self.integral = np.where(advance, self.integral + e * self.period, self.integral)
        with np.errstate(divide="ignore", invalid="ignore"):
            cap = np.where(ki > 0, limit / ki, np.inf)
        self.integral = np.clip(self.integral, -cap, cap)
        force = np.clip(-(kp * e + ki * self.integral + kd * e_dot), -limit, limit)
        wrench = np.zeros(6)
        signals = {}
        for j, a in enumerate(self.axes):
            wrench[INDEX[a]] = force[j]
            signals.update({f"e_{a}": float(e[j]), f"integral_{a}": float(self.integral[j]),
                            f"command_{a}": float(force[j])})
        return wrench, signals


# ------------------------------------------------------------------------------------------------ arm


def computed_torque(model, trajectory_spline, times, angles, kp, kd, base, t, state):
    """``tau = RNEA_q(q, qd; qdd_d + kd (qd_d - qd) + kp (q_d - q))`` (fixed base: ``nu = 0``), the desired
    motion from scipy's spline (held outside its knots)."""
    q_d, qd_d, qdd_d = desired(trajectory_spline, times, angles, t)
    q, qd = np.array(state.q), np.array(state.qd)
    qdd_ref = qdd_d + kd * (qd_d - qd) + kp * (q_d - q)
    st = state if base == "moving" else state.replace(nu=np.zeros(6))
    _, tau = inverse_dynamics(model, st, nu_dot=np.zeros(6), qdd=qdd_ref)
    return tau


def desired(spline, times, angles, t):
    n = angles.shape[1]
    if spline is None or t <= times[0] or t >= times[-1]:
        q = angles[0] if spline is None or t <= times[0] else angles[-1]
        return q.copy(), np.zeros(n), np.zeros(n)
    return spline(t), spline(t, 1), spline(t, 2)


def pd_torque(spline, times, angles, kp, kd, t, state):
    q_d, qd_d, _ = desired(spline, times, angles, t)
    return kp * (q_d - np.asarray(state.q)) + kd * (qd_d - np.asarray(state.qd))


def schedule_torque(times, torques, t, step):
    """``TorqueSchedule.__call__(t + 0.5 step)``: the row in force at ``t + 0.5 step + 1e-12``."""
    k = int(np.searchsorted(times, (t + 0.5 * step) + 1e-12, side="right") - 1)
    return torques[max(k, 0)]
