"""The station-keeping task shared by the single and the vectorised Gymnasium environments: its options
(:class:`StationKeepingConfig`), spaces, randomised episodes (:class:`Episode`), and the observation, reward
and end of an episode computed from state vectors, for any number of environments at once (numpy over rows).

Everything is in SI units; state vectors are laid out as :mod:`uvms.state` lays them out
(``[p(3) world | quaternion(4, wxyz, body to world) | nu(6) = [omega; v] body | q(n) | qd(n) | actuator]``,
docs/conventions.md). Rotations: ``R(quaternion)`` maps body to world axes (Hamilton product).

Observation (float64, ``9 + 6 + 2 n + m`` entries; ``m`` thrust states only in the thruster action modes):

==============  =====  ============================================================  =========
entries          size  meaning                                                      unit
==============  =====  ============================================================  =========
position_world      3  ``p - p_target``, world axes (NED)                            m
position_body       3  ``R^T (p - p_target)``, body axes                             m
attitude            3  rotation vector of ``R_target^T R`` (axis times angle), body  rad
omega               3  angular velocity, body axes                                  rad/s
velocity            3  linear velocity, body axes                                   m/s
q                   n  joint angles                                                 rad
qd                  n  joint rates                                                  rad/s
thrust              m  the thrusters' actual thrusts (their lag states)              N
==============  =====  ============================================================  =========

The current and the arm's planned motion are not observed (they are the disturbance).

Reward per step (weights :class:`Weights`)::

    r = -( w_p |p - p_target|^2 + w_a |attitude|^2 + w_v |nu|^2 + w_e mean(u^2) )

with ``u`` the action scaled to [-1, 1] by its bounds (the effort; ``"commands"``: measured from the command of
zero thrust); on termination the reward is further
decreased by ``termination_penalty`` for each step left in the episode (default: the position and attitude
cost at the termination limits, so ending an episode early never pays).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from uvms import checks

DEFAULT_MODEL = "bluerov2_heavy_alpha5"
"""The default model: the bundled BlueROV2 Heavy with a Reach Alpha 5 arm and eight T200 thrusters."""

DEFAULT_ARM_POSES = {"bluerov2_heavy_alpha5": (0.05, 0.4, 0.4, 0.05)}
"""Arm poses [rad] the bundled models are trimmed for (the BlueROV2's trim foam levels it with the arm at this
pose, docs/vehicle_sources.md); other models: all joints at 0 (clipped into the joint limits)."""

OBS_LIMIT = 1e6
"""Observation entries are clipped to +-this (only a diverged state reaches it)."""

DEFAULT_WRENCH_LIMIT = np.array([20.0, 20.0, 20.0, 100.0, 100.0, 100.0])
"""Action bound ``[K M N X Y Z]`` [N m, N] of the ``"wrench"`` mode for a model without thrusters."""

ARM_MODES = ("trajectory", "torque", "hold", "none")
ACTION_MODES = ("thrusters", "commands", "wrench")

ARM_TRACKER_PERIOD = 0.01
"""Update period [s] of the arm's computed-torque tracker (its torques are held in between)."""

MAX_ARM_KNOTS = 100_000
"""Most knots of an episode's arm motion (``duration / arm_period + 1``): a shorter ``arm_period`` is refused."""


@dataclass(frozen=True)
class Weights:
    """Reward weights (module docstring): ``position`` [1/m^2], ``attitude`` [1/rad^2], ``velocity``
    [1/(m/s)^2 and 1/(rad/s)^2], ``effort`` [-] (the action scaled to [-1, 1])."""

    position: float = 1.0
    attitude: float = 1.0
    velocity: float = 0.1
    effort: float = 0.01


