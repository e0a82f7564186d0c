"""A prescribed joint motion: joints that follow a table of logged angles exactly (``Inputs(joint_motion=...)``),
while the vehicle moves freely under the reaction (hybrid dynamics, :mod:`uvms.dynamics.hybrid`).

:class:`JointMotion` holds a piecewise-cubic interpolant ``q(t)`` through a table of times and joint
positions, stored as its polynomial pieces (``breaks``, ``coefficients``: on ``[b_k, b_k+1]``,
``q(t) = sum_j c[k, :, j] s^j`` with ``s = t - b_k``), so the compiled loop evaluates ``q``, ``qd = dq/dt`` and
``qdd = d2q/dt2`` at every RK4 stage time (:func:`uvms.sim.prescribed.motion_at`). The pieces are:

- positions only (default): scipy's ``CubicSpline`` (C2: position, rate and acceleration continuous, so the
  torques the motion takes are continuous too), with ``boundary`` its end condition: ``"not-a-knot"`` (default:
  no assumption about the ends), ``"clamped"`` (zero rate at both ends: a log that starts and ends at rest),
  ``"natural"`` (zero acceleration at both ends);
- positions and rates (``rates=``): scipy's ``CubicHermiteSpline``, which matches both at every knot but is only
  C1: the acceleration (and the torque) jumps at the knots;
- ``smoothing=``: scipy's ``make_smoothing_spline`` per joint (the cubic smoothing spline of Wahba / Reinsch,
  C2, with a knot at every row), for a noisy log that an interpolant would follow into its noise (whose second
  derivative, the acceleration, the noise would dominate). ``smoothing="gcv"`` chooses each joint's penalty by
  generalised cross-validation; a number is the penalty ``lam`` itself (units of ``s^3``).

Time: the table's first row is the run's ``t = 0`` (a log's absolute timestamps are shifted by it), and a run
may not last longer than the table: beyond its last row there is nothing to follow, so a longer run is refused
(one line) rather than held or extrapolated. The joints are named by the model's joint names (``joints=``), or
given in the model's joint order; every joint of the model must be in the table.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import numpy as np

from uvms import checks
from uvms.errors import UvmsInputError

MAX_TABLE_BYTES = 64 * 1024 * 1024
"""Largest joint-motion table file read (``from_csv``; 64 MiB: an hour of a 10-joint log at 1 kHz)."""

MAX_ROWS = 5_000_000
"""Most rows of a joint-motion table."""

BOUNDARIES = ("not-a-knot", "clamped", "natural")


@dataclass(frozen=True, eq=False)
class JointMotion:
    """A prescribed joint motion (module docstring). Build with :meth:`from_arrays` or :meth:`from_csv`.

    Attributes:
        breaks: (m + 1,) piece boundaries [s] from the table's first row (``breaks[0] = 0``).
        coefficients: (m, n, 4) each piece's power-basis coefficients per joint, lowest power first
            ([rad], [rad/s], [rad/s^2], [rad/s^3]; metres for a prismatic joint).
        joints: the joint of each column (names), or ``None``: the model's joint order.
        kind: ``"cubic"``, ``"hermite"`` or ``"smoothing"`` (module docstring).
    """

    breaks: np.ndarray
    coefficients: np.ndarray
    joints: tuple[str, ...] | None
    kind: str

    @property
    def duration(self) -> float:
        """The time the table covers [s] (last row minus first)."""
        return float(self.breaks[-1])

    @property
    def n_joints(self) -> int:
        return int(self.coefficients.shape[1])

    @classmethod
    def from_arrays(cls, times, angles, *, rates=None, joints: Sequence[str] | None = None,
                    boundary: str = "not-a-knot", smoothing: float | str | None = None) -> "JointMotion":
        """The motion through ``angles`` (K, n) [rad or m] at ``times`` (K,) [s, increasing]; ``rates`` (K, n)
        optional joint rates; ``joints`` the names of the n columns (default: the model's joint order)."""
        t = checks.vector(times, None, "times", " [s]")
        if t.size < 2:
            raise checks.fail("times", f"expected at least 2 rows, got {t.size}")
        if t.size > MAX_ROWS:
            raise checks.fail("times", f"expected at most {MAX_ROWS} rows, got {t.size}")
        steps = np.diff(t)
        if not np.all(steps > 0):
            k = int(np.argmin(steps > 0)) + 1
            raise checks.fail("times", f"expected increasing times, found {t[k]:g} s after {t[k - 1]:g} s (row {k})")
        try:
            one_joint = not isinstance(angles, (str, bytes)) and np.ndim(angles) == 1
        except ValueError:                                  # ragged rows: checks.matrix says so
            one_joint = False
        if one_joint:
            angles = np.reshape(angles, (-1, 1))
        q = checks.matrix(angles, t.size, None, "angles", " [rad or m] (one row per time, one column per joint)")
        if joints is not None:
            joints = tuple(joints)
            if not all(isinstance(j, str) for j in joints) or len(set(joints)) != len(joints) \
                    or len(joints) != q.shape[1]:
                raise checks.fail("joints", f"expected {q.shape[1]} distinct joint names (one per column), got "
                                            f"{checks.show(joints)}")
        if boundary not in BOUNDARIES:
            raise checks.fail("boundary", f"expected one of {', '.join(BOUNDARIES)}, got {checks.show(boundary)}")
        from scipy.interpolate import CubicHermiteSpline, CubicSpline, PPoly, make_smoothing_spline

        s = t - t[0]
        if rates is not None:
            if smoothing is not None:
                raise checks.fail("rates", "expected rates or smoothing, not both (a smoothing spline makes its own)")
            if q.shape[1] == 1 and np.shape(rates) == (t.size,):
                rates = np.reshape(rates, (-1, 1))
            qd = checks.matrix(rates, t.size, q.shape[1], "rates", " (one row per time, one column per joint)")
            pp, kind = CubicHermiteSpline(s, q, qd, axis=0), "hermite"
        elif smoothing is not None:
            lam = None if smoothing == "gcv" else checks.number(smoothing, "smoothing", positive=True, unit="s^3")
            pieces = [PPoly.from_spline(make_smoothing_spline(s, q[:, j], lam=lam)) for j in range(q.shape[1])]
            # the smoothing spline's B-spline repeats its end knots: keep the pieces inside [s_0, s_K-1]
            keep = (pieces[0].x[:-1] >= s[0]) & (pieces[0].x[:-1] < s[-1]) & (np.diff(pieces[0].x) > 0)
            x = np.append(pieces[0].x[:-1][keep], s[-1])
            c = np.stack([p.c[:, keep] for p in pieces], axis=-1)     # (4, m, n)
            pp, kind = PPoly(c, x), "smoothing"
        else:
            pp, kind = CubicSpline(s, q, axis=0, bc_type=boundary), "cubic"
        coefficients = np.ascontiguousarray(np.moveaxis(pp.c[::-1], 0, -1))    # (m, n, 4), lowest power first
        return cls(np.ascontiguousarray(pp.x, dtype=float), coefficients, joints, kind)

    @classmethod
    def from_csv(cls, path: str | os.PathLike[str], *, time: str, columns: dict[str, str] | None = None,
                 **options) -> "JointMotion":
        """The motion of a CSV table file (a header row, then numbers): the times in column ``time`` [s] and,
        per joint, ``columns = {joint name: column}`` (default: every other column, named by the model's joint
        names). ``options`` as :meth:`from_arrays`'s (``boundary``, ``smoothing``). At most
        :data:`MAX_TABLE_BYTES`."""
        header, table = read_table(path)
        source = str(path)
        if columns is None:
            columns = {name: name for name in header if name != time}
        if not isinstance(columns, dict) or not columns:
            raise UvmsInputError(f"expected a mapping of joint names to columns, got {checks.show(columns)}", source,
                                 "columns")
        index = {name: k for k, name in enumerate(header)}
        for name in (time, *columns.values()):
            if name not in index:
                raise UvmsInputError(f"no column {name!r} (columns: {checks.show(header)})", source)
        values = table[:, [index[c] for c in (time, *columns.values())]]
        bad = np.argwhere(~np.isfinite(values))
        if bad.size:
            r, c = bad[0]
            raise UvmsInputError(f"column {(time, *columns.values())[c]!r} row {r + 1}: expected a finite number",
                                 source)
        try:
            return cls.from_arrays(values[:, 0], values[:, 1:], joints=tuple(columns), **options)
        except UvmsInputError as exc:
            raise UvmsInputError(exc.message, source, exc.path) from None

    def __call__(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(q, qd, qdd)`` at time(s) ``t`` [s] (shape ``t.shape + (n,)``), as the compiled loop evaluates them
        (:func:`uvms.sim.prescribed.motion_at`: the piece holding ``t``, the first or last beyond the ends)."""
        t = np.asarray(t, dtype=float)
        k = np.clip(np.searchsorted(self.breaks, t, side="right") - 1, 0, self.breaks.size - 2)
        s = (t - self.breaks[k])[..., None]
        c = self.coefficients[k]
        q = c[..., 0] + s * (c[..., 1] + s * (c[..., 2] + s * c[..., 3]))
        qd = c[..., 1] + s * (2.0 * c[..., 2] + 3.0 * s * c[..., 3])
        qdd = 2.0 * c[..., 2] + 6.0 * s * c[..., 3]
        return q, qd, qdd

    def for_model(self, model, name: str = "joint_motion") -> tuple[np.ndarray, np.ndarray]:
        """``(breaks, coefficients)`` with the columns in ``model``'s joint order; a one-line
        :class:`~uvms.errors.UvmsInputError` naming ``name`` for an unknown or missing joint."""
        n, names = model.n_joints, tuple(model.joint_names)
        if self.joints is None:
            if self.n_joints != n:
                raise checks.fail(name, f"expected {n} columns (one per joint of model {model.name!r}, or named "
                                        f"joints), got {self.n_joints}")
            return self.breaks, self.coefficients
        unknown = [j for j in self.joints if j not in names]
        if unknown:
            raise checks.fail(name, f"unknown joint {unknown[0]!r} (model {model.name!r} has {', '.join(names)})")
        missing = [j for j in names if j not in self.joints]
        if missing:
            raise checks.fail(name, f"expected every joint of model {model.name!r} in the table, missing "
                                    f"{', '.join(repr(j) for j in missing)}")
        order = [self.joints.index(j) for j in names]
        return self.breaks, np.ascontiguousarray(self.coefficients[:, order])


def read_table(path: str | os.PathLike[str]) -> tuple[list[str], np.ndarray]:
    """``(header, values)`` of a CSV table file: one header row of column names, then rows of numbers (an
    empty or non-numeric cell is NaN, refused by the caller where it is used). At most
    :data:`MAX_TABLE_BYTES` and :data:`MAX_ROWS` rows; one-line :class:`~uvms.errors.UvmsInputError` naming the
    file otherwise."""
    import csv

    source = str(path)
    p = Path(path)
    try:
        size = p.stat().st_size
    except OSError as exc:
        raise UvmsInputError(f"cannot read the joint-motion table: {exc.strerror or exc}", source) from None
    if size > MAX_TABLE_BYTES:
        raise UvmsInputError(f"expected a table of at most {MAX_TABLE_BYTES // 2**20} MiB, found "
                             f"{size / 2**20:.1f} MiB", source)
    try:
        with p.open(newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise UvmsInputError(f"cannot read the joint-motion table: {exc}", source) from None
    if not rows:
        raise UvmsInputError("expected a header row of column names, found an empty file", source)
    header = [h.strip() for h in rows[0]]
    body = [r for r in rows[1:] if r]
    if len(body) > MAX_ROWS:
        raise UvmsInputError(f"expected at most {MAX_ROWS} rows, found {len(body)}", source)
    values = np.full((len(body), len(header)), np.nan)
    for r, row in enumerate(body):
        if len(row) != len(header):
            raise UvmsInputError(f"row {r + 1}: expected {len(header)} cells (as the header), found {len(row)}",
                                 source)
        for c, cell in enumerate(row):
            try:
                values[r, c] = float(cell)
            except ValueError:
                pass
    return header, values
