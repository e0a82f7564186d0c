"""Replay a logged trial: the vehicle free from the log's start state, the joints following the log exactly
(prescribed motion, hybrid dynamics), and the run compared with the log (``docs/logs.md``, "Replaying").

:func:`replay` simulates in the **log's** frame convention (a model written in the other one is mapped onto it
by :meth:`uvms.model.Model.in_frame`, the half turn of :mod:`uvms.frames`), so the run's roll, pitch, yaw and
position read like the log's. Logged thruster commands, when the log has them, drive the model file's
thrusters (held from row to row, :func:`commands_of`); without them the thrusters are off.
The joints follow a C2 cubic spline through the logged angles sampled on a uniform grid at the joint stream's own spacing (:class:`uvms.sim.joint_motion.JointMotion`); the start state is
the log's (:meth:`uvms.Log.initial_state`: pose, body velocities from a local fit) with the joints at the
spline's start. The comparison is on a uniform grid (default 40 ms): signals of
:mod:`uvms.identify.experiment` and the scores of :mod:`uvms.logs.score` (RMSE beside the no-skill score of the
start held).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from uvms.errors import UvmsInputError
from uvms.identify.experiment import Experiment, result_signals, signal_values
from uvms.sim.options import Inputs

COMPARED = ("roll", "pitch", "yaw", "depth", "x", "y")
"""Signals a replay compares (:data:`uvms.identify.experiment.SIGNALS`)."""

DEFAULT_STEP = 0.002
"""RK4 step of a replay [s]: the BlueROV2 + Alpha 5's fastest mode (the arm's joint motion) is resolved well
below it; halving it changes the Hinsdale replays' attitude by < 1e-4 deg (``docs/logs.md``)."""

DEFAULT_GRID = 0.04
"""Spacing of the comparison grid [s] (25 Hz, the bundled trials' motion-capture rate)."""


def in_log_frame(model, log):
    """``model`` written in ``log``'s frame convention (:meth:`uvms.model.Model.in_frame`; itself when they
    agree)."""
    return model.in_frame(log.frame)


def joint_motion_of(log, model, *, spacing: float | None = None, smoothing=None):
    """The prescribed joint motion of ``log`` for ``model``: a cubic spline through the logged angles (model
    convention, offsets and signs applied) on a uniform grid from the replay's start to its end, at ``spacing``
    [s] (default: the joint stream's median row spacing). Joints the log does not describe are held at 0."""
    from uvms.sim.joint_motion import JointMotion

    if "joints" not in log.streams:
        raise UvmsInputError("expected a joints stream to replay the arm (the log describes none)", log.source,
                             "joints")
    stream = log.streams["joints"]
    if spacing is None:
        spacing = float(np.median(np.diff(stream.time)))
    spacing = min(max(spacing, 1e-3), log.duration / 2.0)
    times = log.grid(spacing)
    table = log.joint_angles(times)
    angles = np.zeros((times.size, model.n_joints))
    for k, name in enumerate(model.joint_names):
        column = f"q_{name}_rad"
        if column in table.columns:
            angles[:, k] = table[column].to_numpy()
    return JointMotion.from_arrays(times, angles, joints=model.joint_names, smoothing=smoothing)


def commands_of(log, model):
    """``(actuation, schedule)`` of the log's thruster commands for ``model``: the model file's thrusters and a
    :class:`~uvms.sim.inputs.CommandSchedule` of the logged commands from the replay's start (the row in force at
    the start, then each later row at its time, held: zero-order hold); ``(None, None)`` when the log describes
    no thrusters. The log's unit must be each thruster's command unit (``docs/logs.md``, "Thruster commands")."""
    from uvms.sim.inputs import CommandSchedule
    from uvms.sim.options import Actuation

    if "thrusters" not in log.streams:
        return None, None
    stream = log.streams["thrusters"]
    if not model.thrusters:
        raise UvmsInputError(f"the log gives thruster commands but model {model.name!r} has no thrusters (its "
                             f"file's thrusters: key) to replay them on", log.source, "thrusters")
    have = [th.name for th in model.thrusters]
    unknown = [x for x in stream.names if x not in have]
    missing = [x for x in have if x not in stream.names]
    if unknown or missing:
        raise UvmsInputError("expected one command column per thruster of the model (" + ", ".join(have) + ")"
                             + (f"; not a thruster of the model: {', '.join(unknown)}" if unknown else "")
                             + (f"; missing {', '.join(missing)}" if missing else ""), log.source,
                             "thrusters.columns")
    rel = stream.time - log.start
    first = int(np.searchsorted(rel, 1e-9, side="right")) - 1          # the row in force at the start
    last = int(np.searchsorted(rel, log.duration + 1e-9, side="right"))
    times = rel[first:last].copy()
    times[0] = 0.0
    schedule = CommandSchedule(times, stream.parts["commands"][first:last], names=stream.names)
    return Actuation.named("model", model), schedule


