"""``smc-ab``: the paper's sliding-mode controller with an articulated-body model (Section 5).

``f_hat`` comes from the controller's own model of the whole vehicle-manipulator system: a copy of the plant
with every added-mass matrix and drag coefficient multiplied by ``hydro_scale`` (the paper's "60 %" error is
0.4). At each update the compiled articulated-body algorithm (:func:`uvms.dynamics.plant.forward_into` on the
controller's own :class:`~uvms.dynamics.plant.ModelData`) gives the vehicle's ``nu_dot`` at the measured state
and joint torques with ``f_0 = 0`` (Eqs. 16-17, 24-25); the arm's reaction on the vehicle is inside the
articulated inertia ``I_0^*`` and bias ``beta_0^*``, so no acceleration measurement is needed. With
``b_source = "model"``, ``b_hat`` is taken from ``I_0^*`` (``1 / (I_0^*^-1)_jj``). The
update is :func:`uvms.control.kernels.controller_update` (predictor ``AB``).

**Wave feed-forward** (``wave_feed_forward: true``; off by default). Off, the controller's model sees the model
file's constant current and fluid acceleration (``Model.current``, ``Model.fluid_acceleration``), whatever the
run's water. On, it sees the run's water itself, the :class:`~uvms.hydro.flow.FlowData` the plant integrates
(uniform table, depth profile, field, waves), evaluated at the update's time for every body at its own
position: in the outward pass of the prediction each body's drag acts on ``u_f - v`` and its Froude-Krylov and
added-mass forces on ``a_f`` (paper Eq. 7 with ``a_f`` per body, :mod:`uvms.hydro.flow`), so the fluid's wrench
on the whole system enters ``f_hat`` and the command cancels what the model predicts of it (Walker et al. 2023
feed the predicted wave disturbance forward the same way). "Known" is an idealisation: the controller knows the
true water of the run, as if it had a perfect wave and current prediction; a real system would have to
estimate or forecast it (a wave radar, a pressure-sensor array, a current profiler). The simulation hands the
water in (:meth:`ArticulatedBodySMC.set_known_water`, called by :meth:`uvms.sim.plan.RunPlan.build` for every
run); a controller updated by hand without it sees the model's constant environment. With still water or a
constant current equal to the model's, on and off give the same commands.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from uvms.control.registry import parameter, register
from uvms.control.smc import SlidingModeController, SlidingModeParameters
from uvms.dynamics.plant import model_data
from uvms.hydro.flow import FlowData


def flag(value: Any) -> bool:
    """``true`` or ``false`` (a YAML or Python boolean; numbers and strings are refused)."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise ValueError(f"expected true or false, found {value!r}")


@dataclass(frozen=True)
class ArticulatedBodyParameters(SlidingModeParameters):
    """The sliding-mode parameters plus the wave feed-forward switch (module docstring)."""

    wave_feed_forward: bool = parameter(False, flag, "true: the controller's model sees the run's water (waves, "
                                                     "currents) at each update's time; false: the model's constant "
                                                     "current")


@register("smc-ab")
class ArticulatedBodySMC(SlidingModeController):
    """Sliding-mode station keeping whose model is the articulated-body algorithm of the whole system."""

    Parameters = ArticulatedBodyParameters

    parameters: ArticulatedBodyParameters

    def __init__(self, model, parameters: ArticulatedBodyParameters | None = None, *, period: float = 0.01) -> None:
        super().__init__(model, parameters or ArticulatedBodyParameters(), period=period)
        scale = self.parameters.hydro_scale
        self.model = model.with_hydrodynamics_scaled(added_mass=scale, drag=scale)
        self._water: FlowData | None = None

    def set_known_water(self, water: FlowData | None) -> None:
        """The run's water (the plant's compiled :class:`~uvms.hydro.flow.FlowData`, world frame of the model's
        convention), which the model sees with ``wave_feed_forward`` on; ``None`` forgets it. The simulation
        calls this before a run; the next update starts afresh (:meth:`reset`)."""
        if water is not None and not isinstance(water, FlowData):
            raise TypeError(f"expected a uvms.hydro.flow.FlowData or None, got {type(water).__name__}")
        self._water = water
        self.reset()

    @property
    def feeds_water_forward(self) -> bool:
        """Whether the model's water is the run's (``wave_feed_forward`` on and the water handed in)."""
        return self.parameters.wave_feed_forward and self._water is not None

    def model_options(self, n_updates: int) -> dict:
        from uvms.control.kinds import AB

        if self.feeds_water_forward:
            return dict(predictor=AB, system=model_data(self.model), flow=self._water)
        return dict(predictor=AB, system=model_data(self.model), current=np.array(self.model.current, dtype=float),
                    fluid_acceleration=np.array(self.model.fluid_acceleration, dtype=float))
