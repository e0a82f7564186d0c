"""``smc-ab``: the paper's sliding-mode controller with an articulated-body model (Section 5).

``f_hat`` comes from the controller's own model of the whole vehicle-manipulator system: a copy of the plant
with every added-mass matrix and drag coefficient multiplied by ``hydro_scale`` (the paper's "60 %" error is
0.4). At each update the compiled articulated-body algorithm (:func:`uvms.dynamics.plant.forward_into` on the
controller's own :class:`~uvms.dynamics.plant.ModelData`) gives the vehicle's ``nu_dot`` at the measured state
and joint torques with ``f_0 = 0`` (Eqs. 16-17, 24-25); the arm's reaction on the vehicle is inside the
articulated inertia ``I_0^*`` and bias ``beta_0^*``, so no acceleration measurement is needed. With
``b_source = "model"``, ``b_hat`` is taken from ``I_0^*`` (``1 / (I_0^*^-1)_jj``). The
update is :func:`uvms.control.kernels.controller_update` (predictor ``AB``).
"""

from __future__ import annotations

import numpy as np

from uvms.control.registry import register
from uvms.control.smc import SlidingModeController, SlidingModeParameters
from uvms.dynamics.plant import model_data


@register("smc-ab")
class ArticulatedBodySMC(SlidingModeController):
    """Sliding-mode station keeping whose model is the articulated-body algorithm of the whole system."""

    Parameters = SlidingModeParameters

    def __init__(self, model, parameters: SlidingModeParameters | None = None, *, period: float = 0.01) -> None:
        super().__init__(model, parameters, period=period)
        scale = self.parameters.hydro_scale
        self.model = model.with_hydrodynamics_scaled(added_mass=scale, drag=scale)

    def model_options(self, n_updates: int) -> dict:
        from uvms.control.kinds import AB

        return dict(predictor=AB, system=model_data(self.model), current=np.array(self.model.current, dtype=float),
                    fluid_acceleration=np.array(self.model.fluid_acceleration, dtype=float))
