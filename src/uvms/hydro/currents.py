"""Currents that vary with depth or in space and time: the arrays of :class:`uvms.hydro.flow.Flow`.

- :class:`CurrentProfile`: a velocity table against depth below the mean free surface (linear in depth, held
  beyond the ends), given as a table or built from the power law of DNV-RP-C205 Eq. 4.1.3 (tidal current,
  ``v(d) = v_surface ((h - d) / h)^alpha``, ``alpha = 1/7`` typical) by :func:`power_law_profile`.
- :class:`CurrentField`: a velocity on a grid in ``x, y, z, t`` (trilinear in space, linear in time), read from a
  CSV file (:func:`read_field_csv`) or a NetCDF file through xarray (:func:`read_field_netcdf`, the optional
  extra ``uvms[netcdf]``). ``outside`` says what the flow is at a point off the grid (``docs/environment.md``).

The fluid object evaluates them (``uvms.hydro.flow``); this module only turns user input into checked arrays.
Every refusal is one :class:`~uvms.errors.UvmsInputError` line naming the file and the field.
"""

from __future__ import annotations

import csv
import math
import os
from pathlib import Path
from typing import NamedTuple

import numpy as np

from uvms.errors import UvmsInputError, show

OUTSIDE = ("hold", "zero", "error")
"""What a field is outside its grid: ``hold`` (the nearest grid value, per axis), ``zero`` (no velocity beyond
the uniform part) or ``error`` (the run stops with one line when a body leaves the grid)."""

MAX_PROFILE_POINTS = 10_000
MAX_FIELD_POINTS = 2_000_000
"""Most grid points (``nt nz ny nx``) a field file may hold (3 velocities each: 48 MB)."""
MAX_FIELD_BYTES = 256 * 1024 * 1024
"""Largest field file read [bytes], checked before reading."""
COLUMNS = ("x", "y", "z", "t", "u", "v", "w")
"""The CSV field file's columns: grid point (world, m), time (s), velocity (world, m/s)."""


class CurrentProfile(NamedTuple):
    """A current against depth, added to the uniform current.

    Attributes:
        depth: ``(K,)`` depth below the mean free surface [m], positive down, strictly increasing.
        velocity: ``(K, 3)`` world velocity at each depth [m/s]; linear in between, held beyond the ends.
    """

    depth: np.ndarray
    velocity: np.ndarray


class CurrentField(NamedTuple):
    """A gridded current, added to the uniform current.

    Attributes:
        x, y, z: ``(nx,)``, ``(ny,)``, ``(nz,)`` world grid coordinates [m], each strictly increasing (one
            value: constant along that axis).
        t: ``(nt,)`` times [s], strictly increasing (one value: steady).
        velocity: ``(nt, nz, ny, nx, 3)`` world velocity [m/s].
        outside: one of :data:`OUTSIDE`.
    """

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    t: np.ndarray
    velocity: np.ndarray
    outside: str


# ------------------------------------------------------------------------------------------------ profiles


def current_profile(depth, velocity, *, source: str | None = None, field: str = "profile") -> CurrentProfile:
    """A checked :class:`CurrentProfile` from a table (``depth`` ``(K,)`` [m], ``velocity`` ``(K, 3)`` [m/s]).

    Raises:
        UvmsInputError: non-finite values, depths not strictly increasing, a row count that differs, more than
            :data:`MAX_PROFILE_POINTS` rows (one line naming ``field``).
    """
    d = np.asarray(depth, dtype=float).reshape(-1)
    v = np.asarray(velocity, dtype=float)
    if d.size > MAX_PROFILE_POINTS:
        raise UvmsInputError(f"expected at most {MAX_PROFILE_POINTS} depths, found {d.size}", source, f"{field}.depth")
    if d.size == 0:
        raise UvmsInputError("expected at least one depth, found none", source, f"{field}.depth")
    if v.shape != (d.size, 3):
        raise UvmsInputError(f"expected {d.size} rows of [vx, vy, vz] (one per depth), found shape {v.shape}", source,
                             f"{field}.velocity")
    for name, values in (("depth", d), ("velocity", v)):
        if not np.all(np.isfinite(values)):
            bad = values.ravel()[~np.isfinite(values.ravel())][0]
            raise UvmsInputError(f"expected finite numbers, found {show(bad)}", source, f"{field}.{name}")
    _increasing(d, source, f"{field}.depth")
    return CurrentProfile(depth=d.copy(), velocity=v.copy())


