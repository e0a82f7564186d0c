"""Replaying logged trials: :func:`replay` (simulate a log and compare), :func:`plan` (the
:class:`~uvms.identify.experiment.Experiment` of a log), :func:`log_result` (the logged motion as a result)
(``docs/logs.md``, "Replaying")."""

from uvms.replays.run import Replay, log_result, plan, replay

__all__ = ["Replay", "log_result", "plan", "replay"]
