"""The arm's joint encoders: each joint angle (or a prismatic joint's travel) rounded to its resolution::

    q_measured = resolution * round(q / resolution),    resolution = 2 pi / counts_per_turn

(a count's centre: the error is uniform in ``[-resolution/2, resolution/2]``, standard deviation
``resolution / sqrt(12)``; Bernard Widrow and Istvan Kollar, *Quantization Noise*, 2008, ch. 4).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uvms.sensors.base import SensorRecord, Truth, quantised


@dataclass(frozen=True)
class Encoders:
    """``rate`` [Hz]; ``joints`` (names, in the model's order) with their ``indices`` into ``q`` and
    ``resolutions`` [rad or m] (0: exact)."""

    name: str = "encoders"
    rate: float = 50.0
    joints: tuple[str, ...] = ()
    indices: tuple[int, ...] = ()
    resolutions: tuple[float, ...] = ()
    kind = "encoders"

    def errors(self, n_samples: int) -> dict[str, np.ndarray]:
        """None: an encoder's error is its rounding (module docstring)."""
        return {}

    def reading(self, truth: Truth, errors: dict[str, np.ndarray]) -> SensorRecord:
        columns = {name: quantised(np.ascontiguousarray(truth.q[:, j]), res)
                   for name, j, res in zip(self.joints, self.indices, self.resolutions)}
        return SensorRecord(self.name, self.kind, self.name, truth.time, columns)

    def measure(self, truth: Truth) -> SensorRecord:
        return self.reading(truth, {})
