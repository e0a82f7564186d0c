"""Real logs in: a recorded run read from a log description (``docs/logs.md``).

:class:`Log` (also ``uvms.Log``) reads the description and its CSV streams (:mod:`uvms.logs.schema`,
:mod:`uvms.logs.read`), aligns and resamples them (:mod:`uvms.logs.interpolate`), gives the state at the replay's
start (:mod:`uvms.logs.start`) and scores a simulation against the log (:mod:`uvms.logs.score`). On the Sim floor
(``docs/architecture.md``).
"""

from __future__ import annotations

from uvms.logs.log import Log, Stream
from uvms.logs.score import ReplayScores, Series, score, scores
from uvms.logs.start import initial_state

__all__ = ["Log", "Stream", "ReplayScores", "Series", "score", "scores", "initial_state"]
