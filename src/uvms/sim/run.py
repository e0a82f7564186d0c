"""Run a simulation: :func:`simulate`, a short event loop over the compiled plant.

The run is prepared once (:class:`uvms.sim.plan.RunPlan`: inputs checked and normalised, the plant
assembled), advanced by a loop (:mod:`uvms.sim.loop`) and labelled (:mod:`uvms.sim.record`).
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass
from typing import Callable

from uvms import checks
from uvms.dynamics.plant import DEFAULT_BOUNDS  # noqa: F401  (re-exported)
from uvms.hydro.flow import check_status
from uvms.sim.compiled_loop import compilable, run_compiled
from uvms.sim.loop import run_python
from uvms.sim.options import Actuation, Inputs, Recording, grouped  # noqa: F401  (Actuation re-exported)
from uvms.sim.plan import MAX_STEPS, RunPlan, Timing, check_steps, events  # noqa: F401  (re-exported)
from uvms.sim.prescribed import run_prescribed
from uvms.sim.record import result_of
from uvms.sim.result import Result
from uvms.state import State

CHUNK_SECONDS = 0.1
"""Wall time aimed at by one call of the compiled RK4 loop. A long held-input segment (a whole run without a
controller) is cut into calls of a bounded number of steps, sized from the measured cost of the previous call,
so that Ctrl-C (``KeyboardInterrupt``, seen only between calls) and ``progress`` respond within a fraction of a
second. The cut does not change the arithmetic: every call continues the same step grid (``t = k h``)."""

FIRST_CHUNK_STEPS = 64
"""Steps of the first compiled RK4 call of a run; later calls are sized from the measured cost."""


def _next_chunk(steps: int, seconds: float, current: int) -> int:
    """Steps of the next compiled call: aimed at :data:`CHUNK_SECONDS` from the last call's cost, growing at
    most 4-fold per call (a first call may include one-off costs) and never below 16."""
    if steps < current:                       # a short remainder says nothing new about the cost
        return current
    aim = int(steps * CHUNK_SECONDS / max(seconds, 1e-9))
    return max(16, min(aim, 4 * steps))


@dataclass(frozen=True)
class _Chunking:
    first: int
    next: Callable[[int, float, int], int]


_events = events


def simulate(model, initial_state: State | None = None, *, duration: float, step: float = 1e-3, controller=None,
             actuation: Actuation | None = None, inputs: Inputs | None = None, **options) -> Result:
    """Simulate ``duration`` seconds from ``initial_state`` (default: at rest at the origin).

    Args:
        step: integration step [s] (RK4); for an adaptive integrator the recording grid.
        controller: a vehicle controller (:class:`uvms.control.base.Controller`) or ``None``.
        actuation: thrusters between the controller and the vehicle (default: ideal body wrench).
        inputs: joint torques, external wrenches, current, clamped vehicle (:class:`~uvms.sim.options.Inputs`).
        options: ``integrator=`` ``"rk4"`` (compiled, fixed step), a ``solve_ivp`` method name (``"DOP853"``,
            ``"LSODA"`` ...) or an :class:`~uvms.sim.options.Rk4`/:class:`~uvms.sim.options.Adaptive` object;
            ``recording=`` a :class:`~uvms.sim.options.Recording`; or the fields of ``Inputs`` and
            ``Recording`` as plain keywords (``joint_torques=``, ``current=``, ``record_period=``,
            ``progress=`` ...), and ``rtol=``/``atol=`` of an adaptive integrator.

    The result's last row is the state at ``t = duration`` exactly, whatever the recording period.
    """
    wall0 = _time.perf_counter()
    plan = prepare(model, initial_state, duration=duration, step=step, controller=controller, actuation=actuation,
                   inputs=inputs, **options)
    loop = run_prescribed if plan.motion is not None else run_compiled if compilable(plan) else run_python
    outcome, log = loop(plan, _Chunking(FIRST_CHUNK_STEPS, _next_chunk))
    if plan.water is not None:
        check_status(plan.water)                 # a body left a field that has no outside: one line
    return result_of(plan, outcome, log, wall0)


def prepare(model, initial_state: State | None = None, *, duration: float, step: float = 1e-3, controller=None,
            actuation: Actuation | None = None, inputs: Inputs | None = None, **options) -> RunPlan:
    """The checked, compiled-ready :class:`~uvms.sim.plan.RunPlan` of a :func:`simulate` call (same arguments),
    without running it: :func:`uvms.sim.batch.run_plans` runs many in threads."""
    checks.model(model)
    timing = Timing.of(duration, step)
    integrator, recording = options.pop("integrator", "rk4"), options.pop("recording", None)
    return RunPlan.build(model, initial_state, timing, (controller, actuation),
                         grouped(inputs, integrator, recording, options))