def power_law_profile(surface_velocity, water_depth: float, exponent: float = 1.0 / 7.0, *,
                      points: int = 101) -> CurrentProfile:
    """The power-law profile of DNV-RP-C205 Eq. 4.1.3, ``v(d) = v_surface ((h - d) / h)^alpha`` for depths
    ``0 <= d <= h`` (``h = water_depth``, ``alpha = exponent``; zero at the bottom), as a table.

    The table holds ``points`` depths of equal steps in velocity (``d = h (1 - (j / (points - 1))^(1/alpha))``)
    merged with ``points`` equally spaced depths, so that linear interpolation is within ``|v_surface| /
    (points - 1)`` of the law everywhere (the steep part near the bottom included).

    Raises:
        UvmsInputError: a depth or exponent not positive, a non-finite velocity (one line).
    """
    v0 = np.asarray(surface_velocity, dtype=float).reshape(3)
    if not np.all(np.isfinite(v0)):
        raise UvmsInputError(f"expected a finite velocity, found {show(v0.tolist())}", None, "surface_velocity")
    if not (water_depth > 0.0 and math.isfinite(water_depth)):
        raise UvmsInputError(f"expected a positive finite water depth [m], found {water_depth!r}", None,
                             "water_depth")
    if not (exponent > 0.0 and math.isfinite(exponent)):
        raise UvmsInputError(f"expected a positive exponent, found {exponent!r}", None, "exponent")
    j = np.linspace(0.0, 1.0, points)
    s = np.unique(np.concatenate((j ** (1.0 / exponent), j)))   # s = (h - d) / h, increasing
    d = (water_depth * (1.0 - s))[::-1]
    d[0], d[-1] = 0.0, water_depth
    d = np.unique(d)
    shape = np.clip((water_depth - d) / water_depth, 0.0, 1.0) ** exponent
    return CurrentProfile(depth=d, velocity=shape[:, None] * v0[None, :])


# -------------------------------------------------------------------------------------------------- fields


def current_field(x, y, z, t, velocity, outside: str = "hold", *, source: str | None = None,
                  field: str = "field") -> CurrentField:
    """A checked :class:`CurrentField` from its arrays (shapes as the class says).

    Raises:
        UvmsInputError: an axis not strictly increasing or not finite, a velocity of the wrong shape or with
            NaN, an unknown ``outside``, too many grid points (one line naming the file and the axis).
    """
    if outside not in OUTSIDE:
        raise UvmsInputError(f"expected one of {', '.join(OUTSIDE)}, found {show(outside)}", source,
                             f"{field}.outside")
    axes = {}
    for name, values in (("x", x), ("y", y), ("z", z), ("t", t)):
        a = np.asarray(values, dtype=float).reshape(-1)
        if a.size == 0:
            raise UvmsInputError("expected at least one value, found none", source, f"{field}.{name}")
        if not np.all(np.isfinite(a)):
            raise UvmsInputError("expected finite coordinates, found NaN or inf", source, f"{field}.{name}")
        _increasing(a, source, f"{field}.{name}")
        axes[name] = a.copy()
    shape = (axes["t"].size, axes["z"].size, axes["y"].size, axes["x"].size)
    if math.prod(shape) > MAX_FIELD_POINTS:
        raise UvmsInputError(f"expected at most {MAX_FIELD_POINTS} grid points, found {math.prod(shape)}", source,
                             field)
    v = np.asarray(velocity, dtype=float)
    if v.shape != (*shape, 3):
        raise UvmsInputError(f"expected a velocity of shape (nt, nz, ny, nx, 3) = {(*shape, 3)}, found {v.shape}",
                             source, f"{field}.velocity")
    if not np.all(np.isfinite(v)):
        raise UvmsInputError("expected finite velocities, found NaN or inf", source, f"{field}.velocity")
    return CurrentField(x=axes["x"], y=axes["y"], z=axes["z"], t=axes["t"], velocity=v.copy(), outside=outside)


