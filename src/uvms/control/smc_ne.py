"""``smc-ne``: sliding mode with a vehicle-only model plus a Newton-Euler feed-forward of the arm's reaction
(Dunnigan and Russell 1998; the alternative the paper argues against in Section 5).

The controller keeps two models, both with hydrodynamics scaled by ``hydro_scale``: the vehicle body alone
(:class:`uvms.control.smc_vehicle.VehicleModel`) and the whole system for the arm's recursive Newton-Euler
equations. At each update, with the vehicle acceleration ``a_0`` from a simulated IMU
(:class:`uvms.control.imu.SimulatedImu`)::

    qdd    = M_qq^-1 (tau - RNEA_q(a_0, qdd = 0))           the arm's joint accelerations on that base motion
    w_arm  = RNEA_0(vehicle alone; a_0) - RNEA_0(system; a_0, qdd)
                                                              the wrench the arm exerts on the vehicle
    nu_dot_hat = ABA(vehicle alone; f_0 = w_arm)              the vehicle-only model's f_hat with the reaction

``RNEA_0`` is the base wrench of the recursive Newton-Euler algorithm (:func:`uvms.dynamics.rnea.rnea`) on
a base moving with the measured velocity and acceleration; their difference is the force transmitted through
joint 1. (Algebraically ``nu_dot_hat = a_0 - (I^H_0)^-1 RNEA_0(system; a_0, qdd)``: acceleration feedback.)
With a perfect, noise-free acceleration this performs like ``smc-ab``; noise, bias or delay in ``a_0`` enter
``f_hat`` directly, amplified by the arm-to-vehicle mass ratio.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uvms.control.base import Measurement
from uvms.control.imu import ImuParameters, SimulatedImu
from uvms.control.registry import choice, non_negative, non_negative_integer, parameter, register, vector
from uvms.control.smc import SlidingModeController, SlidingModeParameters
from uvms.control.smc_vehicle import VehicleModel
from uvms.dynamics.crba import crba
from uvms.dynamics.kernel_model import make_workspace
from uvms.dynamics.rnea import rnea


@dataclass(frozen=True)
class NewtonEulerParameters(SlidingModeParameters):
    """The sliding-mode parameters plus the simulated IMU's (default: a perfect acceleration measurement)."""

    imu_noise: float = parameter(0.0, non_negative, "IMU white-noise std per component [m/s^2, rad/s^2]")
    imu_bias: tuple[float, ...] = parameter((0.0,) * 6, vector(6, scalar=True),
                                            "IMU bias [omega_dot; v_dot] (6 values or one) [rad/s^2, m/s^2]")
    imu_delay: int = parameter(0, non_negative_integer, "IMU delay [controller samples]")
    imu_seed: int = parameter(0, non_negative_integer, "seed of the IMU noise")
    imu_mode: str = parameter("acceleration", choice("acceleration", "finite_difference"),
                              "acceleration: true nu_dot corrupted; finite_difference: differences of nu")

    def imu(self) -> ImuParameters:
        return ImuParameters(noise=self.imu_noise, bias=self.imu_bias, delay=self.imu_delay, seed=self.imu_seed,
                             mode=self.imu_mode)


@register("smc-ne")
class NewtonEulerSMC(SlidingModeController):
    """Sliding-mode station keeping: vehicle-only model + Newton-Euler feed-forward from a measured acceleration.

    Logs, besides the sliding-mode signals, the measured acceleration ``imu_<axis>`` (surge, sway: ``v_dot``;
    yaw: ``r_dot``).
    """

    Parameters = NewtonEulerParameters

    parameters: NewtonEulerParameters

    def __init__(self, model, parameters: NewtonEulerParameters | None = None, *, period: float = 0.01) -> None:
        super().__init__(model, parameters or NewtonEulerParameters(), period=period)
        scale = self.parameters.hydro_scale
        self.vehicle = VehicleModel(model, scale)
        self.system = model.with_hydrodynamics_scaled(added_mass=scale, drag=scale)
        self.imu = SimulatedImu(self.parameters.imu(), period=self.period)
        n = self.system.n_joints
        self._ws = make_workspace(self.system.n_bodies)
        self._ws_vehicle = make_workspace(1)
        self._M = np.zeros((6 + n, 6 + n))
        self._zero6 = np.zeros(6)
        self._zero_n = np.zeros(n)
        self._empty = np.zeros(0)
        self._current = np.array(self.system.current, dtype=float)
        self._fluid_acceleration = np.array(self.system.fluid_acceleration, dtype=float)
        self._f_system = np.zeros(6)
        self._f_vehicle = np.zeros(6)
        self._tau = np.zeros(n)
        self.last_acceleration = np.zeros(6)

    def reset(self) -> None:
        super().reset()
        self.imu.reset()

    def arm_reaction(self, rotation, nu, q, qd, tau, a0) -> np.ndarray:
        """The wrench (6,) the arm exerts on the vehicle when the base moves with ``nu``, ``a0`` (body axes)."""
        km = self.system.kernel
        vc, af = self._current, self._fluid_acceleration
        rnea(km, self._ws, rotation, nu, q, qd, a0, self._zero_n, self._zero6, vc, af, self._f_system, self._tau)
        crba(km, self._ws, q, self._M)
        qdd = np.linalg.solve(self._M[6:, 6:], tau - self._tau) if q.size else self._empty
        rnea(km, self._ws, rotation, nu, q, qd, a0, qdd, self._zero6, vc, af, self._f_system, self._tau)
        rnea(self.vehicle.model.kernel, self._ws_vehicle, rotation, nu, self._empty, self._empty, a0, self._empty,
             self._zero6, vc, af, self._f_vehicle, self._empty)
        return self._f_vehicle - self._f_system

    def predict(self, measurement: Measurement, rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The vehicle-only ``nu_dot`` at ``f_0 = 0`` with the arm's reaction at the measured acceleration."""
        st = measurement.state
        a0 = self.imu.measure(measurement)
        self.last_acceleration = a0
        nu = np.array(st.nu)
        w_arm = self.arm_reaction(rotation, nu, np.array(st.q), np.array(st.qd),
                                  np.array(measurement.joint_torques, dtype=float), a0)
        return self.vehicle.nu_dot(rotation, nu, w_arm), self.vehicle.inertia

    def update(self, measurement: Measurement):
        out = super().update(measurement)
        for axis, j in (("surge", 3), ("sway", 4), ("yaw", 2)):
            out.signals[f"imu_{axis}"] = float(self.last_acceleration[j])
        return out
