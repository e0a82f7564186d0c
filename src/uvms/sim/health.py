"""Run health: did the vehicle stay under control? (``docs/conventions.md``, decision 25)

A run can integrate to the end (``complete``) and still be lost: the vehicle tumbled, or its thrusters sat at
their limits while the controller asked for more. :func:`run_health` reads that from the recorded run:

- ``saturated_fraction[name]``: the fraction of time thruster ``name``'s allocated thrust (the logged signal
  ``thrust_cmd_<name>``) sits at its lower or upper limit (within ``1e-6`` of the limit range);
- ``peak_unachieved`` / ``rms_unachieved``: peak ``|.|`` and RMS per component of the wrench the thrusters could
  not produce (logged ``unachieved_<K..Z>``: commanded minus allocated, [N m, N]) and the peak norms of its
  moment and force parts;
- ``max_abs_roll`` / ``max_abs_pitch``: the largest ``|phi|`` and ``|theta|`` (ZYX Euler angles, absolute) [rad];
- ``station_departure``: how far the vehicle left its station [m]: the distance from the controller's set point,
  ``|e|`` of the logged translational errors ``e_surge``, ``e_sway``, ``e_heave`` (those the controller
  holds: ``R^T (p - p_d)``, docs/conventions.md "Six-axis station keeping"), less its lowest value since the
  set point last changed (the first update, then each waypoint: ``metadata["set_point_changes_s"]``), the
  largest over the run; ``None`` for a run without those signals (no controller holding a position);
- ``unproduced_share_force`` / ``unproduced_share_moment``: the share of the commanded force (moment) that the
  thrusters did not produce, ``sum_k w_k |u_k| / sum_k w_k |c_k|`` over the samples, with ``c`` the force
  (moment) part of the commanded wrench (logged ``command_<K..Z>``) and ``u`` that of the wrench not produced
  (``unachieved_<K..Z>``); a ``|u_k|`` of at most :data:`UNPRODUCED_FLOOR` (the rounding of the allocation's
  arithmetic) counts as produced, so that a command of rounding size (a vehicle resting at its set point) is not
  "unproduced" many times over. Without a thrust limit reached, ``u`` is the component of ``c`` outside the range of
  the layout's matrix ``Lambda`` (:func:`uvms.thrusters.allocation.unachievable_part`); with limits, the
  residual of the bounded least-squares allocation. A layout with no sway thruster and a pure sway command:
  1 (100 %); a pure surge command: 0. ``None`` without thrusters (ideal actuation) or without a controller.

Time fractions and RMS values weight each sample by the time to the next one (the signals are held between
updates, a zero-order hold; the last sample has no weight; NaN samples before the controller's first update
count for nothing). A run is *unhealthy* when ``max(|roll|, |pitch|)`` exceeds ``attitude_limit`` (default 60
deg), a thruster is saturated more than ``saturation_limit`` of the time (default 0.25), the vehicle left its
station by more than ``station_limit`` (default 1 m) or more than ``unproduced_limit`` (default 0.25) of the
commanded force or moment was not produced; its ``warning`` is then one line saying why. The thrust limits
come from the run's ``metadata["thrust_limits_N"]`` (``{name: [lower, upper]}``, written by
:func:`uvms.sim.scenario.run_scenario`) or the ``thrusters`` argument; without either, saturation is not
assessed. The health limits come from ``metadata["health_limits"]`` (a scenario's
``health`` section) unless given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

WRENCH_LABELS = ("K", "M", "N", "X", "Y", "Z")
"""Components of the body wrench ``[moment; force]`` (docs/conventions.md)."""
UNPRODUCED_FLOOR = 1e-9
"""Largest unproduced force [N] or moment [N m] of a sample that counts as produced: the allocation's rounding
(a least-squares projection leaves ``|u| ~ 1e-16`` of a command of rounding size), far below any thrust."""
SATURATION_TOLERANCE = 1e-6
"""A thrust within this fraction of its limit range ``upper - lower`` of a limit counts as saturated."""


TRANSLATION_ERRORS = ("e_surge", "e_sway", "e_heave")
"""Logged position errors of the bundled controllers (``R^T (p - p_d)``, body axes [m]) that locate the station."""


@dataclass(frozen=True)
class HealthLimits:
    """When a run counts as unhealthy: ``max(|roll|, |pitch|) > attitude_limit`` [rad], a thruster saturated
    more than ``saturation_limit`` of the time [-], the vehicle more than ``station_limit`` [m] off its station,
    or more than ``unproduced_limit`` [-] of the commanded force or moment not produced (module docstring)."""

    attitude_limit: float = math.radians(60.0)
    saturation_limit: float = 0.25
    station_limit: float = 1.0
    unproduced_limit: float = 0.25

    @classmethod
    def of(cls, result) -> HealthLimits:
        """The limits in ``result.metadata["health_limits"]``, else the defaults."""
        given = (getattr(result, "metadata", None) or {}).get("health_limits") or {}
        return cls(**{k: float(v) for k, v in given.items() if k in _LIMIT_NAMES})


_LIMIT_NAMES = ("attitude_limit", "saturation_limit", "station_limit", "unproduced_limit")


@dataclass(frozen=True)
class RunHealth:
    """The health of one run (module docstring); :meth:`as_dict` is the JSON form in ``result.json``."""

    healthy: bool
    warning: str
    max_abs_roll: float
    max_abs_pitch: float
    saturated_fraction: dict[str, float] = field(default_factory=dict)
    peak_unachieved: dict[str, float] = field(default_factory=dict)
    rms_unachieved: dict[str, float] = field(default_factory=dict)
    peak_unachieved_moment: float = 0.0
    peak_unachieved_force: float = 0.0
    limits: HealthLimits = HealthLimits()
    station_departure: float | None = None
    unproduced_share_force: float | None = None
    unproduced_share_moment: float | None = None

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready, with units in the keys."""
        return {"healthy": self.healthy, "warning": self.warning, "max_abs_roll_rad": self.max_abs_roll,
                "max_abs_pitch_rad": self.max_abs_pitch, "saturated_fraction": dict(self.saturated_fraction),
                "peak_unachieved": dict(self.peak_unachieved), "rms_unachieved": dict(self.rms_unachieved),
                "peak_unachieved_moment_Nm": self.peak_unachieved_moment,
                "peak_unachieved_force_N": self.peak_unachieved_force,
                "limits": {"attitude_limit_rad": self.limits.attitude_limit,
                           "saturation_limit": self.limits.saturation_limit},
                "station": {"peak_departure_m": self.station_departure, "limit_m": self.limits.station_limit},
                "unproduced": {"force_share": self.unproduced_share_force,
                               "moment_share": self.unproduced_share_moment,
                               "limit": self.limits.unproduced_limit}}


