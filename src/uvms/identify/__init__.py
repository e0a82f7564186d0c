"""Identification from logs: fit named model parameters (:mod:`uvms.model.parameters`) to logged trials by
least squares on the simulation error (``docs/logs.md``, "Identification").

- :mod:`uvms.identify.experiment`: :class:`Experiment` (one trial's start, inputs and measured signals) and the
  signal definitions;
- :mod:`uvms.identify.fit`: :func:`identify` and its labelled :class:`Identification`;
- :mod:`uvms.identify.write`: the fitted model written as a model file that records how it was fitted.
"""

from uvms.identify.experiment import SIGNALS, Experiment
from uvms.identify.fit import FitOptions, Identification, identify

__all__ = ["SIGNALS", "Experiment", "FitOptions", "Identification", "identify"]
