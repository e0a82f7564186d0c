"""A pressure (depth) sensor on the vehicle: the hydrostatic pressure at its mount (Fossen, *Handbook of Marine
Craft Hydrodynamics and Motion Control*, 2011, sec. 4.1; the water at rest, waves' dynamic pressure left out)::

    p = p_atm + rho |g| depth + e,       depth = (p_body + R r)_z - surface   (z down; up: surface - z)

``e`` white noise of standard deviation ``noise`` [Pa]; the reading is then rounded to ``resolution`` [Pa].
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from uvms.sensors.base import Mount, SensorRecord, Truth, depth_of, mount_point, quantised, stream

ATMOSPHERE = 101_325.0
"""Standard atmosphere [Pa] (ISO 2533), the default ``p_atm``."""


@dataclass(frozen=True)
class PressureSensor:
    """``rate`` [Hz], ``mount``, fluid ``density`` [kg/m^3], ``atmosphere`` [Pa], ``noise`` [Pa] (standard
    deviation), ``resolution`` [Pa] (0: none), ``seed``."""

    name: str = "pressure"
    rate: float = 10.0
    mount: Mount = field(default_factory=Mount)
    density: float = 1000.0
    atmosphere: float = ATMOSPHERE
    noise: float = 0.0
    resolution: float = 0.0
    seed: int = 0
    kind = "pressure"

    def true_values(self, truth: Truth) -> np.ndarray:
        """(K,) the pressure at the mount without noise [Pa]."""
        depth = depth_of(truth, mount_point(truth, self.mount))
        return self.atmosphere + self.density * float(np.linalg.norm(truth.gravity)) * depth

    def errors(self, n_samples: int) -> dict[str, np.ndarray]:
        """The seeded noise of the first ``n_samples`` samples: ``pressure`` (K,) [Pa] (none when noise-free)."""
        if self.noise > 0:
            return {"pressure": stream(self.seed, 0).standard_normal(int(n_samples)) * self.noise}
        return {}

    def reading(self, truth: Truth, errors: dict[str, np.ndarray]) -> SensorRecord:
        """The samples at ``truth.time``: true pressure plus ``errors`` (rows of :meth:`errors`), rounded."""
        p = self.true_values(truth)
        if "pressure" in errors:
            p = p + errors["pressure"]
        p = quantised(p, self.resolution)
        depth = (p - self.atmosphere) / (self.density * float(np.linalg.norm(truth.gravity)))
        return SensorRecord(self.name, self.kind, self.name, truth.time, {"pressure": p, "depth": depth})

    def measure(self, truth: Truth) -> SensorRecord:
        return self.reading(truth, self.errors(truth.time.shape[0]))
