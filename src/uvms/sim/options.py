"""The grouped options of :func:`uvms.simulate` (as diffrax groups its solver, step-size controller and
saving options into objects): what drives the plant (:class:`Inputs`), how the thrusters act
(:class:`Actuation`), which integrator advances it (:class:`Rk4`, :class:`Adaptive`: one interface), and what
is recorded (:class:`Recording`).

``simulate`` also accepts these objects' fields as plain keywords (``joint_torques=...``,
``record_period=...``, ``integrator="DOP853"`` ...): :func:`grouped` sorts them into the groups.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from typing import Any, Callable

import numpy as np

from uvms import checks
from uvms.dynamics.plant import DEFAULT_BOUNDS


@dataclass(frozen=True)
class Actuation:
    """How commanded wrenches reach the vehicle: a thruster layout (empty: ideal body-wrench actuation)."""

    thrusters: tuple = ()

    @classmethod
    def named(cls, name: str | None, model=None) -> "Actuation":
        """``"ideal"`` (or ``None``), a bundled layout name, or ``"model"``: the model file's thrusters."""
        from uvms.thrusters.layouts import layout

        if name is not None and not isinstance(name, str):
            raise checks.fail("name", f"expected 'ideal', 'model' or a thruster layout name, got {checks.show(name)}")
        if name == "model":
            if model is None:
                raise checks.fail("model", "actuation 'model' (the model file's thrusters) needs the model")
            return cls(tuple(model.thrusters))
        return cls(() if name in (None, "ideal") else layout(name))


@dataclass(frozen=True)
class Inputs:
    """What drives the plant besides the controller.

    Attributes:
        joint_torques: constant (n,) [N m], a :class:`~uvms.sim.inputs.TorqueSchedule`, an arm tracker
            (:class:`~uvms.control.arm.ComputedTorqueArm`, :class:`~uvms.control.arm.PdArm`) or any callable
            ``(t, state) -> (n,)``, held over ``control_period``.
        body_wrench: constant external wrench on the vehicle (6,), body axes ``[moment; force]``.
        ee_wrench: constant spatial force on the end effector, end-effector axes (6,).
        current: constant world current (3,) [m/s], a :class:`~uvms.sim.inputs.CurrentTable`, or a callable
            ``t -> (3,)``; default: the model's environment.
        fixed_base: clamp the vehicle (a land-based arm).
        control_period: update period of a callable ``joint_torques`` [s] (default: its ``period``
            attribute, or 10 ms). A vehicle controller is updated at its own ``period``.
        joint_motion: a :class:`~uvms.sim.joint_motion.JointMotion`: every joint follows it exactly (hybrid
            dynamics; the torques it takes are the result's ``joint_torques``), instead of ``joint_torques``.
            Runs with RK4 and no controller; the initial state's ``q, qd`` are the motion's at ``t = 0``.
        thruster_commands: a :class:`~uvms.sim.inputs.CommandSchedule`: the thrusters' held commands from a
            table (a log's), with a ``joint_motion`` (the replay's loop) and an actuation that has thrusters.
        flow: the water as a :class:`~uvms.hydro.flow.Flow` (a current table plus depth profile, gridded field
            and linear waves, each body in the water at its own position; ``docs/flow.md``), instead of
            ``current``.
    """

    joint_torques: Any = None
    body_wrench: Any = None
    ee_wrench: Any = None
    current: Any = None
    fixed_base: bool = False
    control_period: float | None = None
    joint_motion: Any = None
    thruster_commands: Any = None
    flow: Any = None


@dataclass(frozen=True)
class Recording:
    """What a run keeps and reports.

    Attributes:
        period: sampling of the result [s] (default: every step, at most 20 000 samples).
        progress: ``progress(t, duration)`` called after each segment, and within a long one after every
            compiled call (about every :data:`uvms.sim.loop.CHUNK_SECONDS` of computing).
        metadata: extra entries for the result's metadata.
        bounds: sane-state limits (|position| [m], |nu|, |qd|, |actuator|); beyond them the run stops as
            diverged.
        sensors: simulated sensors (:mod:`uvms.sensors` objects) sampled on the recorded rows, each at its own
            rate (:mod:`uvms.sim.sensing`); their samples are the result's ``sensors``.
    """

    period: float | None = None
    progress: Callable[[float, float], None] | None = None
    metadata: dict[str, Any] | None = None
    bounds: np.ndarray = field(default_factory=lambda: DEFAULT_BOUNDS.copy())
    sensors: tuple = ()


