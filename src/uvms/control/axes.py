"""Which of the six axes a station keeper controls, and its per-axis parameters (issue 16).

Axes, in the vehicle's body frame: ``surge, sway, heave`` (x, y, z) and ``roll, pitch, yaw`` (about x, y, z).
A controller's ``axes`` parameter lists a subset in any order (the order of its gains and logged signals);
the default is the paper's ``surge, sway, yaw``. A per-axis parameter is one number (every axis) or one
number per listed axis. Errors and surfaces per axis: ``docs/conventions.md``, "Six-axis station keeping",
and :func:`uvms.control.sliding_kernels.pose_kinematics_into`.

Set points: a world position ``(x, y, z)`` and ZYX Euler attitude ``(roll, pitch, yaw)``, and optionally a list
of waypoints ``[t, x, y, z, roll, pitch, yaw]`` (from time ``t`` on, that pose is held: station keeping at
each waypoint in turn, the desired velocity zero).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from uvms.control.sliding_kernels import AXIS_NAMES
from uvms.errors import UvmsInputError

PAPER_AXES: tuple[str, ...] = ("surge", "sway", "yaw")
"""The paper's controlled axes (the default)."""
ALL_AXES: tuple[str, ...] = AXIS_NAMES
"""Every axis, in slot order."""
TRANSLATIONS = ("surge", "sway", "heave")


def axis_list(value: Any) -> tuple[str, ...]:
    """A converter: a list of distinct axis names (or ``"all"``: the six)."""
    if value == "all":
        return ALL_AXES
    if isinstance(value, str) or not isinstance(value, (list, tuple)) or not value:
        raise ValueError(f"expected a list of axes from {', '.join(ALL_AXES)} (or 'all'), found {value!r}")
    seen: list[str] = []
    for axis in value:
        if axis not in ALL_AXES:
            raise ValueError(f"unknown axis {axis!r}; expected some of {', '.join(ALL_AXES)}")
        if axis in seen:
            raise ValueError(f"axis {axis!r} is named twice")
        seen.append(axis)
    return tuple(seen)


def per_axis(check: Callable[[Any], float]) -> Callable[[Any], float | tuple[float, ...]]:
    """A converter: one number (every axis) or a list of numbers, each through ``check`` (the count is
    checked against the axes by :func:`expand`)."""

    def convert(value: Any):
        if isinstance(value, (list, tuple, np.ndarray)):
            if len(value) == 0:
                raise ValueError("expected a number or one number per axis, found an empty list")
            return tuple(check(x) for x in value)
        return check(value)

    return convert


def expand(value, axes: tuple[str, ...], name: str, default: Callable[[str], float] | None = None
           ) -> tuple[float, ...]:
    """``value`` as one number per axis: a number repeated, a list of ``len(axes)`` numbers as given,
    ``None`` from ``default(axis)``.

    Raises:
        UvmsInputError: a list of the wrong length (one line naming ``controller.parameters.<name>``).
    """
    if value is None:
        return tuple(float(default(a)) for a in axes)
    if isinstance(value, (list, np.ndarray)):
        value = tuple(value)
    if isinstance(value, tuple):
        if len(value) != len(axes):
            raise UvmsInputError(f"expected one number or {len(axes)} numbers (one per axis: {', '.join(axes)}), "
                                 f"found {len(value)}", path=f"controller.parameters.{name}")
        return tuple(float(v) for v in value)
    return (float(value),) * len(axes)


def waypoint_rows(value: Any) -> tuple[tuple[float, ...], ...]:
    """A converter: rows ``[t, x, y, z, roll, pitch, yaw]`` [s, m, rad] with ``0 < t`` strictly increasing."""
    if not isinstance(value, (list, tuple)):
        raise ValueError(f"expected a list of [t, x, y, z, roll, pitch, yaw] rows, found {value!r}")
    rows = []
    for row in value:
        if not isinstance(row, (list, tuple)) or len(row) != 7 or any(
                isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) for v in row):
            raise ValueError(f"expected rows of 7 finite numbers [t, x, y, z, roll, pitch, yaw], found {row!r}")
        rows.append(tuple(float(v) for v in row))
    times = [r[0] for r in rows]
    if any(t <= 0 for t in times) or any(b <= a for a, b in zip(times, times[1:])):
        raise ValueError(f"expected waypoint times > 0 and increasing, found {times}")
    return tuple(rows)


def slots(axes: tuple[str, ...]) -> list[int]:
    """The axis slots (:mod:`uvms.control.sliding_kernels`) of ``axes``."""
    return [AXIS_NAMES.index(a) for a in axes]
