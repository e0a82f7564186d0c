"""The sim-against-pool table of the bundled Hinsdale 2023 trials (``docs/logs.md``, "The real robot"): each
held-out trial replayed with a model, scored against the motion capture, beside the authors' own simulation
of that trial scored the same way over the same span.

The authors' simulated trajectory (``traj_alt_*/_alt_*.csv`` of the bundle: log time, ZYX roll ``qs1`` and pitch
``qs2`` in the world z-up frame; ``uvms/data/hinsdale_2023/SOURCE.md``) is interpolated linearly onto the replay's
comparison grid and compared with the same motion-capture attitude as the replay.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

HELD_OUT = "hinsdale_2023/traj_alt_*"
"""The 13 held-out trials (never used by a fit)."""

FIT_SET = "hinsdale_2023/traj0*"
"""The trials a fit may use."""

LOST_TRACKING = ("traj007-1", "traj016-1", "traj019-0")
"""Fit trials whose motion capture lost track (the attitude jumps by 50-96 deg between 40 ms samples, faster
than 690 deg/s; ``docs/logs.md``): left out of the bundled fit."""


@dataclass(frozen=True)
class TrialScore:
    """One held-out trial: the replay's and the authors' RMSE against the motion capture [deg]."""

    trial: str
    pitch: float
    roll: float
    authors_pitch: float
    authors_roll: float
    held_pitch: float
    held_roll: float

    @property
    def beats_authors(self) -> bool:
        """Lower attitude RMSE than the authors' simulation: ``sqrt((roll^2 + pitch^2) / 2)`` of the two RMSEs."""
        return np.hypot(self.pitch, self.roll) < np.hypot(self.authors_pitch, self.authors_roll)


def authors_simulation(log_path: Path):
    """The authors' simulated trajectory of a held-out trial (a pandas DataFrame), next to its log."""
    import pandas as pd

    return pd.read_csv(log_path.parent / f"{log_path.stem.replace('traj', '', 1)}.csv")


def held_out_scores(model, pattern: str = HELD_OUT) -> list[TrialScore]:
    """Every held-out trial replayed with ``model`` and scored beside the authors' simulation."""
    import warnings

    from uvms.logs.bundled import resolve_logs
    from uvms.logs.score import rms, wrap
    from uvms.model.limits import JointLimitWarning
    from uvms.replays.run import replay

    out = []
    for path in resolve_logs(pattern):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", JointLimitWarning)
            rp = replay(model, path)
        theirs = authors_simulation(path)
        t = rp.times + rp.log.start
        deg = np.degrees
        out.append(TrialScore(
            trial=path.stem, pitch=rp.scores.pitch_rmse_deg, roll=rp.scores.roll_rmse_deg,
            authors_pitch=float(deg(rms(wrap(np.interp(t, theirs.time_secs, theirs.qs2) - rp.measured["pitch"])))),
            authors_roll=float(deg(rms(wrap(np.interp(t, theirs.time_secs, theirs.qs1) - rp.measured["roll"])))),
            held_pitch=rp.scores.pitch_no_skill_rmse_deg, held_roll=rp.scores.roll_no_skill_rmse_deg))
    return out


def markdown_table(published: list[TrialScore], fitted: list[TrialScore]) -> str:
    """The per-trial table of ``docs/logs.md`` (pitch and roll RMSE [deg]) with its median row."""
    lines = ["| trial | fit pitch | fit roll | published pitch | published roll | authors' pitch | authors' roll "
             "| held pitch | held roll |", "| --- |" + " ---: |" * 8]
    rows = [(f.trial, f.pitch, f.roll, p.pitch, p.roll, p.authors_pitch, p.authors_roll, p.held_pitch, p.held_roll)
            for p, f in zip(published, fitted)]
    for r in rows:
        lines.append(f"| {r[0]} | " + " | ".join(f"{v:.2f}" for v in r[1:]) + " |")
    medians = np.median(np.array([r[1:] for r in rows]), axis=0)
    lines.append("| **median** | " + " | ".join(f"**{v:.2f}**" for v in medians) + " |")
    return "\n".join(lines)