def start_state(log, model, motion):
    """The log's start state with the joints at the prescribed motion's start."""
    state = log.initial_state(model)
    q, qd, _ = motion(0.0)
    return state.replace(q=np.asarray(q, dtype=float), qd=np.asarray(qd, dtype=float))


def measured_signals(log, times, frame: str) -> dict[str, np.ndarray]:
    """The log's :data:`COMPARED` signals at ``times`` [s from start], in ``frame``."""
    table = log.in_frame(frame).resample(times)
    position = table[["x_m", "y_m", "z_m"]].to_numpy()
    euler = table[["roll_rad", "pitch_rad", "yaw_rad"]].to_numpy()
    return {name: signal_values(name, times, position, euler, frame) for name in COMPARED}


@dataclass(frozen=True, eq=False)
class Replay:
    """A logged trial replayed (:func:`replay`).

    Attributes:
        name: the trial's name (the log file's stem).
        log: the :class:`uvms.Log`.
        model: the model simulated (in the log's frame convention).
        result: the simulated :class:`~uvms.sim.result.Result` (``t = 0`` at the log's start).
        times: (K,) the comparison grid [s].
        measured, simulated, held: ``{signal: (K,)}`` of the log, the run and the no-skill prediction (the
            start value held), in the log's frame [rad, m].
        scores: the :class:`~uvms.logs.score.ReplayScores`.
        experiment: the :class:`~uvms.identify.experiment.Experiment` that was simulated (:func:`plan`).
    """

    name: str
    log: Any
    model: Any
    result: Any
    times: np.ndarray
    measured: dict
    simulated: dict
    held: dict
    scores: Any
    experiment: Experiment

    def comparison(self) -> dict:
        """``comparison.json``'s content: the scores, what was compared and how."""
        return {"trial": self.name, "log": self.log.source, "model": self.model.name, "frame": self.log.frame,
                "start_s": self.log.start, "duration_s": self.log.duration,
                "grid_s": float(self.times[1] - self.times[0]), **self.scores.to_dict(),
                "complete": bool(self.result.complete),
                "x_change_rmse_m": _rms(self.simulated["x"] - self.measured["x"]),
                "y_change_rmse_m": _rms(self.simulated["y"] - self.measured["y"]),
                "x_change_no_skill_rmse_m": _rms(self.measured["x"]),
                "y_change_no_skill_rmse_m": _rms(self.measured["y"])}

    def figure(self):
        """Log and simulation per signal (:func:`uvms.plots.comparison_figure`)."""
        from uvms.plots import comparison_figure

        s = self.scores
        scores = {"roll": s.roll_rmse_deg, "pitch": s.pitch_rmse_deg, "yaw": s.yaw_change_rmse_deg,
                  "depth": s.depth_change_rmse_m}
        return comparison_figure(self.times, self.measured, self.simulated, held=self.held, scores=scores,
                                 title=f"{self.name}: {self.model.name} against the log ({self.log.frame})")


def _rms(e) -> float:
    return float(np.sqrt(np.mean(np.square(e))))


def _log_of(log):
    from uvms.logs import Log

    if isinstance(log, Log):
        return log
    if isinstance(log, (str, os.PathLike)):
        return Log.load(log)
    raise UvmsInputError(f"expected a uvms.Log or a log description file, got {type(log).__name__}", path="log")


