"""Joint limits of a model (URDF ``<limit lower upper effort velocity>``): kept on the model, not enforced by
the dynamics, and reported after a run that crosses them (``docs/models.md``, "Joint limits")."""

from __future__ import annotations

import numpy as np

class JointLimitWarning(UserWarning):
    """A run crossed a joint limit of its model (one warning per run; the lines are in the result's metadata)."""


QUANTITIES = (("position", "q", "rad or m"), ("velocity", "qd", "rad/s or m/s"), ("effort", "tau", "N m or N"))


def joint_limit_crossings(model, time, q, qd, tau) -> list[str]:
    """One line per joint and limit crossed in a run: ``time`` (K,), ``q``, ``qd``, ``tau`` (K, n).

    Position limits are ``[lower, upper]``; velocity and effort limits bound ``|qd|`` and ``|tau|``. A limit
    that is ``inf`` (none given) is never crossed.
    """
    lines: list[str] = []
    time = np.asarray(time, dtype=float)
    limits = model.joint_limits
    for k, name in enumerate(model.joint_names):
        lower, upper, effort, velocity = limits[k]
        checks = (
            ("position", q[:, k], None if lower == -np.inf and upper == np.inf else
             (q[:, k] < lower) | (q[:, k] > upper), f"[{lower:g}, {upper:g}]"),
            ("velocity", qd[:, k], None if velocity == np.inf else np.abs(qd[:, k]) > velocity, f"+/-{velocity:g}"),
            ("effort", tau[:, k], None if effort == np.inf else np.abs(tau[:, k]) > effort, f"+/-{effort:g}"),
        )                                   # None: no limit given (inf), nothing to compare
        for what, values, outside, bounds in checks:
            if outside is not None and np.any(outside):
                first = int(np.argmax(outside))
                lines.append(f"joint {name!r} crossed its {what} limit {bounds} at t = {time[first]:.6g} s "
                             f"(range in the run: {values.min():.6g} to {values.max():.6g})")
    return lines
