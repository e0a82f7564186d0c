"""A simulated inertial measurement of the vehicle's body acceleration (for the ``smc-ne`` controller).

Sampled once per controller update, ``k = 0, 1, ...``::

    raw_k      = nu_dot_k                          ("acceleration": the true body acceleration)
               = (nu_k - nu_{k-1}) / period        ("finite_difference": differences of measured velocity)
    measured_k = raw_{k - delay} + bias + noise_k  noise_k ~ N(0, noise^2) per component, seeded

``nu_dot = [omega_dot; v_dot]`` is the spatial body acceleration [rad/s^2, m/s^2] (what the dynamics use;
a real accelerometer's specific force would first be corrected for gravity and ``omega x v``). Before
``delay`` samples exist the first sample is repeated (the sensor starts at rest with the vehicle).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from uvms.control.base import Measurement


@dataclass(frozen=True)
class ImuParameters:
    """``noise``: white-noise standard deviation of every component [m/s^2, rad/s^2]; ``bias`` (6,) constant
    offset; ``delay`` in samples; ``seed`` of the noise; ``mode``: ``"acceleration"`` or ``"finite_difference"``."""

    noise: float = 0.0
    bias: tuple[float, ...] = (0.0,) * 6
    delay: int = 0
    seed: int = 0
    mode: str = "acceleration"

    @property
    def is_perfect(self) -> bool:
        """True for the noise-free, unbiased, undelayed true acceleration."""
        return self.noise == 0 and not any(self.bias) and self.delay == 0 and self.mode == "acceleration"


class SimulatedImu:
    """Corrupts :attr:`Measurement.nu_dot` (or differences ``nu``) as in the module docstring."""

    def __init__(self, parameters: ImuParameters | None = None, *, period: float) -> None:
        self.parameters = parameters or ImuParameters()
        if self.parameters.mode not in ("acceleration", "finite_difference"):
            raise ValueError(f"unknown IMU mode {self.parameters.mode!r}")
        self.period = float(period)
        self._bias = np.broadcast_to(np.asarray(self.parameters.bias, dtype=float), (6,)).copy()
        self.reset()

    def reset(self) -> None:
        """Restart the noise sequence and empty the delay line."""
        self._rng = np.random.default_rng(self.parameters.seed)
        self._buffer: deque[np.ndarray] = deque(maxlen=self.parameters.delay + 1)
        self._last_nu: np.ndarray | None = None

    def measure(self, measurement: Measurement) -> np.ndarray:
        """The measured body acceleration (6,) at this update."""
        par = self.parameters
        nu = np.array(measurement.state.nu, dtype=float)
        if par.mode == "acceleration":
            raw = np.array(measurement.nu_dot, dtype=float)
        else:
            raw = np.zeros(6) if self._last_nu is None else (nu - self._last_nu) / self.period
        self._last_nu = nu
        if not self._buffer:
            self._buffer.extend([raw] * (par.delay + 1))
        else:
            self._buffer.append(raw)
        out = self._buffer[0] + self._bias
        if par.noise > 0:
            out = out + self._rng.normal(0.0, par.noise, 6)
        return out
