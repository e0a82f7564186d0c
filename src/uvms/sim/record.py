"""From what a loop recorded to a labelled :class:`~uvms.sim.result.Result`: the final sample, the inputs and
signals of every row (zero-order hold of the updates), the end-effector path, metadata and joint-limit
crossings."""

from __future__ import annotations

import time as _time

import numpy as np

from uvms.dynamics.plant import kernel_model
from uvms.kinematics import end_effector_path
from uvms.sim.health import actuation_metadata, set_point_metadata
from uvms.sim.result import Result
from uvms.state import JOINTS


def held_signals(per_update: list[dict[str, float]], which: np.ndarray) -> dict[str, np.ndarray]:
    """One column per signal name, row ``r`` holding update ``which[r]``'s value (NaN where that update did
    not log the name). Updates logging the same names in the same order (the usual case) fill their rows in
    one assignment."""
    groups: dict[tuple[str, ...], list[int]] = {}
    for u, sg in enumerate(per_update):
        groups.setdefault(tuple(sg), []).append(u)
    names = sorted({k for keys in groups for k in keys})
    column = {k: i for i, k in enumerate(names)}
    held = np.full((len(per_update), len(names)), np.nan)
    for keys, rows in groups.items():
        if keys:
            held[np.ix_(rows, [column[k] for k in keys])] = [list(per_update[u].values()) for u in rows]
    return {k: held[which, column[k]] for k in names}


def versions() -> dict[str, str]:
    """Versions of uvms and the numerical libraries, for a result's metadata."""
    import numba
    import scipy

    import uvms

    return {"uvms_version": uvms.__version__, "numpy_version": np.__version__, "scipy_version": scipy.__version__,
            "numba_version": numba.__version__}


RK4_STABILITY = 2.785
"""RK4's stability limit on the negative real axis: ``dx/dt = -x / tau`` stays bounded for ``h <= 2.785 tau``."""


def stiff_joint(model, h: float, q=None) -> tuple[int, float, float, float] | None:
    """The joint whose damping and regularised friction are too stiff for RK4 at step ``h`` [s], as
    ``(index, inertia J, time constant tau [s], least friction_speed that keeps it stable)``, or ``None``.

    Below ``v_s`` the joint law ``tau_p = -b qd - F_c clip(qd / v_s, -1, 1)`` (``docs/models.md``, "Joint damping
    and friction") is a viscous law of slope ``c = b + F_c / v_s``; with ``J = 1 / (M^-1)_jj`` the least inertia
    the joint drives (every other coordinate free; ``M`` at ``q``, default zeros) its time constant is
    ``tau = J / c``, and RK4 is unstable for ``h > 2.785 tau`` (:data:`RK4_STABILITY`). The stiffest such joint
    is named; the friction speed returned makes ``tau >= h`` (``v_s >= F_c / (J / h - b)``; ``inf`` when the
    damping alone is too stiff)."""
    from uvms.dynamics.api import mass_matrix
    from uvms.state import State

    n = model.n_joints
    damping, friction = np.asarray(model.joint_damping, float), np.asarray(model.joint_friction, float)
    c = damping + friction / np.asarray(model.joint_friction_speed, float)
    if n == 0 or not np.any(c > 0):
        return None
    try:
        inverse = np.linalg.inv(mass_matrix(model, State.from_euler(model, q=np.zeros(n) if q is None else q)))
    except np.linalg.LinAlgError:
        return None
    J = 1.0 / np.diag(inverse)[6:]
    tau = np.divide(J, c, out=np.full(n, np.inf), where=c > 0)
    j = int(np.argmin(tau))
    if not h > RK4_STABILITY * tau[j]:
        return None
    room = J[j] / h - damping[j]
    return j, float(J[j]), float(tau[j]), float(friction[j] / room) if room > 0 else float("inf")


def divergence_hint(model, h: float) -> str:
    """What to change after a divergence at step ``h`` [s]: the stiff joint and its ``friction_speed``
    (:func:`stiff_joint`) when there is one, otherwise a smaller step."""
    stiff = stiff_joint(model, h)
    if stiff is None:
        return f"try a smaller step (now {h:g} s)"
    j, J, tau, speed = stiff
    name = model.joint_names[j]
    key = f"joints.{name}"
    fix = (f"raise {key}.friction_speed in the model file to at least {speed:.3g} (or lower {key}.friction), "
           if np.isfinite(speed) else f"lower {key}.damping in the model file, ")
    return (f"joint {name!r} is too stiff for the step {h:g} s: friction {float(model.joint_friction[j]):g} over "
            f"friction_speed {float(model.joint_friction_speed[j]):g} plus damping {float(model.joint_damping[j]):g} "
            f"on an inertia of {J:.3g} give a time constant of {tau:.3g} s, and RK4 needs a step below "
            f"{RK4_STABILITY:g} times it: {fix}or take a step below {RK4_STABILITY * tau:.3g} s")