def hold_weights(time: np.ndarray) -> np.ndarray:
    """Weight of each sample under a zero-order hold: the time to the next sample (the last: 0); equal weights
    when the run has a single sample."""
    t = np.asarray(time, dtype=float)
    if t.size < 2:
        return np.ones(t.size)
    return np.append(np.diff(t), 0.0)


def _weighted(values: np.ndarray, weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The finite samples of ``values`` and their weights."""
    ok = np.isfinite(values)
    return values[ok], weights[ok]


def saturated_fraction(thrust: np.ndarray, lower: float, upper: float, weights: np.ndarray) -> float:
    """Fraction of the (weighted) time ``thrust`` sits at ``lower`` or ``upper`` (within
    :data:`SATURATION_TOLERANCE` of ``upper - lower``); 0 without a finite sample."""
    values, w = _weighted(np.asarray(thrust, dtype=float), weights)
    if values.size == 0 or w.sum() <= 0:
        return 0.0
    tol = SATURATION_TOLERANCE * (upper - lower)
    at_limit = (values >= upper - tol) | (values <= lower + tol)
    return float(np.sum(w * at_limit) / np.sum(w))


def weighted_rms(values: np.ndarray, weights: np.ndarray) -> float:
    """Root mean square of the finite samples of ``values`` under the zero-order hold ``weights``."""
    v, w = _weighted(np.asarray(values, dtype=float), weights)
    if v.size == 0 or w.sum() <= 0:
        return 0.0
    return float(np.sqrt(np.sum(w * v * v) / np.sum(w)))


def station_departure(time: np.ndarray, errors: np.ndarray, changes=(), tolerance: float = 0.0) -> float:
    """How far the vehicle left its station [m]: the largest rise of the distance ``|errors[k]|`` ((K, j) position
    errors from the set point [m]) above its lowest value since the set point last changed (``changes``: the
    times [s] it changed after the first update; a sample at ``t >= change - tolerance`` belongs to the new set
    point). NaN samples (before the first update) count for nothing; 0 without a finite sample."""
    t = np.asarray(time, dtype=float)
    distance = np.sqrt(np.sum(np.square(np.asarray(errors, dtype=float).reshape(t.size, -1)), axis=1))
    segment = np.searchsorted(np.sort(np.asarray(changes, dtype=float)) - tolerance, t, side="right")
    worst = 0.0
    for k in np.unique(segment):
        d = distance[(segment == k) & np.isfinite(distance)]
        if d.size:
            worst = max(worst, float(np.max(d - np.minimum.accumulate(d))))
    return worst


def unproduced_share(commanded: np.ndarray, unproduced: np.ndarray, weights: np.ndarray) -> float:
    """``sum_k w_k |u_k| / sum_k w_k |c_k|``: the share of the commanded vectors ``c`` ((K, 3) forces or moments)
    that was not produced (``u``, (K, 3)), each sample weighted by ``weights`` (zero-order hold); rows with a NaN
    count for nothing; a ``|u_k|`` of at most :data:`UNPRODUCED_FLOOR` counts as produced; 0 when nothing was
    commanded."""
    c, u = np.asarray(commanded, dtype=float), np.asarray(unproduced, dtype=float)
    ok = np.all(np.isfinite(c), axis=1) & np.all(np.isfinite(u), axis=1)
    w = np.asarray(weights, dtype=float)[ok]
    total = float(np.sum(w * np.linalg.norm(c[ok], axis=1)))
    missing = np.linalg.norm(u[ok], axis=1)
    missing = np.where(missing <= UNPRODUCED_FLOOR, 0.0, missing)
    return float(np.sum(w * missing) / total) if total > 0 else 0.0


def set_point_metadata(plan) -> dict[str, Any]:
    """``{"set_point_changes_s": [...]}``: the times [s] of the controller updates of a
    :class:`~uvms.sim.plan.RunPlan` at which its set point changes to a waypoint (the first update at or after
    each waypoint's time, within the run), for :func:`station_departure`; ``{}`` without waypoints."""
    parameters = getattr(plan.controller, "parameters", None)
    rows = getattr(parameters, "waypoints", None) or ()
    every, h = plan.control_every, plan.timing.h
    changes = []
    for row in rows:
        t_w = float(row[0])
        if every <= 0 or not math.isfinite(t_w) or t_w <= 0:
            continue
        m = math.ceil(t_w / (every * h))
        while m > 0 and (m - 1) * every * h >= t_w:
            m -= 1
        while m * every * h < t_w:
            m += 1
        if m * every <= plan.timing.n_total:
            changes.append(m * every * h)
    return {"set_point_changes_s": sorted(set(changes))} if changes else {}


def _thrust_limits(result, thrusters) -> dict[str, tuple[float, float]]:
    if thrusters is not None:
        from uvms.thrusters.layouts import thrust_limits

        lower, upper = thrust_limits(tuple(thrusters))
        return {t.name: (float(lo), float(hi)) for t, lo, hi in zip(thrusters, lower, upper)}
    given = (getattr(result, "metadata", None) or {}).get("thrust_limits_N") or {}
    return {str(k): (float(v[0]), float(v[1])) for k, v in given.items()}


def actuation_metadata(actuation) -> dict[str, Any]:
    """``{"thrust_limits_N": {name: [lower, upper]}}`` of an :class:`~uvms.sim.run.Actuation` (``None`` or ideal:
    no thrusters, ``{}``): what a run's metadata needs for :func:`run_health` to assess saturation."""
    thrusters = tuple(getattr(actuation, "thrusters", ()) or ())
    if not thrusters:
        return {}
    from uvms.thrusters.layouts import thrust_limits

    lower, upper = thrust_limits(thrusters)
    return {"thrust_limits_N": {t.name: [float(lo), float(hi)] for t, lo, hi in zip(thrusters, lower, upper)}}


def run_health(result, *, limits: HealthLimits | None = None, thrusters=None) -> RunHealth:
    """The :class:`RunHealth` of a :class:`~uvms.sim.result.Result` (module docstring).

    Args:
        result: the run.
        limits: when the run counts as unhealthy (default: :meth:`HealthLimits.of` the run).
        thrusters: the run's thruster layout (default: the limits in ``result.metadata["thrust_limits_N"]``).
    """
    limits = limits or HealthLimits.of(result)
    weights = hold_weights(result.time)
    euler = result.euler
    roll = float(np.abs(euler[:, 0]).max()) if len(euler) else 0.0
    pitch = float(np.abs(euler[:, 1]).max()) if len(euler) else 0.0

    saturated = {}
    for name, (lower, upper) in _thrust_limits(result, thrusters).items():
        signal = result.signals.get(f"thrust_cmd_{name}")
        if signal is not None:
            saturated[name] = saturated_fraction(signal, lower, upper, weights)

    peak, rms = {}, {}
    for label in WRENCH_LABELS:
        signal = result.signals.get(f"unachieved_{label}")
        if signal is not None:
            values = np.asarray(signal, dtype=float)
            finite = values[np.isfinite(values)]
            peak[label] = float(np.abs(finite).max()) if finite.size else 0.0
            rms[label] = weighted_rms(values, weights)
    moment = force = 0.0
    if len(peak) == 6:
        wrench = np.column_stack([np.asarray(result.signals[f"unachieved_{a}"], dtype=float) for a in WRENCH_LABELS])
        wrench = wrench[np.all(np.isfinite(wrench), axis=1)]
        if len(wrench):
            moment = float(np.linalg.norm(wrench[:, :3], axis=1).max())
            force = float(np.linalg.norm(wrench[:, 3:], axis=1).max())

    departure = None
    present = [name for name in TRANSLATION_ERRORS if name in result.signals]
    if present:
        metadata = getattr(result, "metadata", None) or {}
        departure = station_departure(result.time,
                                      np.column_stack([np.asarray(result.signals[n], dtype=float) for n in present]),
                                      metadata.get("set_point_changes_s") or (),
                                      0.5 * float(metadata.get("step_s") or 0.0))
    share_force = share_moment = None
    commanded = [f"command_{a}" for a in WRENCH_LABELS]
    if len(peak) == 6 and all(name in result.signals for name in commanded):
        c = np.column_stack([np.asarray(result.signals[name], dtype=float) for name in commanded])
        u = np.column_stack([np.asarray(result.signals[f"unachieved_{a}"], dtype=float) for a in WRENCH_LABELS])
        share_moment = unproduced_share(c[:, :3], u[:, :3], weights)
        share_force = unproduced_share(c[:, 3:], u[:, 3:], weights)

    reasons = []
    if max(roll, pitch) > limits.attitude_limit:
        which, angle = ("roll", roll) if roll >= pitch else ("pitch", pitch)
        reasons.append(f"|{which}| reached {math.degrees(angle):.1f} deg (limit "
                       f"{math.degrees(limits.attitude_limit):.4g} deg)")
    over = {k: v for k, v in saturated.items() if v > limits.saturation_limit}
    if over:
        worst = max(over, key=over.__getitem__)
        others = f" and {len(over) - 1} more thruster{'s' if len(over) > 2 else ''}" if len(over) > 1 else ""
        reasons.append(f"thruster {worst}{others} saturated {over[worst] * 100:.0f} % of the time (limit "
                       f"{limits.saturation_limit * 100:.4g} %)")
    if departure is not None and departure > limits.station_limit:
        reasons.append(f"left its station by {departure:.3g} m (limit {limits.station_limit:.4g} m)")
    if share_force is not None and max(share_force, share_moment) > limits.unproduced_limit:
        which, share = ("force", share_force) if share_force >= share_moment else ("moment", share_moment)
        reasons.append(f"{share * 100:.0f} % of the commanded {which} could not be produced by the thrusters "
                       f"(limit {limits.unproduced_limit * 100:.4g} %)")
    warning = ""
    if reasons:
        unproduced = (f"; wrench not produced: peak {force:.3g} N, {moment:.3g} N m" if force > 0 or moment > 0
                      else "")
        warning = "unhealthy run (control lost?): " + "; ".join(reasons) + unproduced
    return RunHealth(healthy=not reasons, warning=warning, max_abs_roll=roll, max_abs_pitch=pitch,
                     saturated_fraction=saturated, peak_unachieved=peak, rms_unachieved=rms,
                     peak_unachieved_moment=moment, peak_unachieved_force=force, limits=limits,
                     station_departure=departure, unproduced_share_force=share_force,
                     unproduced_share_moment=share_moment)


__all__ = ["HealthLimits", "RunHealth", "run_health", "hold_weights", "saturated_fraction", "weighted_rms",
           "station_departure", "unproduced_share", "set_point_metadata"]