@dataclass(frozen=True)
class StationKeepingConfig:
    """Options of ``uvms/StationKeeping-v0`` (keywords of ``gymnasium.make``).

    Attributes:
        model: a :class:`~uvms.model.Model`, or a bundled model name or file (default :data:`DEFAULT_MODEL`).
        action: ``"thrusters"`` (one thrust set point per thruster [N], between each thruster's reverse and
            forward limit; converted to the thruster's command by the inverse of its curve or table, then its
            own lag applies), ``"commands"`` (the thrusters' own commands in their units, e.g. the T200's PWM
            pulse width [us] or a Healey thruster's voltage [V], between the commands of the thrust limits;
            zero effort at the command of zero thrust) or ``"wrench"`` (the body wrench ``[K M N X Y Z]``
            [N m, N], body axes, applied directly: ideal actuation). Default: ``"thrusters"`` when the model
            has thrusters.
        wrench_limit: ``"wrench"`` mode bounds (6,) [N m, N] (default: for a model with thrusters, per axis
            ``sum_i |Lambda[a, i]| max(|T_min,i|, |T_max,i|)``, :data:`DEFAULT_WRENCH_LIMIT` on the axes they
            cannot drive; for a model without thrusters :data:`DEFAULT_WRENCH_LIMIT`).
        dt: duration of one environment step [s] (the action is held over it); a whole number of ``step``.
        step: integration step [s] (compiled RK4; default 5 ms: two steps per environment step. Against 1 ms
            steps, 3 s of random thrusts on the default model differ by 3e-7 m and 1e-6 rad, docs/gym.md).
        duration: episode duration [s]; the episode is truncated after ``round(duration / dt)`` steps.
        target_position: world position to hold [m]; the target attitude is level with ``target_yaw`` [rad].
        initial_position: half-width [m] of the uniform initial offset from the target, per world axis.
        initial_attitude: half-width [rad] of the uniform initial roll, pitch and yaw offsets.
        current: largest current speed [m/s]: each episode draws a constant horizontal world current,
            direction uniform, speed uniform in ``[0, current]``.
        arm: the arm's motion, the disturbance: ``"trajectory"`` (a clamped cubic spline through joint angles
            drawn every ``arm_period`` seconds within ``arm_amplitude`` of ``arm_pose`` and the joint limits,
            tracked by computed torque :class:`~uvms.control.arm.ComputedTorqueArm` with the model's own
            Newton-Euler equations (moving base), gains ``arm_gains = (kp, kd)`` [1/s^2, 1/s], updated every
            :data:`ARM_TRACKER_PERIOD`), ``"torque"``
            (joint torques drawn uniform in ``+-arm_torque`` [N m] (one amplitude or one per joint) every
            ``arm_period`` seconds, no tracking: a light joint spins up, e.g. the Alpha 5's wrist roll passes
            1000 rad/s within 0.2 s at 0.5 N m and the episode ends as diverged; give it a small amplitude),
            ``"hold"`` (the tracker holding ``arm_pose``) or ``"none"`` (no joint torques: the arm falls).
        arm_pose: the arm's start pose (n,) [rad] (default :data:`DEFAULT_ARM_POSES`).
        max_tilt: termination when the body z axis leans more than this from the vertical [rad] (tumbling).
        max_distance: termination when the vehicle is farther than this from the target [m].
        weights: the reward's :class:`Weights`.
        termination_penalty: reward lost per step left when the episode terminates (default module docstring).
        threads: threads of the vectorised environment (default: the machine's cores).
    """

    model: Any = DEFAULT_MODEL
    action: str | None = None
    wrench_limit: Any = None
    dt: float = 0.01
    step: float = 0.005
    duration: float = 20.0
    target_position: Any = (0.0, 0.0, 0.0)
    target_yaw: float = 0.0
    initial_position: float = 0.2
    initial_attitude: float = 0.1
    current: float = 0.1
    arm: str = "trajectory"
    arm_pose: Any = None
    arm_amplitude: float = 0.5
    arm_period: float = 2.0
    arm_torque: Any = 0.5
    arm_gains: tuple = (100.0, 20.0)
    max_tilt: float = np.pi / 3
    max_distance: float = 5.0
    weights: Weights = field(default_factory=Weights)
    termination_penalty: float | None = None
    threads: int | None = None


def rotation_vector_error(target: np.ndarray, quaternion: np.ndarray) -> np.ndarray:
    """(N, 3) rotation vectors [rad] of ``R_target^T R`` (the attitude error in body axes) for a target
    quaternion (4,) and (N, 4) unit quaternions (:func:`uvms.rotations.attitude_error`)."""
    from uvms.rotations import attitude_error

    out = np.zeros((quaternion.shape[0], 3))
    for k in range(quaternion.shape[0]):
        attitude_error(np.asarray(target, dtype=float), np.ascontiguousarray(quaternion[k], dtype=float), out[k])
    return out


@dataclass(frozen=True)
class Episode:
    """One episode's random draw: the initial state, the constant world current [m/s] and the arm input, as
    :class:`~uvms.sim.options.Inputs` for :func:`uvms.simulate` (``inputs``)."""

    initial_state: Any
    current: np.ndarray
    inputs: Any


