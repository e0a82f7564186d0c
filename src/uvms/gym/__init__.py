"""Gymnasium environments of uvms (optional extra: ``pip install uvms[gym]``).

``import uvms.gym`` registers:

- ``uvms/StationKeeping-v0``: :class:`~uvms.gym.station_keeping.StationKeepingEnv` with
  ``gymnasium.make("uvms/StationKeeping-v0", model=..., ...)``, and its vectorised version
  :class:`~uvms.gym.vector.StationKeepingVectorEnv` with
  ``gymnasium.make_vec("uvms/StationKeeping-v0", num_envs=N, ...)`` (the vector entry point: N environments
  stepped together by :class:`~uvms.sim.batch_stepper.BatchSimulator`).

Spaces, reward and options: :mod:`uvms.gym.task` and docs/gym.md.
"""

from __future__ import annotations

import gymnasium

from uvms.gym.task import StationKeepingConfig, Weights

ENV_ID = "uvms/StationKeeping-v0"

if ENV_ID not in gymnasium.registry:
    gymnasium.register(id=ENV_ID, entry_point="uvms.gym.station_keeping:StationKeepingEnv",
                       vector_entry_point="uvms.gym.vector:StationKeepingVectorEnv")

__all__ = ["ENV_ID", "StationKeepingConfig", "Weights"]
