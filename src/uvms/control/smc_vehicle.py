"""``smc-vehicle``: the sliding-mode law with a model of the vehicle alone; the arm is a disturbance.

The controller's model is the vehicle body of the plant (its mass, inertia, added mass, drag and buoyancy,
hydrodynamics scaled by ``hydro_scale``) with no arm (:meth:`uvms.model.Model.vehicle_only`). ``f_hat`` is
that body's ``nu_dot`` at ``f_0 = 0``; every reaction of the arm is left to the robust term
``k sat(s / Phi)``, whose bound ``F`` does not know about it. This is the baseline the paper improves on.
"""

from __future__ import annotations

import numpy as np

from uvms.control.base import Measurement
from uvms.control.registry import register
from uvms.control.smc import SlidingModeController, SlidingModeParameters
from uvms.dynamics.aba import aba
from uvms.dynamics.kernel_model import make_workspace


class VehicleModel:
    """The vehicle-only model's forward dynamics with a preallocated workspace (compiled ABA, 0 joints)."""

    def __init__(self, plant, hydro_scale: float) -> None:
        self.model = plant.with_hydrodynamics_scaled(added_mass=hydro_scale, drag=hydro_scale).vehicle_only()
        self._ws = make_workspace(1)
        self._empty = np.zeros(0)
        self._zero6 = np.zeros(6)
        self._current = np.array(self.model.current, dtype=float)
        self._fluid_acceleration = np.array(self.model.fluid_acceleration, dtype=float)
        self._nu_dot = np.zeros(6)

    @property
    def inertia(self) -> np.ndarray:
        """The vehicle's 6x6 inertia with added mass ``I^H_0`` (body axes, about its origin)."""
        return self.model.kernel.inertia_h[0]

    def nu_dot(self, rotation: np.ndarray, nu: np.ndarray, body_wrench: np.ndarray | None = None) -> np.ndarray:
        """``nu_dot`` (6,) of the vehicle alone under ``body_wrench`` (default none) at pose ``rotation``."""
        aba(self.model.kernel, self._ws, rotation, nu, self._empty, self._empty, self._empty,
            self._zero6 if body_wrench is None else body_wrench, self._zero6, self._current,
            self._fluid_acceleration, False, self._nu_dot, self._empty)
        return self._nu_dot.copy()


@register("smc-vehicle")
class VehicleOnlySMC(SlidingModeController):
    """Sliding-mode station keeping with a vehicle-only model (no arm coupling in ``f_hat``)."""

    Parameters = SlidingModeParameters

    def __init__(self, model, parameters: SlidingModeParameters | None = None, *, period: float = 0.01) -> None:
        super().__init__(model, parameters, period=period)
        self.vehicle = VehicleModel(model, self.parameters.hydro_scale)

    def predict(self, measurement: Measurement, rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The vehicle-only ``nu_dot`` at ``f_0 = 0`` and the vehicle's inertia ``I^H_0``."""
        return self.vehicle.nu_dot(rotation, np.array(measurement.state.nu)), self.vehicle.inertia