class StationKeepingTask:
    """The task of a :class:`StationKeepingConfig` for one model (module docstring)."""

    def __init__(self, config: StationKeepingConfig) -> None:
        from uvms.model.load import load_model
        from uvms.model.model import Model
        from uvms.sim.options import Actuation

        self.config = c = config
        model = c.model if isinstance(c.model, Model) else load_model(c.model)
        self.model, self.n_joints = model, model.n_joints
        thrusters = tuple(model.thrusters or ())
        action = c.action or ("thrusters" if thrusters else "wrench")
        if action not in ACTION_MODES:
            raise checks.fail("action", f"expected one of {', '.join(ACTION_MODES)}, got {checks.show(action)}")
        if action != "wrench" and not thrusters:
            raise checks.fail("action", "the model has no thrusters: use action='wrench'")
        self.action = action
        self._setup_timing(c)
        self._setup_arm(c)
        self._setup_reward(c)
        self._setup_action(thrusters, Actuation)

    def _setup_timing(self, c: StationKeepingConfig) -> None:
        self.dt = checks.number(c.dt, "dt", positive=True, unit="s")
        self.h = checks.number(c.step, "step", positive=True, unit="s")
        self.substeps = int(round(self.dt / self.h))
        if self.substeps < 1 or abs(self.substeps * self.h - self.dt) > 1e-9 * self.dt:
            raise checks.fail("dt", f"expected a whole number of integration steps of {self.h:g} s, got {c.dt!r}")
        from uvms.sim.plan import MAX_STEPS
        from uvms.sim.stepper import HORIZON

        if HORIZON / self.h > MAX_STEPS:           # the episode's simulator lays its events out over HORIZON
            raise checks.fail("step", f"expected at least {HORIZON / MAX_STEPS:g} s (at most {MAX_STEPS:.0e} steps in "
                                      f"the simulator's horizon of {HORIZON:g} s), got {c.step!r}")
        duration = checks.number(c.duration, "duration", positive=True, unit="s")
        if duration > HORIZON:
            raise checks.fail("duration", f"expected an episode of at most {HORIZON:g} s (the step API's horizon, "
                                          f"uvms.sim.stepper.HORIZON), got {duration:g} s")
        if self.dt > duration:
            raise checks.fail("dt", f"expected an environment step of at most the episode's duration ({duration:g} s), "
                                    f"got {self.dt:g} s")
        self.max_steps = max(1, int(round(duration / self.dt)))
        for name in ("initial_position", "initial_attitude", "current"):
            checks.number(getattr(c, name), name, nonnegative=True)
        self.target_position = checks.vector(c.target_position, 3, "target_position", " [m]")
        yaw = checks.number(c.target_yaw, "target_yaw", unit="rad")
        self.target_quaternion = np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])

    def _setup_arm(self, c: StationKeepingConfig) -> None:
        n, model = self.n_joints, self.model
        if c.arm not in ARM_MODES:
            raise checks.fail("arm", f"expected one of {', '.join(ARM_MODES)}, got {checks.show(c.arm)}")
        checks.number(c.arm_amplitude, "arm_amplitude", nonnegative=True, unit="rad")
        period = checks.number(c.arm_period, "arm_period", positive=True, unit="s")
        if self.max_steps * self.dt / period + 1 > MAX_ARM_KNOTS:
            raise checks.fail("arm_period", f"expected at most {MAX_ARM_KNOTS} arm knots in the episode "
                                            f"(arm_period >= {self.max_steps * self.dt / (MAX_ARM_KNOTS - 1):.3g} s), "
                                            f"got {period:g} s")
        torque = checks.vector(np.broadcast_to(c.arm_torque, (n,)) if np.ndim(c.arm_torque) == 0 else c.arm_torque,
                               n, "arm_torque", " [N m] (one, or one per joint)")
        if np.any(torque < 0):
            raise checks.fail("arm_torque", f"expected non-negative amplitudes [N m], got {checks.show(c.arm_torque)}")
        self.arm_torque = torque
        gains = checks.vector(c.arm_gains, 2, "arm_gains", " (kp [1/s^2], kd [1/s])")
        if np.any(gains < 0):
            raise checks.fail("arm_gains", f"expected non-negative gains, got {checks.show(c.arm_gains)}")
        self.arm_gains = gains
        pose = c.arm_pose if c.arm_pose is not None else DEFAULT_ARM_POSES.get(model.name, np.zeros(n))
        limits = np.asarray(model.joint_limits, dtype=float)[:, :2] if n else np.zeros((0, 2))
        self.arm_pose = np.clip(checks.vector(pose, n, "arm_pose", " [rad] (one per joint)"), limits[:, 0],
                                limits[:, 1])
        self.joint_box = (np.maximum(limits[:, 0], self.arm_pose - c.arm_amplitude),
                          np.minimum(limits[:, 1], self.arm_pose + c.arm_amplitude))

    def _setup_reward(self, c: StationKeepingConfig) -> None:
        for name in ("max_tilt", "max_distance"):
            checks.number(getattr(c, name), name, positive=True)
        w = c.weights
        if not isinstance(w, Weights):
            raise checks.fail("weights", f"expected a uvms.gym.Weights, got {checks.show(w)}")
        for name in ("position", "attitude", "velocity", "effort"):
            checks.number(getattr(w, name), f"weights.{name}", nonnegative=True)
        self.weights = w
        penalty = c.termination_penalty
        if penalty is None:
            penalty = w.position * c.max_distance ** 2 + w.attitude * c.max_tilt ** 2
        self.termination_penalty = checks.number(penalty, "termination_penalty", nonnegative=True)

    # ---------------------------------------------------------------------------------------- spaces

    def _setup_action(self, thrusters: tuple, actuation_class) -> None:
        from uvms.thrusters.layouts import layout_matrix, thrust_limits

        c = self.config
        self.offset = 0.0
        if self.action in ("thrusters", "commands"):
            from uvms.thrusters.command import thrust_command

            self.actuation = actuation_class(thrusters)
            self.thrust_data = thrust_command(thrusters)
            self.n_thrust_states = len(thrusters)
            self.low, self.high = (np.asarray(a, dtype=float) for a in thrust_limits(thrusters))
            if self.action == "commands":            # the commands of the thrust limits and of zero thrust
                bounds = np.stack([self.low, self.high, np.zeros_like(self.low)])
                commands = np.empty_like(bounds)
                thrust_to_command(self.thrust_data, bounds, commands)
                self.low, self.high, self.offset = commands
            self.scale = np.maximum(np.abs(self.low - self.offset), np.abs(self.high - self.offset))
        else:
            self.actuation = actuation_class()
            if c.wrench_limit is not None:
                limit = checks.vector(c.wrench_limit, 6, "wrench_limit", " [N m, N]")
                if np.any(limit <= 0):
                    raise checks.fail("wrench_limit", "expected 6 positive bounds [N m, N]")
            elif thrusters:
                lower, upper = thrust_limits(thrusters)
                limit = np.abs(layout_matrix(thrusters)) @ np.maximum(np.abs(lower), np.abs(upper))
                limit = np.where(limit > 0.0, limit, DEFAULT_WRENCH_LIMIT)   # axes the thrusters cannot drive
            else:
                limit = DEFAULT_WRENCH_LIMIT.copy()
            self.low, self.high, self.scale = -limit, limit.copy(), limit.copy()
            self.n_thrust_states = 0
        self.obs_size = 15 + 2 * self.n_joints + self.n_thrust_states
        self._R, self._quaternion = np.zeros((3, 3)), np.zeros(4)

    def spaces(self):
        """``(observation_space, action_space)`` of one environment (module docstring; float64 Boxes)."""
        from gymnasium import spaces

        obs = spaces.Box(-np.inf, np.inf, shape=(self.obs_size,), dtype=np.float64)
        act = spaces.Box(self.low.copy(), self.high.copy(), dtype=np.float64)
        return obs, act

    # -------------------------------------------------------------------------------------- episodes

    def draw(self, rng: np.random.Generator) -> Episode:
        """An :class:`Episode` drawn from ``rng`` (initial offset, current, arm motion)."""
        from uvms.sim.options import Inputs
        from uvms.state import State

        c, n = self.config, self.n_joints
        position = self.target_position + rng.uniform(-c.initial_position, c.initial_position, 3)
        euler = np.array([0.0, 0.0, c.target_yaw]) + rng.uniform(-c.initial_attitude, c.initial_attitude, 3)
        state = State.from_euler(self.model, position=position, euler=euler, q=self.arm_pose.copy())
        heading = rng.uniform(0.0, 2.0 * np.pi)
        speed = rng.uniform(0.0, c.current)
        current = np.array([speed * np.cos(heading), speed * np.sin(heading), 0.0])
        knots = np.arange(0.0, self.max_steps * self.dt + c.arm_period, c.arm_period)
        if c.arm == "trajectory" and n:
            angles = rng.uniform(self.joint_box[0], self.joint_box[1], (knots.size, n))
            angles[0] = self.arm_pose
            torques = self._tracker(knots, angles)
        elif c.arm == "torque" and n:
            from uvms.sim.inputs import TorqueSchedule

            torques = TorqueSchedule(knots, rng.uniform(-self.arm_torque, self.arm_torque, (knots.size, n)))
        elif c.arm == "hold" and n:
            torques = self._tracker(np.zeros(1), self.arm_pose[None, :])
        else:
            torques = np.zeros(n)
        return Episode(state, current, Inputs(joint_torques=torques, current=current))

    def _tracker(self, times: np.ndarray, angles: np.ndarray):
        from uvms.control.arm import ComputedTorqueArm, JointTrajectory

        kp, kd = self.arm_gains
        return ComputedTorqueArm(self.model, JointTrajectory(times, angles), kp=kp, kd=kd, base="moving",
                                 period=ARM_TRACKER_PERIOD)

    # ----------------------------------------------------------------------------- actions, observations

    def checked_actions(self, actions, rows: int | None = None) -> np.ndarray:
        """(N, a) float64 actions: one environment's action of the action space's shape ``(a,)`` (``rows``
        ``None``), or ``rows`` environments' ``(rows, a)``. An action of another shape, not numbers (a string,
        ``None``, booleans) or with a NaN or infinite entry is one :class:`~uvms.errors.UvmsInputError` line (a
        ``ValueError``) naming ``action`` (``actions``); finite values outside the box are clipped
        (:meth:`commands`)."""
        a = self.low.size
        what = f" (the action space's {self.action} bounds: shape ({a},))"
        if rows is None:
            return checks.vector(actions, a, "action", what).reshape(1, a)
        return checks.matrix(actions, rows, a, "actions", f" (one action per environment: shape ({rows}, {a}))")

    def commands(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(commands (N, c), effort (N,))`` of (N, a) actions clipped to their bounds: thrust set points
        turned into thruster commands, or the commands or the body wrench themselves."""
        a = np.clip(actions, self.low, self.high)
        effort = np.mean(((a - self.offset) / self.scale) ** 2, axis=1)
        out = np.zeros((a.shape[0], max(a.shape[1], 6)))    # the simulator holds max(m, 6) commands
        if self.action == "thrusters":
            thrust_to_command(self.thrust_data, a, out[:, :a.shape[1]])
        else:
            out[:, :a.shape[1]] = a
        return out, effort

    def observe(self, x: np.ndarray) -> np.ndarray:
        """(N, obs) observations of (N, size) state vectors (module docstring; compiled:
        :func:`uvms.gym.kernels.observe_rows`); non-finite entries (a diverged state) read as 0, and entries
        are clipped to +-:data:`OBS_LIMIT`."""
        from uvms.gym.kernels import observe_rows

        out = np.empty((x.shape[0], self.obs_size))
        observe_rows(x, self.target_position, self.target_quaternion, self.n_joints, self.n_thrust_states,
                     OBS_LIMIT, self._R, self._quaternion, out)
        return out

    def evaluate(self, obs: np.ndarray, effort: np.ndarray, codes: np.ndarray, steps: np.ndarray):
        """``(reward, terminated, truncated)`` (N,) after a step, from the new observations, the effort of the
        actions, the simulators' divergence codes and the steps taken in each episode."""
        w = self.weights
        distance2 = np.sum(obs[:, 0:3] ** 2, axis=1)
        attitude2 = np.sum(obs[:, 6:9] ** 2, axis=1)
        nu2 = np.sum(obs[:, 9:15] ** 2, axis=1)
        reward = -(w.position * distance2 + w.attitude * attitude2 + w.velocity * nu2 + w.effort * effort)
        attitude = obs[:, 6:9]
        # tilt: the angle between the body z axis and the world's, from R_target^T R (target level)
        q = _quaternion_of(attitude)
        tilt = np.arccos(np.clip(1.0 - 2.0 * (q[:, 1] ** 2 + q[:, 2] ** 2), -1.0, 1.0))
        terminated = (codes != 0) | (tilt > self.config.max_tilt) | (distance2 > self.config.max_distance ** 2)
        truncated = ~terminated & (steps >= self.max_steps)
        reward = np.where(terminated, reward - self.termination_penalty * (self.max_steps - steps), reward)
        return reward, terminated, truncated


def _quaternion_of(rotation_vector: np.ndarray) -> np.ndarray:
    """(N, 4) unit quaternions of (N, 3) rotation vectors."""
    angle = np.linalg.norm(rotation_vector, axis=1)
    half = 0.5 * angle
    s = np.where(angle > 1e-12, np.sin(half) / np.where(angle > 1e-12, angle, 1.0), 0.5)
    return np.concatenate([np.cos(half)[:, None], rotation_vector * s[:, None]], axis=1)


def thrust_to_command(data, thrusts: np.ndarray, out: np.ndarray) -> None:
    """Thruster commands (N, m) for steady thrusts (N, m) [N]: the inverse of each thruster's curve or table,
    :func:`uvms.thrusters.command.allocate_command`'s last stage."""
    from uvms.gym.kernels import thrust_commands

    thrust_commands(data.kind, data.params, data.coefficients, thrusts, out)
