"""``uvms/StationKeeping-v0``: hold a vehicle-manipulator system at a pose while its arm moves and a current
pushes it (one environment, on the step API :class:`uvms.sim.stepper.Simulator`).

Spaces, reward and options: :mod:`uvms.gym.task` (:class:`~uvms.gym.task.StationKeepingConfig`) and
docs/gym.md. Each :meth:`~StationKeepingEnv.reset` draws an :class:`~uvms.gym.task.Episode` from the
environment's seeded generator (``reset(seed=...)`` reproduces the episode exactly) and builds the episode's
simulator; each :meth:`~StationKeepingEnv.step` holds the action for ``dt`` seconds (``dt / step`` compiled RK4
steps with the arm's PD tracker inside the compiled loop).
"""

from __future__ import annotations

from dataclasses import fields

import gymnasium
import numpy as np

from uvms.gym.task import Episode, StationKeepingConfig, StationKeepingTask


def config_of(kwargs: dict) -> StationKeepingConfig:
    """A :class:`StationKeepingConfig` from keyword options (unknown keywords: ``TypeError``, as Python's)."""
    known = {f.name for f in fields(StationKeepingConfig)}
    unknown = sorted(set(kwargs) - known)
    if unknown:
        raise TypeError(f"uvms/StationKeeping-v0 got an unexpected keyword argument {unknown[0]!r}")
    return StationKeepingConfig(**kwargs)


class StationKeepingEnv(gymnasium.Env):
    """Station keeping of a vehicle-manipulator system (module docstring).

    Keywords: the fields of :class:`~uvms.gym.task.StationKeepingConfig` (``model``, ``action``, ``dt``,
    ``step``, ``duration``, ``current``, ``arm`` ...).

    Observation: ``Box(-inf, inf, (15 + 2 n + m,), float64)``: position error [m] in world and body axes,
    attitude error rotation vector [rad], body angular [rad/s] and linear [m/s] velocity, joint angles [rad]
    and rates [rad/s], and (thruster modes) the ``m`` thrusters' thrusts [N].
    Action: ``"thrusters"``: ``Box(T_min, T_max, (m,), float64)`` thrust set points [N]; ``"commands"``: the
    thrusters' own commands (e.g. PWM [us]) between the commands of the thrust limits;
    ``"wrench"``: ``Box(-limit, limit, (6,), float64)`` body wrench ``[K M N X Y Z]`` [N m, N]. Actions outside
    the box are clipped; an action of another shape, not numbers, or with a NaN or infinite entry is one
    :class:`~uvms.errors.UvmsInputError` line naming ``action`` (:meth:`StationKeepingTask.checked_actions
    <uvms.gym.task.StationKeepingTask.checked_actions>`).

    Attributes: ``task`` (:class:`~uvms.gym.task.StationKeepingTask`), ``episode`` (the current
    :class:`~uvms.gym.task.Episode`), ``simulator`` (the episode's :class:`~uvms.sim.stepper.Simulator`).
    """

    metadata = {"render_modes": []}

    def __init__(self, render_mode: str | None = None, **options) -> None:
        if render_mode is not None:
            raise ValueError(f"uvms/StationKeeping-v0 has no render modes, got render_mode={render_mode!r}")
        self.render_mode = None
        self.task = StationKeepingTask(config_of(options))
        self.observation_space, self.action_space = self.task.spaces()
        self.episode: Episode | None = None
        self.simulator = None
        self._steps = 0
        self._code = 0

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Draw a new episode (``seed`` reseeds the environment's generator) and return ``(obs, info)``;
        ``info["episode"]`` is the :class:`~uvms.gym.task.Episode` drawn."""
        from uvms.sim.stepper import Simulator

        super().reset(seed=seed)
        task = self.task
        self.episode = task.draw(self.np_random)
        self.simulator = Simulator(task.model, self.episode.initial_state, step=task.h, actuation=task.actuation,
                                   inputs=self.episode.inputs)
        self._steps, self._code = 0, 0
        return self._observation()[0], {"episode": self.episode, "time": 0.0}

    def _observation(self) -> np.ndarray:
        from uvms.sim.integrate import pack

        return self.task.observe(pack(self.simulator.state)[None, :].astype(float))

    def step(self, action):
        """Hold ``action`` for ``dt`` seconds; returns ``(obs, reward, terminated, truncated, info)``."""
        from uvms.errors import SimulationDiverged

        if self.simulator is None:
            raise gymnasium.error.ResetNeeded("call reset() before step()")
        command, effort = self.task.commands(self.task.checked_actions(action))
        try:
            self.simulator.step(self.task.dt, command=command[0])
        except SimulationDiverged:
            self._code = 1
        self._steps += 1
        obs = self._observation()
        reward, terminated, truncated = self.task.evaluate(obs, effort, np.array([self._code]),
                                                           np.array([self._steps]))
        info = {"time": self._steps * self.task.dt}
        return obs[0], float(reward[0]), bool(terminated[0]), bool(truncated[0]), info