def read_field_csv(path: str | os.PathLike[str], outside: str = "hold") -> CurrentField:
    """A :class:`CurrentField` from a CSV file with a header naming the columns :data:`COLUMNS` (any order;
    no others): one row per grid point and time, every combination of the distinct ``x, y, z, t`` values
    exactly once (a full grid, rows in any order).

    Raises:
        UvmsInputError: a file too large, unreadable or without the columns; a value that is not a finite number;
            a missing or repeated grid point (one line naming the file and the column or row).
    """
    source = str(path)
    values = _read_csv_columns(Path(path), source)
    axes = {name: np.unique(values[name]) for name in ("x", "y", "z", "t")}
    shape = (axes["t"].size, axes["z"].size, axes["y"].size, axes["x"].size)
    rows = values["x"].size
    if math.prod(shape) > MAX_FIELD_POINTS:
        raise UvmsInputError(f"expected at most {MAX_FIELD_POINTS} grid points, found {math.prod(shape)}", source,
                             "rows")
    if rows != math.prod(shape):
        raise UvmsInputError(f"expected a full grid of {' x '.join(str(n) for n in shape)} (t, z, y, x) = "
                             f"{math.prod(shape)} rows, found {rows} (a ragged or repeated grid)", source, "rows")
    index = tuple(np.searchsorted(axes[name], values[name]) for name in ("t", "z", "y", "x"))
    seen = np.zeros(shape, dtype=bool)
    seen[index] = True
    if not seen.all():  # as many rows as grid points, so a missing point means a repeated one
        missing = np.argwhere(~seen)[0]
        point = {name: axes[name][missing[k]] for k, name in enumerate(("t", "z", "y", "x"))}
        raise UvmsInputError(f"expected every grid point once, found none at x={point['x']:g}, y={point['y']:g}, "
                             f"z={point['z']:g}, t={point['t']:g} (a point is repeated)", source, "rows")
    velocity = np.empty((*shape, 3))
    for k, name in enumerate(("u", "v", "w")):
        velocity[(*index, k)] = values[name]
    return current_field(axes["x"], axes["y"], axes["z"], axes["t"], velocity, outside, source=source, field="file")


def _read_csv_columns(path: Path, source: str) -> dict[str, np.ndarray]:
    _checked_size(path, source)
    try:
        with path.open(newline="", encoding="utf-8") as stream:
            reader = csv.reader(stream)
            header = [h.strip() for h in next(reader, [])]
            if sorted(header) != sorted(COLUMNS):
                raise UvmsInputError(f"expected the columns {', '.join(COLUMNS)} (any order), found "
                                     f"{show(header)}", source, "header")
            columns: list[list[float]] = [[] for _ in header]
            for line, row in enumerate(reader, start=2):
                if not row:
                    continue
                if len(row) != len(header):
                    raise UvmsInputError(f"expected {len(header)} values, found {len(row)}", source, f"line {line}")
                if line - 1 > MAX_FIELD_POINTS:
                    raise UvmsInputError(f"expected at most {MAX_FIELD_POINTS} rows", source, "rows")
                for k, text in enumerate(row):
                    try:
                        value = float(text)
                    except ValueError:
                        raise UvmsInputError(f"expected a number, found {show(text)}", source,
                                             f"line {line}, column {header[k]}") from None
                    if not math.isfinite(value):
                        raise UvmsInputError(f"expected a finite number, found {show(text)}", source,
                                             f"line {line}, column {header[k]}")
                    columns[k].append(value)
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise UvmsInputError(f"cannot read the field file: {' '.join(str(exc).split())}", source) from None
    if not columns[0]:
        raise UvmsInputError("expected at least one row of values, found none", source, "rows")
    return {name: np.array(columns[k]) for k, name in enumerate(header)}


