"""``smc-vehicle``: the sliding-mode law with a model of the vehicle alone; the arm is a disturbance.

The controller's model is the vehicle body of the plant (its mass, inertia, added mass, drag and buoyancy,
hydrodynamics scaled by ``hydro_scale``) with no arm (:meth:`uvms.model.Model.vehicle_only`). ``f_hat`` is
that body's ``nu_dot`` at ``f_0 = 0`` (the compiled articulated-body algorithm with no joints); every reaction
of the arm is left to the robust term ``k sat(s / Phi)``, whose bound ``F`` does not know about it. This is the
baseline the paper improves on. With ``b_source = "model"``, ``b_hat`` comes from the vehicle's ``I^H_0``.
The update is :func:`uvms.control.kernels.controller_update` (predictor ``VEHICLE``).
"""

from __future__ import annotations

import numpy as np

from uvms.control.registry import register
from uvms.control.smc import SlidingModeController, SlidingModeParameters
from uvms.dynamics.plant import kernel_model, model_data


class VehicleModel:
    """The controller's vehicle-only model: the plant's body 0, hydrodynamics scaled by ``hydro_scale``."""

    def __init__(self, plant, hydro_scale: float) -> None:
        self.model = plant.with_hydrodynamics_scaled(added_mass=hydro_scale, drag=hydro_scale).vehicle_only()

    @property
    def inertia(self) -> np.ndarray:
        """The vehicle's 6x6 inertia with added mass ``I^H_0`` (body axes, about its origin)."""
        return kernel_model(self.model).inertia_h[0]

    def options(self) -> dict:
        """The :class:`~uvms.control.kernels.ControllerData` fields of this model (fresh model data)."""
        return dict(vehicle=model_data(self.model), current=np.array(self.model.current, dtype=float),
                    fluid_acceleration=np.array(self.model.fluid_acceleration, dtype=float))


@register("smc-vehicle")
class VehicleOnlySMC(SlidingModeController):
    """Sliding-mode station keeping with a vehicle-only model (no arm coupling in ``f_hat``)."""

    Parameters = SlidingModeParameters

    def __init__(self, model, parameters: SlidingModeParameters | None = None, *, period: float = 0.01) -> None:
        super().__init__(model, parameters, period=period)
        self.vehicle = VehicleModel(model, self.parameters.hydro_scale)

    def model_options(self, n_updates: int) -> dict:
        from uvms.control.kinds import VEHICLE

        return dict(predictor=VEHICLE, **self.vehicle.options())
