"""Datasheet thruster: steady thrust looked up from a measured table, followed with a first-order lag.

A manufacturer's datasheet gives the steady (bollard) thrust against the command at one supply voltage,
e.g. Blue Robotics' T200 thrust against the ESC pulse width. The model::

    T_ss(c) = linear interpolation of the table at the command c (clipped to the table's range)
    dT/dt   = (T_ss(c) - T) / tau

Forward and reverse thrust are whatever the table says (the T200 gives 5.25 kgf forward but 4.07 kgf reverse
at 16 V), and a dead band is a run of zero thrust. The inverse :func:`table_command` gives the command for a
wanted thrust (the middle of a flat run, e.g. the dead band's centre for zero thrust), for allocators that
compute thrusts.

The table needs at least two points, commands strictly increasing and thrust non-decreasing in the command
(so that more command never gives less thrust and the inverse exists). The datasheet does not give a time
constant: ``tau`` is a model parameter.

Bundled: :func:`t200_table`, Blue Robotics' "T200 Public Performance Data 10-20V (September 2019)", sheet
"16 V" (``data/t200_16v.csv``, kgf converted to N with ``g = 9.80665 m/s^2``). The other voltages of that
spreadsheet are not bundled: their thrust columns dip by up to 0.014 kgf between neighbouring commands
(measurement noise), which the monotonic check refuses.

CSV format (:func:`load_thruster_table`): lines starting with ``#`` are comments; the first other line is a
header naming a ``command`` column (``command`` or ``command_<unit>``) and a thrust column, ``thrust_N`` [N]
or ``thrust_kgf`` [kgf]; other columns are ignored.

The compiled kernels take the flat array of :meth:`TableThrusterParameters.as_array`:
``[tau, n, command_0..command_{n-1}, thrust_0..thrust_{n-1}]`` (indices ``P_TIME_CONSTANT``, ``P_N_POINTS``,
``P_TABLE``).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np
from numba import njit

from uvms.errors import UvmsInputError, show

P_TIME_CONSTANT, P_N_POINTS, P_TABLE = 0, 1, 2
STANDARD_GRAVITY = 9.80665
"""[m/s^2], the kgf-to-newton factor (CGPM 1901)."""

T200_VOLTAGE = 16.0
T200_SOURCE = ('Blue Robotics, "T200 Public Performance Data 10-20V (September 2019)", sheet "16 V" '
               "(PWM [us] against Force [kgf])")


def _check_table(command: np.ndarray, thrust: np.ndarray, source: str | None,
                 command_name: str = "command", thrust_name: str = "thrust") -> None:
    """One-line :class:`UvmsInputError` naming ``source`` and the column for a table that cannot be used."""
    if command.ndim != 1 or thrust.ndim != 1 or command.size != thrust.size:
        raise UvmsInputError(f"expected two columns of equal length, got {command.size} commands and "
                             f"{thrust.size} thrusts", source, command_name)
    if command.size < 2:
        raise UvmsInputError(f"expected at least two table points, got {command.size}", source, command_name)
    for name, col in ((command_name, command), (thrust_name, thrust)):
        bad = np.flatnonzero(~np.isfinite(col))
        if bad.size:
            raise UvmsInputError(f"expected finite numbers, got {show(col[bad[0]])} at point {bad[0] + 1}",
                                 source, name)
    steps = np.diff(command)
    if np.any(steps <= 0):
        i = int(np.flatnonzero(steps <= 0)[0])
        raise UvmsInputError(f"commands must increase strictly, but point {i + 2} ({command[i + 1]:g}) follows "
                             f"{command[i]:g}", source, command_name)
    dips = np.diff(thrust)
    if np.any(dips < 0):
        i = int(np.flatnonzero(dips < 0)[0])
        raise UvmsInputError(f"thrust must not decrease as the command increases, but it falls from "
                             f"{thrust[i]:g} to {thrust[i + 1]:g} at point {i + 2}", source, thrust_name)


@dataclass(frozen=True, eq=False)
class TableThrusterParameters:
    """A thruster described by its steady thrust table and a first-order lag.

    Attributes:
        command: (n,) commands, strictly increasing (any unit, e.g. ESC pulse width [us]).
        thrust: (n,) steady thrust at each command [N], non-decreasing.
        time_constant: ``tau`` [s], > 0.
        voltage: supply voltage the table was measured at [V] (information; ``nan`` if unknown).
        source: where the table came from (file or document), used in error messages.
    """

    command: np.ndarray
    thrust: np.ndarray
    time_constant: float
    voltage: float = math.nan
    source: str | None = None

    def __post_init__(self) -> None:
        command = np.array(self.command, dtype=float)
        thrust = np.array(self.thrust, dtype=float)
        _check_table(command, thrust, self.source)
        tau = float(self.time_constant)
        if not (math.isfinite(tau) and tau > 0):
            raise UvmsInputError(f"expected a positive time constant [s], got {show(self.time_constant)}",
                                 self.source, "time_constant")
        command.setflags(write=False)
        thrust.setflags(write=False)
        object.__setattr__(self, "command", command)
        object.__setattr__(self, "thrust", thrust)
        object.__setattr__(self, "time_constant", tau)
        object.__setattr__(self, "voltage", float(self.voltage))

    @property
    def max_thrust(self) -> float:
        """Largest forward thrust of the table [N]."""
        return float(self.thrust[-1])

    @property
    def min_thrust(self) -> float:
        """Most negative (reverse) thrust of the table [N]."""
        return float(self.thrust[0])

    def as_array(self) -> np.ndarray:
        """``[tau, n, command..., thrust...]`` for the kernels."""
        n = self.command.size
        p = np.empty(P_TABLE + 2 * n)
        p[P_TIME_CONSTANT] = self.time_constant
        p[P_N_POINTS] = n
        p[P_TABLE:P_TABLE + n] = self.command
        p[P_TABLE + n:] = self.thrust
        return p


def _parse_csv(text: str, source: str) -> tuple[np.ndarray, np.ndarray]:
    lines = [(i + 1, line) for i, line in enumerate(text.splitlines())
             if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise UvmsInputError("expected a header line and table rows, found no data", source, "header")
    header_no, header_line = lines[0]
    header = [h.strip() for h in next(csv.reader([header_line]))]
    cmd_cols = [i for i, h in enumerate(header) if h == "command" or h.startswith("command_")]
    thrust_cols = [i for i, h in enumerate(header) if h in ("thrust_N", "thrust_kgf")]
    if len(cmd_cols) != 1 or len(thrust_cols) != 1:
        raise UvmsInputError(f"expected one 'command' (or 'command_<unit>') column and one 'thrust_N' or "
                             f"'thrust_kgf' column, got {show(header)}", source, f"line {header_no}")
    ci, ti = cmd_cols[0], thrust_cols[0]
    scale = STANDARD_GRAVITY if header[ti] == "thrust_kgf" else 1.0
    command, thrust = [], []
    for line_no, line in lines[1:]:
        row = [x.strip() for x in next(csv.reader([line]))]
        if len(row) <= max(ci, ti):
            raise UvmsInputError(f"expected {len(header)} columns, got {len(row)}", source, f"line {line_no}")
        for col, out, factor in ((ci, command, 1.0), (ti, thrust, scale)):
            try:
                value = float(row[col])
            except ValueError:
                raise UvmsInputError(f"expected a number, got {show(row[col])}", source,
                                     f"line {line_no}, column {header[col]}") from None
            if not math.isfinite(value):
                raise UvmsInputError(f"expected a finite number, got {show(row[col])}", source,
                                     f"line {line_no}, column {header[col]}")
            out.append(value * factor)
    command_a, thrust_a = np.array(command), np.array(thrust)
    _check_table(command_a, thrust_a, source, header[ci], header[ti])
    return command_a, thrust_a


def load_thruster_table(path: str | Path, *, time_constant: float,
                        voltage: float = math.nan) -> TableThrusterParameters:
    """Read a thrust table CSV (see the module docstring) into :class:`TableThrusterParameters`.

    Raises:
        UvmsInputError: the file cannot be read or parsed, or the table is unusable (fewer than two points,
            commands not strictly increasing, thrust decreasing), one line naming the file and the field.
    """
    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8-sig")   # a spreadsheet's byte-order mark is not data
    except (OSError, UnicodeDecodeError) as exc:
        raise UvmsInputError(f"cannot read the thrust table ({exc.__class__.__name__})", source) from None
    command, thrust = _parse_csv(text, source)
    return TableThrusterParameters(command, thrust, time_constant, voltage, source)


def t200_table(time_constant: float) -> TableThrusterParameters:
    """Blue Robotics T200 at 16 V (bundled datasheet table, thrust in N); ``time_constant`` [s] is yours.

    Command: ESC pulse width [us], 1100-1900 (1500 = stop, dead band 1472-1528 at zero thrust). Thrust:
    -39.91 N (-4.07 kgf) at 1100 us to +51.44 N (5.25 kgf) at 1900 us.
    """
    text = resources.files("uvms.thrusters").joinpath("data/t200_16v.csv").read_text(encoding="utf-8")
    command, thrust = _parse_csv(text, "uvms/thrusters/data/t200_16v.csv")
    return TableThrusterParameters(command, thrust, time_constant, T200_VOLTAGE, T200_SOURCE)


@njit(cache=True)
def table_thrust(p, command):
    """Steady thrust [N] at ``command``: linear interpolation, clipped to the table's end values."""
    n = int(p[P_N_POINTS])
    c0 = P_TABLE
    t0 = P_TABLE + n
    if command <= p[c0]:
        return p[t0]
    if command >= p[c0 + n - 1]:
        return p[t0 + n - 1]
    lo = 0
    hi = n - 1
    while hi - lo > 1:                     # bisection: p[c0 + lo] <= command < p[c0 + hi]
        mid = (lo + hi) // 2
        if p[c0 + mid] <= command:
            lo = mid
        else:
            hi = mid
    x0 = p[c0 + lo]
    x1 = p[c0 + hi]
    y0 = p[t0 + lo]
    y1 = p[t0 + hi]
    return y0 + (y1 - y0) * (command - x0) / (x1 - x0)