@dataclass(frozen=True)
class Rk4:
    """The compiled classical fourth-order Runge-Kutta method at the run's fixed ``step`` (paper Section 4)."""

    name = "rk4"


@dataclass(frozen=True)
class Adaptive:
    """``scipy.integrate.solve_ivp`` with ``method`` (``"DOP853"``, ``"LSODA"``, ``"Radau"`` ...) between
    updates; the run's ``step`` is then the recording grid (the solver's own steps are at most 50 of them)."""

    method: str = "DOP853"
    rtol: float = 1e-10
    atol: float = 1e-12

    @property
    def name(self) -> str:
        return self.method


_INPUT_KEYS = {f.name for f in fields(Inputs)}
_RECORDING_KEYS = {"record_period": "period", "progress": "progress", "metadata": "metadata", "bounds": "bounds",
                   "sensors": "sensors"}


def grouped(inputs: Inputs | None, integrator, recording: Recording | None,
            keywords: dict[str, Any]) -> tuple[Inputs, Rk4 | Adaptive, Recording]:
    """The three option groups of a :func:`uvms.simulate` call, from the group objects and/or their fields given
    as plain keywords (``rtol``/``atol`` belong to an adaptive integrator). Unknown keywords are a ``TypeError``,
    as for any Python function; a keyword given twice (in its group and plainly) a one-line input error."""
    unknown = set(keywords) - _INPUT_KEYS - set(_RECORDING_KEYS) - {"rtol", "atol"}
    if unknown:
        raise TypeError(f"simulate() got an unexpected keyword argument {sorted(unknown)[0]!r}")
    for name, group, ok in (("inputs", inputs, Inputs), ("recording", recording, Recording)):
        if group is not None and not isinstance(group, ok):
            raise checks.fail(name, f"expected None or a uvms {ok.__name__}, got {checks.show(group)}")
    plain_inputs = {k: v for k, v in keywords.items() if k in _INPUT_KEYS}
    plain_recording = {_RECORDING_KEYS[k]: v for k, v in keywords.items() if k in _RECORDING_KEYS}
    if inputs is not None and plain_inputs:
        raise checks.fail(next(iter(plain_inputs)), "given both in inputs= and as a keyword")
    if recording is not None and plain_recording:
        raise checks.fail(next(iter(plain_recording)), "given both in recording= and as a keyword")
    inputs = replace(inputs or Inputs(), **plain_inputs)
    recording = replace(recording or Recording(), **plain_recording)
    tolerances = {k: keywords[k] for k in ("rtol", "atol") if k in keywords}
    return inputs, _integrator(integrator, tolerances), recording


def _integrator(value, tolerances: dict) -> Rk4 | Adaptive:
    if isinstance(value, (Rk4, Adaptive)):
        chosen = value
    else:
        known = {m.lower(): m for m in ("rk4", *checks.ADAPTIVE_METHODS)}
        if not isinstance(value, str) or value.lower() not in known:
            raise checks.fail("integrator", f"expected 'rk4', one of {', '.join(checks.ADAPTIVE_METHODS)}, or an "
                                            f"Rk4/Adaptive object, got {checks.show(value)}")
        chosen = Rk4() if known[value.lower()] == "rk4" else Adaptive(known[value.lower()])
    for name, value in tolerances.items():
        checks.number(value, name, positive=True)
    if isinstance(chosen, Adaptive):
        chosen = Adaptive(chosen.method, *(checks.number(tolerances.get(k, getattr(chosen, k)), k, positive=True)
                                           for k in ("rtol", "atol")))
    return chosen