def read_field_netcdf(path: str | os.PathLike[str], outside: str = "hold", *,
                      variables: tuple[str, str, str] = ("u", "v", "w")) -> CurrentField:
    """A :class:`CurrentField` from a NetCDF file read with xarray (install ``uvms[netcdf]``): coordinates
    ``x, y, z`` [m] (world) and ``t`` [s] (numbers, not dates), and the velocity ``variables`` [m/s] over
    those four dimensions (any order; a dimension a variable lacks is a single value).

    Raises:
        UvmsInputError: xarray not installed, a file too large or unreadable, a missing coordinate or variable,
            an axis not strictly increasing, NaN values (one line naming the file and the field).
    """
    source = str(path)
    try:
        import xarray
    except ImportError:
        raise UvmsInputError("reading a NetCDF field needs xarray: pip install 'uvms[netcdf]' (or give a CSV "
                             "field file)", source) from None
    _checked_size(Path(path), source)
    try:
        dataset = xarray.open_dataset(path, decode_times=False)
    except (OSError, ValueError, TypeError, KeyError) as exc:
        raise UvmsInputError(f"cannot read the NetCDF file: {' '.join(str(exc).split())}", source) from None
    with dataset:
        axes = {}
        for name in ("x", "y", "z", "t"):
            if name not in dataset.coords and name not in dataset.variables:
                raise UvmsInputError(f"expected a coordinate {name!r}, found {show(sorted(map(str, dataset.coords)))}",
                                     source, name)
            values = np.asarray(dataset[name].values)
            if values.dtype.kind not in "fiu":
                raise UvmsInputError(f"expected numbers (t in seconds), found values of type {values.dtype}", source,
                                     name)
            axes[name] = values.astype(float).reshape(-1)
        shape = tuple(axes[name].size for name in ("t", "z", "y", "x"))
        if math.prod(shape) > MAX_FIELD_POINTS:
            raise UvmsInputError(f"expected at most {MAX_FIELD_POINTS} grid points, found {math.prod(shape)}", source,
                                 "grid")
        velocity = np.empty((*shape, 3))
        for k, name in enumerate(variables):
            if name not in dataset.data_vars:
                raise UvmsInputError(f"expected a variable {name!r}, found {show(sorted(map(str, dataset.data_vars)))}",
                                     source, name)
            data = dataset[name]
            extra = [d for d in data.dims if d not in ("t", "z", "y", "x")]
            if extra:
                raise UvmsInputError(f"expected dimensions among t, z, y, x, found {show(list(map(str, data.dims)))}",
                                     source, name)
            for dim in ("t", "z", "y", "x"):
                if dim not in data.dims:
                    data = data.expand_dims({dim: dataset[dim].values.reshape(-1)})
            velocity[..., k] = np.broadcast_to(data.transpose("t", "z", "y", "x").values.astype(float), shape)
    for name in ("x", "y", "z", "t"):
        if not np.all(np.isfinite(axes[name])):
            raise UvmsInputError("expected finite coordinates, found NaN or inf", source, name)
        _increasing(axes[name], source, name)
    if not np.all(np.isfinite(velocity)):
        raise UvmsInputError("expected finite velocities, found NaN or inf", source, ", ".join(variables))
    return current_field(axes["x"], axes["y"], axes["z"], axes["t"], velocity, outside, source=source, field="file")


def read_field(path: str | os.PathLike[str], outside: str = "hold") -> CurrentField:
    """A field file by its suffix: ``.csv`` (:func:`read_field_csv`), ``.nc`` / ``.nc4`` / ``.cdf``
    (:func:`read_field_netcdf`)."""
    suffix = Path(path).suffix.lower()
    if suffix == ".csv":
        return read_field_csv(path, outside)
    if suffix in (".nc", ".nc4", ".cdf"):
        return read_field_netcdf(path, outside)
    raise UvmsInputError(f"expected a .csv or .nc field file, found {show(Path(path).name)}", str(path))


def _checked_size(path: Path, source: str) -> int:
    try:
        size = path.stat().st_size
    except OSError as exc:
        raise UvmsInputError(f"cannot read the field file: {' '.join(str(exc).split())}", source) from None
    if size > MAX_FIELD_BYTES:
        raise UvmsInputError(f"expected a field file of at most {MAX_FIELD_BYTES // 2 ** 20} MB, found "
                             f"{size / 2 ** 20:.0f} MB", source)
    return size


def _increasing(values: np.ndarray, source: str | None, field: str) -> None:
    steps = np.diff(values)
    if np.any(steps <= 0.0):
        k = int(np.argmax(steps <= 0.0))
        raise UvmsInputError(f"expected strictly increasing values, found {values[k + 1]:g} after {values[k]:g}",
                             source, field)