def divergence_message(plan, outcome) -> str:
    """The one-line reason a run stopped early, with :func:`divergence_hint`."""
    h = plan.timing.h
    idx = abs(outcome.code) - 1
    what = outcome.reason or ("is not finite" if outcome.code < 0 else "left its sane range")
    quantity = "" if outcome.reason else f"{plan.layout.quantity_name(idx)} "
    return f"simulation diverged at t = {outcome.done * h:.4g} s: {quantity}{what}; {divergence_hint(plan.model, h)}"


def result_of(plan, outcome, log, wall0: float) -> Result:
    """The :class:`Result` of a finished loop (module docstring). The last row is the state at ``t = duration``
    exactly for a complete run, and the state where it stopped otherwise."""
    timing, rec, x = plan.timing, plan.samples, plan.x
    n_out = int(rec.count[0])
    complete = outcome.code == 0
    if complete:                            # the final state is always a row, at exactly t = duration
        if timing.n_total % rec.every:
            rec.states[n_out] = x
            n_out += 1
        rec.times[n_out - 1] = timing.duration
    elif n_out == 0 or rec.times[n_out - 1] < outcome.done * timing.h:
        rec.times[n_out] = outcome.done * timing.h
        rec.states[n_out] = x
        n_out += 1
    out_t, out_x = rec.times[:n_out], rec.states[:n_out]
    n = plan.layout.n_joints
    update_times = np.array(log.steps) * timing.h
    which = np.clip(np.searchsorted(update_times, out_t + 0.5 * timing.h, side="right") - 1, 0, len(log.steps) - 1)
    out_tau = np.array(log.torques, dtype=float).reshape(len(log.steps), n)[which]
    signals = log.held(which)
    if plan.motion is not None:             # a prescribed joint motion: the torques it takes at every row
        from uvms.sim.prescribed import command_signals, row_torques

        out_tau = row_torques(plan, out_t, out_x)
        signals = command_signals(plan, out_t)
    ee = np.zeros((n_out, 3))
    end_effector_path(kernel_model(plan.model), np.ascontiguousarray(out_x), ee)
    meta = {"integrator": plan.integrator.name, "step_s": timing.h, "duration_s": timing.duration,
            "fixed_base": plan.fixed_base, "frame": plan.model.convention,
            **({"joint_motion": True} if plan.motion is not None else {}),
            "wall_time_s": _time.perf_counter() - wall0, "model": plan.model.name,
            "joint_names": list(plan.model.joint_names), "joint_types": list(plan.model.joint_type), **versions(),
            **actuation_metadata(plan), **set_point_metadata(plan), **(plan.recording.metadata or {})}
    report_joint_limits(plan.model, out_t, out_x, out_tau, meta)
    from uvms.sim.sensing import sensor_records

    sensors = sensor_records(plan, out_t, out_x, out_tau, signals)
    if sensors:
        meta["sensors"] = {name: {"kind": r.kind, "rate_hz": float(s.rate), "frame_id": r.frame_id,
                                  **({"mount": {"offset_m": s.mount.offset.tolist(),       # sensor -> body axes
                                                "rotation": s.mount.rotation.tolist()}} if hasattr(s, "mount") else {})}
                           for (name, r), s in zip(sensors.items(), plan.recording.sensors)}
    return Result(time=out_t, states=out_x, n_joints=n, end_effector=ee, joint_torques=out_tau,
                  signals=signals, complete=complete,
                  message="" if complete else divergence_message(plan, outcome), metadata=meta, sensors=sensors)


def report_joint_limits(model, t, x, tau, meta: dict) -> None:
    """Joint limits crossed in the run (:func:`uvms.model.limits.joint_limit_crossings`): a warning, and the
    lines under ``metadata["joint_limit_crossings"]``."""
    from uvms.model.limits import JointLimitWarning, joint_limit_crossings

    n = model.n_joints
    lines = joint_limit_crossings(model, t, x[:, JOINTS:JOINTS + n], x[:, JOINTS + n:JOINTS + 2 * n], tau)
    if lines:
        import warnings

        meta["joint_limit_crossings"] = lines
        warnings.warn(f"{model.name}: {lines[0]}" + (f" (and {len(lines) - 1} more)" if len(lines) > 1 else ""),
                      JointLimitWarning, stacklevel=4)