def plan(model, log, *, step: float = DEFAULT_STEP, grid: float = DEFAULT_GRID, smoothing=None,
         body_wrench=None) -> Experiment:
    """The :class:`~uvms.identify.experiment.Experiment` of a log: what :func:`replay` simulates and compares
    (``model`` in the log's frame convention; ``body_wrench`` an optional constant disturbance)."""
    log = _log_of(log)
    model = in_log_frame(model, log)
    motion = joint_motion_of(log, model, smoothing=smoothing)
    actuation, commands = commands_of(log, model)
    times = log.grid(grid)
    inputs = Inputs(joint_motion=motion, body_wrench=body_wrench, thruster_commands=commands)
    name = Path(log.source).stem if log.source else "log"
    return Experiment(name, start_state(log, model, motion), log.duration, times,
                      measured_signals(log, times, log.frame), inputs=inputs, step=step, frame=log.frame,
                      actuation=actuation)


def replay(model, log, *, step: float = DEFAULT_STEP, grid: float = DEFAULT_GRID, smoothing=None,
           body_wrench=None, progress=None) -> Replay:
    """Simulate a logged trial and compare it with the log (module docstring).

    Args:
        model: a :class:`~uvms.model.Model` (or a model name or file).
        log: a :class:`uvms.Log` or a log description file.
        step: RK4 step [s]; grid: comparison spacing [s].
        smoothing: the joint spline's smoothing (``None``: interpolate; ``"gcv"`` or a penalty, as
            :meth:`uvms.sim.joint_motion.JointMotion.from_arrays`).
        body_wrench: an optional constant body wrench ``[moment; force]`` (a disturbance) [N m, N].
        progress: ``progress(t, duration)`` during the run.
    """
    from uvms.sim.run import simulate

    if isinstance(model, (str, os.PathLike)):
        from uvms.model.load import load_model

        model = load_model(model)
    log = _log_of(log)
    model = in_log_frame(model, log)
    e = plan(model, log, step=step, grid=grid, smoothing=smoothing, body_wrench=body_wrench)
    result = simulate(model, e.initial_state, duration=e.duration, step=e.step, inputs=e.inputs,
                      actuation=e.actuation, record_period=e.record_period(), progress=progress)
    simulated = result_signals(result, e.times, COMPARED, e.frame)
    held = {name: np.full(e.times.size, values[0]) for name, values in e.measured.items()}
    scores = log.score(e.times, roll=simulated["roll"], pitch=simulated["pitch"],
                       yaw=simulated["yaw"], depth=_depth(result, e.times, e.frame), frame=e.frame)
    return Replay(e.name, log, model, result, e.times, e.measured, simulated, held, scores, e)


def _depth(result, times, frame: str) -> np.ndarray:
    """Depth [m, positive down] of a run at ``times`` (:func:`uvms.frames.depth`)."""
    from uvms.frames import depth

    return depth(np.interp(times, result.time, result.position[:, 2]), frame)


def log_result(log, model, *, grid: float = DEFAULT_GRID, times=None):
    """The logged motion as a :class:`~uvms.sim.result.Result` of ``model`` (in the log's frame convention) on
    a uniform grid (or at ``times`` [s from the start], e.g. a simulation's rows): pose and joint angles from the
    log, velocities and torques zero (for drawing it, e.g. in 3-D beside the simulation)."""
    from uvms.dynamics.poses import end_effector_position
    from uvms.sim.result import Result
    from uvms.state import StateLayout

    times = log.grid(grid) if times is None else log.check_times(times)
    table = log.resample(times)
    layout = StateLayout(model.n_joints)
    states = np.zeros((times.size, layout.size))
    states[:, layout.position] = table[["x_m", "y_m", "z_m"]].to_numpy()
    states[:, layout.quaternion] = table[["qw", "qx", "qy", "qz"]].to_numpy()
    for k, name in enumerate(model.joint_names):
        column = f"q_{name}_rad"
        if column in table.columns:
            states[:, layout.q.start + k] = table[column].to_numpy()
    drawn = Result(time=times, states=states, n_joints=model.n_joints, end_effector=np.zeros((times.size, 3)),
                   joint_torques=np.zeros((times.size, model.n_joints)),
                   metadata={"scenario": f"log {log.source}", "joint_names": list(model.joint_names)})
    ee = np.array([end_effector_position(model, drawn.state(k)) for k in range(times.size)])
    return replace(drawn, end_effector=ee)
