"""``smc-ne``: sliding mode with a vehicle-only model plus a Newton-Euler feed-forward of the arm's reaction
(Dunnigan and Russell 1998; the alternative the paper argues against in Section 5).

The controller keeps two models, both with hydrodynamics scaled by ``hydro_scale``: the vehicle body alone
(:class:`uvms.control.smc_vehicle.VehicleModel`) and the whole system for the arm's recursive Newton-Euler
equations. At each update, with the vehicle acceleration ``a_0`` from a simulated IMU
(:class:`uvms.sensors.body_acceleration.SimulatedImu`)::

    qdd    = M_qq^-1 (tau - RNEA_q(a_0, qdd = 0))           the arm's joint accelerations on that base motion
    w_arm  = RNEA_0(vehicle alone; a_0) - RNEA_0(system; a_0, qdd)
                                                              the wrench the arm exerts on the vehicle
    nu_dot_hat = ABA(vehicle alone; f_0 = w_arm)              the vehicle-only model's f_hat with the reaction

``RNEA_0`` is the base wrench of the recursive Newton-Euler algorithm (:func:`uvms.dynamics.plant.inverse_into`) on
a base moving with the measured velocity and acceleration; their difference is the force transmitted through
joint 1. (Algebraically ``nu_dot_hat = a_0 - (I^H_0)^-1 RNEA_0(system; a_0, qdd)``: acceleration feedback.)
With a perfect, noise-free acceleration this performs like ``smc-ab``; noise, bias or delay in ``a_0`` enter
``f_hat`` directly, amplified by the arm-to-vehicle mass ratio. The update is :func:`uvms.control.kernels.controller_update`
(predictor ``NE``; :func:`uvms.control.kernels.arm_reaction`, the IMU :func:`uvms.sensors.body_acceleration.imu_measure`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uvms.sensors.body_acceleration import ImuParameters, SimulatedImu, imu_data
from uvms.control.registry import choice, non_negative, non_negative_integer, parameter, register, vector
from uvms.control.smc import SlidingModeController, SlidingModeParameters
from uvms.control.smc_vehicle import VehicleModel
from uvms.dynamics.plant import model_data


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

    @property
    def signal_names(self) -> tuple[str, ...]:
        return super().signal_names + tuple(f"imu_{a}" for a in self.axes)

    def reset(self) -> None:
        super().reset()
        self.imu.reset()

    def model_options(self, n_updates: int) -> dict:
        from uvms.control.kinds import NE

        imu = self.parameters.imu()
        return dict(predictor=NE, needs_acceleration=imu.mode == "acceleration", system=model_data(self.system),
                    vehicle=model_data(self.vehicle.model), current=np.array(self.system.current, dtype=float),
                    fluid_acceleration=np.array(self.system.fluid_acceleration, dtype=float),
                    imu=imu_data(imu, self.period, n_updates))

    def _before_update(self, data):
        """The Python path shares :attr:`imu` (its noise table grows on demand, the same seeded sequence)."""
        if data.imu is not self.imu.data:
            data = data._replace(imu=self.imu.data)
        self.imu.ensure_noise(int(self.imu.data.count[0]) + 1)
        return data._replace(imu=self.imu.data) if data.imu is not self.imu.data else data

    @property
    def last_acceleration(self) -> np.ndarray:
        """The IMU's last measurement (6,)."""
        return self.imu.data.out.copy()
