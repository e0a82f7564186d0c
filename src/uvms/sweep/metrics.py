"""Scalar metrics of a sweep's runs: the named metrics of :mod:`uvms.sim.metrics` (their one definition),
under the names the sweep code has always imported."""

from __future__ import annotations

from uvms.sim.metrics import NAMED, STATISTICS, Series, check_metric, compute_metrics, default_metrics

__all__ = ["NAMED", "STATISTICS", "Series", "check_metric", "compute_metrics", "default_metrics"]
