"""A simulated inertial measurement of the vehicle's body acceleration, as the ``smc-ne`` controller reads it
(moved here from ``uvms.control.imu``, which re-exports it; the datasheet IMU of a run is :mod:`uvms.sensors.imu`).

Sampled once per controller update, ``k = 0, 1, ...``::

    raw_k      = nu_dot_k                          ("acceleration": the true body acceleration)
               = (nu_k - nu_{k-1}) / period        ("finite_difference": differences of measured velocity)
    measured_k = raw_{k - delay} + bias + noise_k  noise_k ~ N(0, noise^2) per component, seeded

``nu_dot = [omega_dot; v_dot]`` is the spatial body acceleration [rad/s^2, m/s^2] (what the dynamics use;
a real accelerometer's specific force would first be corrected for gravity and ``omega x v``). Before
``delay`` samples exist the first sample is repeated (the sensor starts at rest with the vehicle).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from uvms.jit import kernel


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


class ImuData(NamedTuple):
    """A compiled simulated IMU: parameters, delay line and pre-drawn noise (memory reset when built)."""

    mode: int                   # ACCELERATION or FINITE_DIFFERENCE
    delay: int                  # [samples]
    period: float               # [s] between samples (the controller's)
    bias: np.ndarray            # (6,)
    noisy: bool
    noise: np.ndarray           # (N, 6) noise of sample k in row k ((1, 6) zeros when noise-free)
    buffer: np.ndarray          # (delay + 1, 6) delay line (a ring)
    last_nu: np.ndarray         # (6,) the previous sample's nu
    count: np.ndarray           # (1,) int64 samples taken
    out: np.ndarray             # (6,) the last measurement


ACCELERATION, FINITE_DIFFERENCE = 0, 1
_MODES = {"acceleration": ACCELERATION, "finite_difference": FINITE_DIFFERENCE}


def imu_data(parameters: ImuParameters, period: float, n_samples: int) -> ImuData:
    """A fresh :class:`ImuData` whose noise table holds the first ``n_samples`` draws of
    ``np.random.default_rng(seed).normal(0, noise, 6)``, in the order the samples take them."""
    par = parameters
    noisy = par.noise > 0
    from uvms.checks import MAX_RECORDED_VALUES

    if noisy and 6 * int(n_samples) > MAX_RECORDED_VALUES:      # the table is drawn before the run: bound it
        from uvms.errors import UvmsInputError

        raise UvmsInputError(f"expected at most {MAX_RECORDED_VALUES // 6:.3g} updates of a noisy IMU (its noise is "
                             f"drawn before the run), found {int(n_samples):.3g}: a shorter run or a longer "
                             f"controller period", path="duration")
    noise = (np.random.default_rng(par.seed).normal(0.0, par.noise, (max(int(n_samples), 1), 6)) if noisy
             else np.zeros((1, 6)))
    return ImuData(mode=_MODES[par.mode], delay=int(par.delay), period=float(period),
                   bias=np.broadcast_to(np.asarray(par.bias, dtype=float), (6,)).copy(), noisy=noisy, noise=noise,
                   buffer=np.zeros((par.delay + 1, 6)), last_nu=np.zeros(6), count=np.zeros(1, dtype=np.int64),
                   out=np.zeros(6))


@kernel
def imu_measure(imu, nu, nu_dot_true):
    """One sample (module docstring) into ``imu.out``: the raw sample (``nu_dot_true``, or
    ``(nu - nu_previous) / period``, 0 at the first) through the delay line (filled with the first sample),
    plus the bias, plus this sample's noise row. Raises if the noise table is exhausted."""
    k = imu.count[0]
    if imu.noisy and k >= imu.noise.shape[0]:
        raise ValueError("the IMU's pre-drawn noise table is exhausted (build the controller with more updates)")
    slots = imu.delay + 1
    write = k % slots
    for j in range(6):
        if imu.mode == ACCELERATION:
            raw = nu_dot_true[j]
        elif k == 0:
            raw = 0.0
        else:
            raw = (nu[j] - imu.last_nu[j]) / imu.period
        imu.last_nu[j] = nu[j]
        if k == 0:
            for i in range(slots):
                imu.buffer[i, j] = raw
        else:
            imu.buffer[write, j] = raw
    oldest = (k + 1) % slots if k > 0 else 0
    for j in range(6):
        value = imu.buffer[oldest, j] + imu.bias[j]
        if imu.noisy:
            value = value + imu.noise[k, j]
        imu.out[j] = value
    imu.count[0] = k + 1


class SimulatedImu:
    """Corrupts :attr:`Measurement.nu_dot` (or differences ``nu``) as in the module docstring (the compiled
    :func:`imu_measure`; the noise table grows as samples are taken, continuing the seeded sequence)."""

    def __init__(self, parameters: ImuParameters | None = None, *, period: float) -> None:
        self.parameters = parameters or ImuParameters()
        if self.parameters.mode not in _MODES:
            raise ValueError(f"unknown IMU mode {self.parameters.mode!r}")
        self.period = float(period)
        self.reset()

    def reset(self) -> None:
        """Restart the noise sequence and empty the delay line."""
        self._rng = np.random.default_rng(self.parameters.seed)
        self.data = imu_data(self.parameters, self.period, 0)
        if self.data.noisy:
            self.data = self.data._replace(noise=self._rng.normal(0.0, self.parameters.noise, (256, 6)))

    def ensure_noise(self, samples: int) -> None:
        """Make the noise table hold at least ``samples`` rows (drawing on from the same generator)."""
        table = self.data.noise
        if self.data.noisy and table.shape[0] < samples:
            more = self._rng.normal(0.0, self.parameters.noise, (max(samples - table.shape[0], table.shape[0]), 6))
            self.data = self.data._replace(noise=np.concatenate([table, more]))

    def measure(self, measurement) -> np.ndarray:
        """The measured body acceleration (6,) at this update (``measurement``: a
        :class:`uvms.control.base.Measurement`, read for ``state.nu`` and ``nu_dot``)."""
        self.ensure_noise(int(self.data.count[0]) + 1)
        nu = np.array(measurement.state.nu, dtype=float)
        nu_dot = np.array(measurement.nu_dot, dtype=float) if self.data.mode == ACCELERATION else np.zeros(6)
        imu_measure(self.data, nu, nu_dot)
        return self.data.out.copy()
