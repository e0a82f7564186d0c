"""How well a simulated replay follows a log: RMSE of attitude and depth, beside the no-skill score
(``docs/logs.md``, "Scores").

For the N samples ``k`` of a simulation (``sim``) and the log at the same times (``log``), angles in radians,
differences wrapped to ``[-pi, pi)`` (``wrap(a) = (a + pi) mod 2 pi - pi``), ``rms(e) = sqrt(mean(e_k^2))`` (every
sample weighted alike; give a uniform grid):

- ``roll_rmse_deg = rms(wrap(roll_sim - roll_log))``, the same for pitch;
- ``yaw_change_rmse_deg = rms(wrap(wrap(yaw_sim - yaw_sim[0]) - wrap(yaw_log - yaw_log[0])))``: the change of
  yaw from the first sample, since a simulation started from the log's attitude keeps its heading only as well
  as it turns with it;
- ``depth_change_rmse_m = rms((depth_sim - depth_sim[0]) - (depth_log - depth_log[0]))``, depth positive down;
- the no-skill scores ``*_no_skill_*``: the same RMSE for a "simulation" that holds the first sample's value
  (``rms(wrap(roll_log - roll_log[0]))``, ..., ``rms(wrap(yaw_log - yaw_log[0]))``, ``rms(depth_log -
  depth_log[0])``). A model has skill on a quantity when its RMSE is below that quantity's no-skill score.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from uvms.errors import UvmsInputError
from uvms.frames import check_frame, convert_euler


def wrap(angle) -> np.ndarray:
    """Angles [rad] wrapped to ``[-pi, pi)``."""
    return (np.asarray(angle, dtype=float) + math.pi) % (2.0 * math.pi) - math.pi


def rms(error) -> float:
    """``sqrt(mean(error^2))``."""
    e = np.asarray(error, dtype=float)
    return float(np.sqrt(np.mean(e * e)))


@dataclass(frozen=True)
class Series:
    """Attitude and depth sampled at common times: ``roll``, ``pitch``, ``yaw`` [rad] (ZYX, one frame) and
    ``depth`` [m, positive down], each (N,)."""

    roll: np.ndarray
    pitch: np.ndarray
    yaw: np.ndarray
    depth: np.ndarray

    @classmethod
    def checked(cls, size: int | None = None, **values) -> "Series":
        """A series from four equal-length finite vectors (``size`` of them if given), else one line naming the
        argument."""
        arrays = {}
        for name in ("roll", "pitch", "yaw", "depth"):
            a = np.atleast_1d(np.asarray(values[name], dtype=float))
            n = size if size is not None else next(iter(arrays.values())).size if arrays else a.size
            if a.ndim != 1 or a.size != n or n == 0 or not np.all(np.isfinite(a)):
                raise UvmsInputError(f"expected {n} finite values (one per time), found shape {a.shape}"
                                     + ("" if np.all(np.isfinite(a)) else " with non-finite values"), path=name)
            arrays[name] = a
        return cls(**arrays)


@dataclass(frozen=True)
class ReplayScores:
    """The RMSE of a replay against its log and the no-skill scores (module docstring); units in the names."""

    samples: int
    roll_rmse_deg: float
    pitch_rmse_deg: float
    yaw_change_rmse_deg: float
    depth_change_rmse_m: float
    roll_no_skill_rmse_deg: float
    pitch_no_skill_rmse_deg: float
    yaw_change_no_skill_rmse_deg: float
    depth_change_no_skill_rmse_m: float

    def to_dict(self) -> dict[str, float | int]:
        """The scores by name (for ``comparison.json``)."""
        return asdict(self)


def scores(log: Series, sim: Series) -> ReplayScores:
    """The scores of ``sim`` against ``log`` (both at the same N times, angles in the same frame)."""
    if sim.roll.size != log.roll.size:
        raise UvmsInputError(f"expected {log.roll.size} simulated samples (as the log's), found {sim.roll.size}",
                             path="sim")
    log_yaw, sim_yaw = wrap(log.yaw - log.yaw[0]), wrap(sim.yaw - sim.yaw[0])
    log_depth = log.depth - log.depth[0]
    deg = 180.0 / math.pi
    return ReplayScores(
        samples=int(log.roll.size),
        roll_rmse_deg=rms(wrap(sim.roll - log.roll)) * deg,
        pitch_rmse_deg=rms(wrap(sim.pitch - log.pitch)) * deg,
        yaw_change_rmse_deg=rms(wrap(sim_yaw - log_yaw)) * deg,
        depth_change_rmse_m=rms((sim.depth - sim.depth[0]) - log_depth),
        roll_no_skill_rmse_deg=rms(wrap(log.roll - log.roll[0])) * deg,
        pitch_no_skill_rmse_deg=rms(wrap(log.pitch - log.pitch[0])) * deg,
        yaw_change_no_skill_rmse_deg=rms(log_yaw) * deg,
        depth_change_no_skill_rmse_m=rms(log_depth),
    )


def score(log, times, *, roll, pitch, yaw, depth, frame: str | None = None) -> ReplayScores:
    """A simulation's ``roll``, ``pitch``, ``yaw`` [rad] (ZYX, in ``frame``, default the log's) and ``depth``
    [m, positive down] at ``times`` [s from the replay's start] against ``log`` (a :class:`uvms.Log`) sampled at
    the same times (Slerp attitude, linear position)."""
    t = log.check_times(times)
    sim = Series.checked(t.size, roll=roll, pitch=pitch, yaw=yaw, depth=depth)
    frame = check_frame(frame if frame is not None else log.frame, "frame")
    table = log.resample(t)
    euler = convert_euler(table[["roll_rad", "pitch_rad", "yaw_rad"]].to_numpy(), log.frame, frame)
    reference = Series(roll=euler[:, 0], pitch=euler[:, 1], yaw=euler[:, 2], depth=table["depth_m"].to_numpy())
    return scores(reference, sim)
