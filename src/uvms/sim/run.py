"""Run a simulation: the outer loop of controller updates around the compiled integrator.

Between two events (a controller update, a change in the joint-torque schedule, the end) every input is
held (zero-order hold) and the compiled RK4 loop (:func:`uvms.sim.integrate.rk4`) advances the state with
no Python in between. The adaptive alternative hands the same compiled derivative to scipy's
``solve_ivp`` (DOP853, LSODA, Radau ...) segment by segment.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from uvms import checks
from uvms.control.base import ControlOutput, Measurement
from uvms.dynamics.fastcall import specialised
from uvms.dynamics.kernel_model import make_workspace
from uvms.kinematics import end_effector_path
from uvms.sim.actuation import actuator_kernel, n_actuator_states
from uvms.sim.inputs import CurrentTable, TorqueSchedule
from uvms.sim.integrate import check_state, pack, rk4, state_derivative, unpack
from uvms.sim.result import Result
from uvms.state import State

MAX_STEPS = 10**9
"""Largest number of steps in one run (duration / step): ~3 hours of computing at 10 us per step."""

DEFAULT_BOUNDS = np.array([1e4, 1e3, 1e3, 1e6])
"""Sane-state limits for divergence detection: |position| [m], |nu| [rad/s, m/s], |qd| [rad/s], |actuator|."""

CHUNK_SECONDS = 0.1
"""Wall time aimed at by one call of the compiled RK4 loop. A long held-input segment (a whole run without a
controller) is cut into calls of a bounded number of steps, sized from the measured cost of the previous call,
so that Ctrl-C (``KeyboardInterrupt``, seen only between calls) and ``progress`` respond within a fraction of a
second. The cut does not change the arithmetic: every call continues the same step grid (``t = k h``)."""

FIRST_CHUNK_STEPS = 64
"""Steps of the first compiled RK4 call of a run; later calls are sized from the measured cost."""


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


def _six(value, name: str) -> np.ndarray:
    return checks.optional_vector(value, 6, name, " [moment; force]")


def _quantity_name(index: int, n: int) -> str:
    names = ["x", "y", "z", "qw", "qx", "qy", "qz", "p (roll rate)", "q (pitch rate)", "r (yaw rate)",
             "u (surge velocity)", "v (sway velocity)", "w (heave velocity)"]
    if index < 13:
        return names[index]
    if index < 13 + n:
        return f"q{index - 12}"
    if index < 13 + 2 * n:
        return f"qd{index - 12 - n}"
    return f"actuator state {index - 13 - 2 * n}"


_COMMAND_NAMES = tuple(f"command_{a}" for a in ("K", "M", "N", "X", "Y", "Z"))
"""Logged commanded body wrench ``[K, M, N, X, Y, Z]`` (moments about and forces along the body axes)."""


class _Commands:
    """Turns a controller's wrench into held actuator commands (allocation, thrust -> voltage).

    Fast path every update: the layout's pseudo-inverse (minimum-norm least squares); only when that violates a
    thrust limit does the saturation-aware :func:`~uvms.thrusters.allocation.allocate` run. Healey thrusters get
    the compiled steady-state inverse (thrust -> inflow -> speed -> voltage, clipped to the supply); table
    thrusters the table's inverse (:func:`~uvms.thrusters.table.table_command`, the dead band's centre at zero).
    """

    LABELS = ("K", "M", "N", "X", "Y", "Z")

    def __init__(self, thrusters: tuple):
        self.thrusters = thrusters
        self.m = len(thrusters)
        if self.m:
            from uvms.thrusters.healey import healey_voltage_for_thrust, steady_coefficients
            from uvms.thrusters.layouts import layout_matrix, thrust_limits
            from uvms.thrusters.table import table_command

            self.Lambda = layout_matrix(thrusters)
            self.pinv = np.linalg.pinv(self.Lambda)
            self.lower, self.upper = thrust_limits(thrusters)
            self.healey = [(t.parameters.as_array(), steady_coefficients(t.parameters)) if t.model == "healey"
                           else None for t in thrusters]
            self.voltage = healey_voltage_for_thrust
            self.table = [t.parameters.as_array() if t.model == "table" else None for t in thrusters]
            self.table_command = table_command
            self.names = [f"thrust_cmd_{t.name}" for t in thrusters] + [f"unachieved_{a}" for a in self.LABELS]

    def __call__(self, wrench: np.ndarray) -> tuple[np.ndarray, dict[str, float]]:
        if self.m == 0:
            return np.array(wrench, dtype=float), {}
        thrust = self.pinv @ wrench
        if np.any(thrust < self.lower) or np.any(thrust > self.upper):
            from uvms.thrusters.allocation import allocate

            thrust = allocate(self.Lambda, wrench, self.lower, self.upper).thrust
        residual = wrench - self.Lambda @ thrust
        command = np.zeros(max(self.m, 6))
        thrusts = thrust.tolist()
        for j, T in enumerate(thrusts):
            h = self.healey[j]
            if h is not None:
                command[j] = self.voltage(h[0], h[1], T)
            elif self.table[j] is not None:
                command[j] = self.table_command(self.table[j], T)
            else:
                command[j] = T
        return command, dict(zip(self.names, thrusts + residual.tolist()))


def simulate(model, initial_state: State | None = None, *, duration: float, step: float = 1e-3,
             integrator: str = "rk4", fixed_base: bool = False,
             joint_torques: TorqueSchedule | Callable | np.ndarray | None = None,
             body_wrench=None, ee_wrench=None, current: CurrentTable | Callable | np.ndarray | None = None,
             controller=None, actuation: Actuation | None = None, control_period: float | None = None,
             record_period: float | None = None, rtol: float = 1e-10, atol: float = 1e-12,
             bounds: np.ndarray = DEFAULT_BOUNDS, progress: Callable[[float, float], None] | None = None,
             metadata: dict[str, Any] | None = None) -> Result:
    """Simulate ``duration`` seconds from ``initial_state`` (default: at rest at the origin).

    Args:
        step: integration step [s] (RK4); for an adaptive integrator the recording grid (its own steps are
            at most 50 of these).
        integrator: ``"rk4"`` (compiled, fixed step) or a ``solve_ivp`` method (``"DOP853"``, ``"LSODA"`` ...).
        fixed_base: clamp the vehicle (a land-based arm); released otherwise.
        joint_torques: constant (n,), a :class:`TorqueSchedule`, or a callable ``(t, state) -> (n,)``
            (an arm controller; held over ``control_period``).
        body_wrench: constant external wrench on the vehicle (6,), body axes ``[moment; force]``.
        ee_wrench: constant spatial force on the end effector, end-effector axes (6,).
        current: constant world current (3,), a :class:`CurrentTable`, or a callable ``t -> (3,)``;
            default: the model's environment.
        controller: a vehicle controller (:class:`uvms.control.base.Controller`) or ``None``.
        actuation: thrusters between the controller and the vehicle (default: ideal body wrench).
        control_period: update period of a callable ``joint_torques`` (an arm controller) [s] (default: its
            ``period`` attribute, or 10 ms). A vehicle controller is updated at its own ``period``.
        record_period: sampling of the result [s] (default: every step, at most 20 000 samples).
        progress: ``progress(t, duration)`` called after each segment, and within a long one after every
            compiled call (about every :data:`CHUNK_SECONDS` of computing).

    The result's last row is the state at ``t = duration`` exactly, whatever ``record_period``.
    """
    wall0 = _time.perf_counter()
    checks.model(model)
    n_total = check_steps(duration, step)
    duration = float(duration)
    n = model.n_joints
    state = State.zero(model) if initial_state is None else checks.state(model, initial_state, "initial_state")
    integrator, fixed_base, joint_torques, current, control_period, record_period, rtol, atol, bounds = \
        checks.simulate_arguments(model, integrator, fixed_base, joint_torques, current, controller, actuation,
                                  control_period, record_period, rtol, atol, bounds, progress, metadata)
    actuation = actuation or Actuation()
    act = actuator_kernel(actuation.thrusters)
    n_act = n_actuator_states(act)
    if state.actuator.size != n_act:
        state = state.replace(actuator=np.zeros(n_act))
    if fixed_base:
        state = state.replace(nu=np.zeros(6))
    x = pack(state).astype(float)

    h = duration / n_total
    # -- events on the step grid: controller updates (its own period), arm-command updates (control_period),
    #    and the breakpoints of a torque schedule (snapped to the nearest step)
    arm_callable = callable(joint_torques) and not isinstance(joint_torques, TorqueSchedule)
    ctrl_every = arm_every = 0
    if controller is not None:
        ctrl_every = max(1, int(round((getattr(controller, "period", None) or control_period or 0.01) / h)))
    if arm_callable:
        arm_every = max(1, int(round((control_period or getattr(joint_torques, "period", None) or 0.01) / h)))
    breakpoints = ([int(round(tb / h)) for tb in joint_torques.breakpoints() if 0 < tb < duration]
                   if isinstance(joint_torques, TorqueSchedule) else [])
    events = _events(n_total, (ctrl_every, arm_every), breakpoints)
    if record_period is None:
        record_period = h * max(1, int(np.ceil(n_total / 20000)))
    record_every = max(1, int(round(record_period / h)))

    # -- inputs
    if current is None:
        table = CurrentTable.constant(model.current, model.fluid_acceleration)
    elif isinstance(current, CurrentTable):
        table = current
    elif callable(current):
        table = CurrentTable.from_function(
            lambda t: checks.returned_vector(current(t), 3, "current", " (world frame, m/s)", t), duration, h)
    else:
        table = CurrentTable.constant(current, model.fluid_acceleration)
    # fresh writeable copies: numba compiles read-only arrays (the model's are) as a different type
    env_t = np.array(table.times, dtype=float, order="C")
    env_vc = np.array(table.velocity, dtype=float, order="C").reshape(-1, 3)
    env_af = np.array(table.acceleration, dtype=float, order="C").reshape(-1, 3)

    def torques_at(t: float, st: State) -> np.ndarray:
        if joint_torques is None:
            return np.zeros(n)
        if isinstance(joint_torques, TorqueSchedule):      # breakpoints snap to the nearest step
            return np.array(joint_torques(t + 0.5 * h), dtype=float).reshape(n)
        if callable(joint_torques):
            return checks.returned_vector(joint_torques(t, st), n, "joint_torques", " (one per joint)", t)
        return joint_torques
    f_ext = _six(body_wrench, "body_wrench")
    f_ee = _six(ee_wrench, "ee_wrench")
    commands = _Commands(actuation.thrusters)
    if controller is not None and hasattr(controller, "reset"):
        controller.reset()

    km = model.kernel
    ws = make_workspace(model.n_bodies)
    n_rec = n_total // record_every + 2
    out_t = np.zeros(n_rec)
    out_x = np.zeros((n_rec, x.size))
    out_t[0] = 0.0
    out_x[0] = x
    n_out = 1
    done = 0
    complete = True
    message = ""
    R = np.zeros((3, 3))
    vecs = np.zeros((5, 6))
    thrust = np.zeros(max(len(actuation.thrusters), 1))
    xdot = np.zeros(x.size)
    zero_cmd = np.zeros(max(len(actuation.thrusters), 6))
    rk4_call = None
    chunk_steps = FIRST_CHUNK_STEPS
    tau = np.zeros(n)
    command = zero_cmd
    signals: dict[str, float] = {}
    # (step, tau, signals) of the updates, zero-order hold; an update that holds no recorded row is dropped
    updates: list[tuple[int, np.ndarray, dict[str, float]]] = []
    for event in events:
        t = done * h
        st = unpack(x, n)
        if not arm_callable or done % arm_every == 0:
            tau = torques_at(t, st)
        if controller is not None and done % ctrl_every == 0:
            def true_nu_dot(x=x.copy(), t=t, tau=tau, held=command):
                state_derivative(km, ws, act, x, t, tau, f_ext, f_ee, held, env_t, env_vc, env_af, bool(fixed_base),
                                 xdot, R, vecs, thrust)
                return xdot[7:13].copy()

            out: ControlOutput = controller.update(Measurement(time=t, state=st, joint_torques=tau,
                                                               nu_dot_source=true_nu_dot))
            wrench = checks.returned_vector(getattr(out, "wrench", None), 6, "controller.update().wrench",
                                            " [moment; force]", t)
            command, alloc_signals = commands(wrench)
            signals = dict(out.signals)
            signals.update(zip(_COMMAND_NAMES, wrench.tolist()))
            signals.update(alloc_signals)
        if updates and -(-updates[-1][0] // record_every) * record_every >= done:
            updates.pop()                   # no row recorded at its steps [previous, done): nothing to log
        updates.append((done, tau, signals))
        steps = event - done
        if integrator == "rk4":
            k_done = code = 0
            while k_done < steps and code == 0:       # bounded calls: Ctrl-C and progress between them
                chunk = min(steps - k_done, chunk_steps)
                args = (km, ws, act, x, 0.0, float(h), int(chunk), int(done + k_done), int(record_every), tau, f_ext,
                        f_ee, command, env_t, env_vc, env_af, bool(fixed_base), bounds, out_t, out_x, int(n_out))
                if rk4_call is None:
                    rk4_call = specialised(rk4, *args)
                tic = _time.perf_counter()
                k, n_out, code = rk4_call(*args)
                chunk_steps = _next_chunk(chunk, _time.perf_counter() - tic, chunk_steps)
                k_done += k
                if progress is not None and code == 0 and k_done < steps:
                    progress((done + k_done) * h, duration)
            reason = ""
        else:
            k_done, n_out, code, reason = _adaptive_segment(km, ws, act, x, t, h, steps, record_every, done, tau,
                                                            f_ext, f_ee, command, env_t, env_vc, env_af,
                                                            bool(fixed_base), bounds, out_t, out_x, n_out,
                                                            integrator, rtol, atol)
        done += k_done
        if code != 0:
            complete = False
            idx = abs(code) - 1
            what = reason or ("is not finite" if code < 0 else "left its sane range")
            quantity = "" if reason else f"{_quantity_name(idx, n)} "
            message = (f"simulation diverged at t = {done * h:.4g} s: {quantity}{what}; "
                       f"try a smaller step (now {h:g} s)")
            if n_out == 0 or out_t[n_out - 1] < done * h:
                out_t[n_out] = done * h
                out_x[n_out] = x
                n_out += 1
            break
        if progress is not None:
            progress(done * h, duration)

    if complete:                            # the final state is always a row, at exactly t = duration
        if n_total % record_every:
            out_x[n_out] = x
            n_out += 1
        out_t[n_out - 1] = duration
    out_t = out_t[:n_out]
    out_x = out_x[:n_out]
    # inputs and signals of each row: those of the last update at or before its time (zero-order hold)
    update_times = np.array([u[0] * h for u in updates])
    which = np.clip(np.searchsorted(update_times, out_t + 0.5 * h, side="right") - 1, 0, len(updates) - 1)
    out_tau = np.array([u[1] for u in updates], dtype=float).reshape(len(updates), n)[which]
    sig = _held_signals([u[2] for u in updates], which)
    ee = np.zeros((n_out, 3))
    end_effector_path(km, np.ascontiguousarray(out_x), ee)
    meta = {"integrator": integrator, "step_s": h, "duration_s": duration, "fixed_base": bool(fixed_base),
            "wall_time_s": _time.perf_counter() - wall0, "model": model.name, **_versions(), **(metadata or {})}
    _report_joint_limits(model, out_t, out_x, out_tau, meta)
    return Result(time=out_t, states=out_x, n_joints=n, end_effector=ee, joint_torques=out_tau,
                  signals=sig, complete=complete, message=message, metadata=meta)


def _report_joint_limits(model, t, x, tau, meta: dict) -> None:
    """Joint limits crossed in the run (:func:`uvms.model.limits.joint_limit_crossings`): a warning, and the
    lines under ``metadata["joint_limit_crossings"]``."""
    from uvms.model.limits import joint_limit_crossings

    n = model.n_joints
    lines = joint_limit_crossings(model, t, x[:, 13:13 + n], x[:, 13 + n:13 + 2 * n], tau)
    if lines:
        import warnings

        meta["joint_limit_crossings"] = lines
        warnings.warn(f"{model.name}: {lines[0]}" + (f" (and {len(lines) - 1} more)" if len(lines) > 1 else ""),
                      stacklevel=3)


def check_steps(duration: float, step: float) -> int:
    """The number of steps of a run, ``round(duration / step)``; :class:`~uvms.errors.UvmsInputError` (a
    ``ValueError``) naming the argument unless both are positive finite numbers giving 1 to :data:`MAX_STEPS`."""
    duration = checks.number(duration, "duration", positive=True, unit="s, at least one step")
    step = checks.number(step, "step", positive=True, unit="s")
    n = duration / step
    if not 0.5 <= n <= MAX_STEPS:
        raise checks.fail("step", f"expected 1 to {MAX_STEPS:.0e} steps of {step:g} s in {duration:g} s, "
                                  f"found {n:.3g}")
    return int(round(n))


def _next_chunk(steps: int, seconds: float, current: int) -> int:
    """Steps of the next compiled call: aimed at :data:`CHUNK_SECONDS` from the last call's cost, growing at
    most 4-fold per call (a first call may include one-off costs) and never below 16."""
    if steps < current:                       # a short remainder says nothing new about the cost
        return current
    aim = int(steps * CHUNK_SECONDS / max(seconds, 1e-9))
    return max(16, min(aim, 4 * steps))


def _events(n_total: int, periods: tuple[int, ...], breakpoints: list[int]):
    """The steps at which the loop stops, in order: multiples of each non-zero period (in steps), the
    breakpoints, and ``n_total``; generated one at a time (a long run holds no list of them)."""
    upcoming = {every: every for every in periods if every}
    pending = sorted(b for b in set(breakpoints) if 0 < b < n_total)
    i = 0
    event = 0
    while event < n_total:
        event = min(n_total, *upcoming.values(), pending[i] if i < len(pending) else n_total)
        yield event
        for every in upcoming:
            if upcoming[every] <= event:
                upcoming[every] = (event // every + 1) * every
        while i < len(pending) and pending[i] <= event:
            i += 1


def _held_signals(per_update: list[dict[str, float]], which: np.ndarray) -> dict[str, np.ndarray]:
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


def _versions() -> dict[str, str]:
    import numba
    import scipy

    import uvms

    return {"uvms_version": uvms.__version__, "numpy_version": np.__version__, "scipy_version": scipy.__version__,
            "numba_version": numba.__version__}


def _adaptive_segment(km, ws, act, x, t0, h, steps, record_every, done, tau, f_ext, f_ee, command, env_t, env_vc,
                      env_af, fixed_base, bounds, out_t, out_x, n_out, method, rtol, atol):
    """One held-input segment with ``scipy.integrate.solve_ivp``; records on the same grid as RK4.

    Returns ``(steps_done, n_out, code, reason)`` like :func:`~uvms.sim.integrate.rk4`, with ``reason`` set when
    the solver itself gave up. ``step`` bounds the recording grid; the solver's own steps are at most 50 of them.
    """
    from scipy.integrate import solve_ivp

    n = km.parent.shape[0] - 1
    R = np.zeros((3, 3))
    vecs = np.zeros((5, 6))
    thrust = np.zeros(max(act.kind.shape[0], 1))

    def f(t, y):
        dy = np.zeros(y.size)
        state_derivative(km, ws, act, np.ascontiguousarray(y), t, tau, f_ext, f_ee, command, env_t, env_vc, env_af,
                         fixed_base, dy, R, vecs, thrust)
        return dy

    grid = [k for k in range(done + 1, done + steps + 1) if k % record_every == 0]
    t1 = (done + steps) * h
    t_eval = [min(k * h, t1) for k in grid]
    if not grid or grid[-1] != done + steps:
        t_eval.append(t1)
    sol = solve_ivp(f, (t0, t1), x, method=method, rtol=rtol, atol=atol, max_step=max(h, 1e-6) * 50,
                    t_eval=t_eval)
    for j in range(sol.y.shape[1]):                 # every output sample is checked, as RK4 checks every step
        y = sol.y[:, j].copy()
        y[3:7] /= np.linalg.norm(y[3:7])
        code = check_state(y, n, bounds)
        k = int(round(sol.t[j] / h))
        x[:] = y
        if code != 0:
            return k - done, n_out, code, ""
        if j < len(grid) and n_out < out_t.shape[0]:
            out_t[n_out] = grid[j] * h
            out_x[n_out] = y
            n_out += 1
    if not sol.success:
        k = int(round(sol.t[-1] / h)) if sol.t.size else done
        return k - done, n_out, -1, f"the {method} solver stopped ({sol.message})"
    return steps, n_out, 0, ""
