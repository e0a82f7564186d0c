"""The vectorised ``uvms/StationKeeping-v0``: ``num_envs`` environments stepped together on
:class:`uvms.sim.batch_stepper.BatchSimulator` (all compiled loops advanced by one compiled call per thread,
without the GIL), with observations and rewards computed for all rows at once.

``gymnasium.make_vec("uvms/StationKeeping-v0", num_envs=N)`` builds it (the registered vector entry point).
Environment ``k`` behaves as the single :class:`~uvms.gym.station_keeping.StationKeepingEnv` seeded with
``seed + k`` (the same episodes and, for the same actions, the same numbers). Autoreset: next-step mode
(``gymnasium.vector.AutoresetMode.NEXT_STEP``): after an episode ends, the next ``step`` call resets that
environment (its action is ignored) and returns the first observation of the new episode with reward 0.
"""

from __future__ import annotations

import gymnasium
import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from uvms.gym.station_keeping import config_of
from uvms.gym.task import StationKeepingTask


class StationKeepingVectorEnv(VectorEnv):
    """``num_envs`` station-keeping environments (module docstring). Keywords: as
    :class:`~uvms.gym.station_keeping.StationKeepingEnv`'s. ``infos["episode_time"]`` (N,) [s]."""

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}

    def __init__(self, num_envs: int = 1, render_mode: str | None = None, **options) -> None:
        from uvms import checks
        from uvms.sim.batch_stepper import COMMAND, MAX_MEMBERS, BatchSimulator

        if render_mode is not None:
            raise ValueError(f"uvms/StationKeeping-v0 has no render modes, got render_mode={render_mode!r}")
        self.render_mode = None
        options.pop("max_episode_steps", None)          # episodes end at their own duration
        self.num_envs = checks.count(num_envs, "num_envs", minimum=1)
        if self.num_envs > MAX_MEMBERS:
            raise checks.fail("num_envs", f"expected at most {MAX_MEMBERS} environments (the batch simulator's "
                                          f"limit), got {self.num_envs}")
        self.task = task = StationKeepingTask(config_of(options))
        self.single_observation_space, self.single_action_space = task.spaces()
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._rngs = [seeding.np_random(None)[0] for _ in range(self.num_envs)]
        self.episodes = [task.draw(rng) for rng in self._rngs]
        self.batch = BatchSimulator(task.model, self.num_envs, step=task.h, actuation=task.actuation,
                                    inputs=[e.inputs for e in self.episodes],
                                    states=[e.initial_state for e in self.episodes],
                                    threads=task.config.threads)
        self._command = COMMAND
        self._steps = np.zeros(self.num_envs, dtype=np.int64)
        self._ended = np.zeros(self.num_envs, dtype=bool)

    def _new_episode(self, k: int) -> None:
        self.episodes[k] = episode = self.task.draw(self._rngs[k])
        self.batch.reset(k, episode.initial_state, inputs=episode.inputs)
        self._steps[k] = 0
        self._ended[k] = False

    def reset(self, *, seed: int | list[int | None] | None = None, options: dict | None = None):
        """Reset every environment: ``seed`` an int (environment ``k`` gets ``seed + k``), a list of
        ``num_envs`` seeds, or ``None``. Returns ``(obs (N, obs), infos)``."""
        super().reset(seed=int(seed) if isinstance(seed, (int, np.integer)) else None)
        if seed is None:
            seeds = [None] * self.num_envs
        elif isinstance(seed, (int, np.integer)):
            seeds = [int(seed) + k for k in range(self.num_envs)]
        else:
            seeds = list(seed)
            if len(seeds) != self.num_envs:
                raise ValueError(f"expected {self.num_envs} seeds, got {len(seeds)}")
        for k, s in enumerate(seeds):
            if s is not None or seed is None:
                self._rngs[k] = seeding.np_random(s)[0]
            self._new_episode(k)
        return self.task.observe(self.batch.x), {"episode_time": np.zeros(self.num_envs)}

    def step(self, actions):
        """Hold each row of ``actions`` (N, a) for ``dt`` seconds; returns ``(obs, rewards, terminations,
        truncations, infos)``, each with one row per environment. ``actions`` of another shape than
        ``(num_envs, a)``, not numbers or with a NaN or infinite entry: one :class:`~uvms.errors.UvmsInputError`
        line naming ``actions`` (no environment is stepped or reset)."""
        task = self.task
        actions = task.checked_actions(actions, self.num_envs)     # a bad action changes nothing
        ended = self._ended.copy()
        for k in np.flatnonzero(ended):
            self._new_episode(k)
        commands, effort = task.commands(actions)
        active = ~ended
        self.batch.advance(task.substeps, commands, self._command, active)
        self._steps[active] += 1
        obs = task.observe(self.batch.x)
        reward, terminated, truncated = task.evaluate(obs, effort, self.batch.codes, self._steps)
        reward[~active] = 0.0
        terminated &= active
        truncated &= active
        self._ended = terminated | truncated
        return obs, reward, terminated, truncated, {"episode_time": self._steps * task.dt}

    def close_extras(self, **kwargs) -> None:
        self.batch.close()