@njit(cache=True)
def table_command(p, thrust):
    """Command giving the steady ``thrust`` [N] (inverse of :func:`table_thrust`), thrust clipped to the table.

    Where the table is flat at that thrust (a dead band) the middle of the flat run is returned.
    """
    n = int(p[P_N_POINTS])
    c0 = P_TABLE
    t0 = P_TABLE + n
    target = min(max(thrust, p[t0]), p[t0 + n - 1])
    # first point with thrust >= target
    i = 0
    while p[t0 + i] < target:
        i += 1
    if i == 0:
        c_lo = p[c0]
    else:
        y0 = p[t0 + i - 1]
        y1 = p[t0 + i]
        c_lo = p[c0 + i - 1] + (p[c0 + i] - p[c0 + i - 1]) * (target - y0) / (y1 - y0)
    # last point with thrust <= target
    j = n - 1
    while p[t0 + j] > target:
        j -= 1
    if j == n - 1:
        c_hi = p[c0 + n - 1]
    else:
        y0 = p[t0 + j]
        y1 = p[t0 + j + 1]
        c_hi = p[c0 + j] + (p[c0 + j + 1] - p[c0 + j]) * (target - y0) / (y1 - y0)
    return 0.5 * (c_lo + c_hi)


@njit(cache=True)
def table_derivative(p, T, command):
    """``dT/dt`` [N/s] at thrust ``T`` [N] and ``command``: ``(T_ss(command) - T) / tau``."""
    return (table_thrust(p, command) - T) / p[P_TIME_CONSTANT]


@njit(cache=True)
def table_rk4_step(p, T, command, h):
    """One classical RK4 step of length ``h`` [s] at a constant command; returns the new thrust [N]."""
    k1 = table_derivative(p, T, command)
    k2 = table_derivative(p, T + 0.5 * h * k1, command)
    k3 = table_derivative(p, T + 0.5 * h * k2, command)
    k4 = table_derivative(p, T + h * k3, command)
    return T + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


def table_exact(params: TableThrusterParameters, T0: float, command: float, t):
    """Exact response ``T(t)`` [N] from ``T0`` to a constant command (for tests and plots)."""
    target = float(np.interp(command, params.command, params.thrust))
    return target + (T0 - target) * np.exp(-np.asarray(t, dtype=float) / params.time_constant)


def read_table_text(text: str, *, time_constant: float, source: str = "<table>",
                    voltage: float = math.nan) -> TableThrusterParameters:
    """Like :func:`load_thruster_table`, from CSV text already in memory (``source`` names it in errors)."""
    command, thrust = _parse_csv(text, source)
    return TableThrusterParameters(command, thrust, time_constant, voltage, source)
