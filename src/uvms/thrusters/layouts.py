"""Bundled thruster layouts for the paper vehicle (cube of side 0.596 m, centre of mass at the origin).

Body axes: x forward, y starboard, z down; positions from the centre of mass [m], unit directions.

=============  ================================================================================================
name           thrusters
=============  ================================================================================================
``paper``      ``surge_port`` at (0, -0.15, 0) and ``surge_starboard`` at (0, +0.15, 0), both along +x; ``heave``
               at the origin along +z. Produces X, Z and N (yaw by differential surge); **no sway force Y**,
               which the paper's controller nevertheless commands.
``paper-sway`` ``paper`` plus ``sway`` at the origin along +y: produces X, Y, Z and N. The bundled default.
``ideal``      no thrusters: the commanded body wrench is applied as it is (``layout("ideal") == ()``).
=============  ================================================================================================

All thrusters default to the Healey model (:mod:`uvms.thrusters.healey`) with the default parameters.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Literal

import numpy as np

from uvms.errors import UvmsInputError
from uvms.thrusters.allocation import allocation_matrix
from uvms.thrusters.first_order import FirstOrderParameters
from uvms.thrusters.healey import HealeyParameters
from uvms.thrusters.ideal import IdealParameters
from uvms.thrusters.table import (
    STANDARD_GRAVITY,
    TableThrusterParameters,
    load_thruster_table,
    t200_table,
)

ThrusterKind = Literal["healey", "first_order", "ideal", "table"]
ThrusterParameters = HealeyParameters | FirstOrderParameters | IdealParameters | TableThrusterParameters

_PARAMETER_TYPES: dict[str, type] = {
    "healey": HealeyParameters,
    "first_order": FirstOrderParameters,
    "ideal": IdealParameters,
    "table": TableThrusterParameters,
}
TABLE_PARAMETERS = ("time_constant",)
"""Parameters of a ``model: table`` thruster in a model file (the table itself is under ``table``)."""
DEFAULT_TABLE_TIME_CONSTANT = 0.1
"""Default lag ``tau`` [s] of a table thruster; datasheets do not give one (``docs/models.md``)."""

DEFAULT_LAYOUT = "paper-sway"
VEHICLE_SIDE = 0.596
"""Side of the paper vehicle's cube [m]."""


@dataclass(frozen=True)
class Thruster:
    """One thruster: where it is, where it pushes, and its dynamic model.

    Attributes:
        name: label, unique within a layout.
        position: (3,) point of application in the vehicle frame, from the centre of mass [m].
        direction: (3,) unit thrust direction in the vehicle frame (normalised on construction).
        model: ``"healey"``, ``"first_order"``, ``"ideal"`` or ``"table"`` (datasheet table, whose
            parameters must be given).
        parameters: the model's parameters; ``None`` means the model's defaults.
    """

    name: str
    position: tuple[float, float, float]
    direction: tuple[float, float, float]
    model: ThrusterKind = "healey"
    parameters: ThrusterParameters | None = None

    def __post_init__(self) -> None:
        if self.model not in _PARAMETER_TYPES:
            raise UvmsInputError(f"thruster model must be one of {sorted(_PARAMETER_TYPES)}, got {self.model!r}",
                                 path=f"thrusters.{self.name}.model")
        position = np.asarray(self.position, dtype=float)
        direction = np.asarray(self.direction, dtype=float)
        if position.shape != (3,) or not np.all(np.isfinite(position)):
            raise UvmsInputError(f"position must be 3 finite numbers, got {self.position!r}",
                                 path=f"thrusters.{self.name}.position")
        norm = float(np.linalg.norm(direction)) if direction.shape == (3,) else 0.0
        if not (np.isfinite(norm) and norm > 1e-12):
            raise UvmsInputError(f"direction must be 3 finite numbers, not all zero, got {self.direction!r}",
                                 path=f"thrusters.{self.name}.direction")
        object.__setattr__(self, "position", tuple(float(x) for x in position))
        object.__setattr__(self, "direction", tuple(float(x) for x in direction / norm))
        expected = _PARAMETER_TYPES[self.model]
        if self.parameters is None:
            if self.model == "table":
                raise UvmsInputError("a 'table' thruster needs its TableThrusterParameters",
                                     path=f"thrusters.{self.name}.parameters")
            object.__setattr__(self, "parameters", expected())
        elif not isinstance(self.parameters, expected):
            raise UvmsInputError(f"a {self.model!r} thruster needs {expected.__name__}, got "
                                 f"{type(self.parameters).__name__}", path=f"thrusters.{self.name}.parameters")

    @property
    def max_thrust(self) -> float:
        """Largest steady forward thrust [N] (the models but ``table`` are odd: symmetric limits)."""
        assert self.parameters is not None  # filled in by __post_init__
        return float(self.parameters.max_thrust)

    @property
    def min_thrust(self) -> float:
        """Most negative steady thrust [N]: ``-max_thrust``, or a table's reverse end."""
        if isinstance(self.parameters, TableThrusterParameters):
            return self.parameters.min_thrust
        return -self.max_thrust


_LAYOUTS: dict[str, tuple[Thruster, ...]] = {
    "paper": (
        Thruster("surge_port", (0.0, -0.15, 0.0), (1.0, 0.0, 0.0)),
        Thruster("surge_starboard", (0.0, 0.15, 0.0), (1.0, 0.0, 0.0)),
        Thruster("heave", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
    ),
    "ideal": (),
}
_LAYOUTS["paper-sway"] = _LAYOUTS["paper"] + (Thruster("sway", (0.0, 0.0, 0.0), (0.0, 1.0, 0.0)),)


def _table_thruster(spec, index: int, base, source: str | None) -> Thruster:
    """A ``model: table`` thruster: the bundled T200, a CSV beside the model file, or an inline table."""
    from pathlib import Path

    where = f"thrusters[{index}]"
    values = dict(spec.parameters or {})
    for key in values:
        if key not in TABLE_PARAMETERS:
            raise UvmsInputError(f"unknown table parameter; expected one of: {', '.join(TABLE_PARAMETERS)}",
                                 source, f"{where}.parameters.{key}")
    if spec.max_thrust is not None:
        raise UvmsInputError("max_thrust follows from the table; remove it", source, f"{where}.max_thrust")
    tau = values.get("time_constant", DEFAULT_TABLE_TIME_CONSTANT)
    if not tau > 0:
        raise UvmsInputError(f"expected a positive time constant [s], found {tau:g}", source,
                             f"{where}.parameters.time_constant")
    table = spec.table
    if isinstance(table, str):
        if table.lower() == "t200":
            parameters = t200_table(tau)
        else:
            path = Path(table)
            if not path.is_absolute() and base is not None:
                path = Path(base) / path
            if not path.exists():
                raise UvmsInputError(f"no such thrust table file: {path} (or 't200' for the bundled T200)",
                                     source, f"{where}.table")
            parameters = load_thruster_table(path, time_constant=tau)  # errors name the CSV and its line
    else:
        thrust_name = "thrust_N" if table.thrust_N is not None else "thrust_kgf"
        scale = 1.0 if table.thrust_N is not None else STANDARD_GRAVITY
        thrust = [x * scale for x in (table.thrust_N if table.thrust_N is not None else table.thrust_kgf)]
        try:
            parameters = TableThrusterParameters(table.command, thrust, tau, source=source)
        except UvmsInputError as exc:     # name the model file's field, not the table's column
            field = thrust_name if exc.path == "thrust" else exc.path
            raise UvmsInputError(exc.message, source, f"{where}.table.{field}") from None
    return Thruster(spec.name, tuple(spec.position), tuple(spec.direction), "table", parameters)


def thruster_from_spec(spec, index: int = 0, *, base=None, source: str | None = None) -> Thruster:
    """A :class:`Thruster` from a model file's thruster entry (``uvms.model.schema.ThrusterSpec``).

    ``parameters`` keys are the fields of the model's parameter class (``HealeyParameters`` etc.); for ideal
    and first-order thrusters ``max_thrust`` may also be given at the entry's top level. A ``table`` thruster
    takes ``time_constant`` [s] (default :data:`DEFAULT_TABLE_TIME_CONSTANT`) and reads its ``table``: a CSV
    path is relative to ``base`` (the model file's folder).
    """
    if spec.model == "table":
        return _table_thruster(spec, index, base, source)
    cls = _PARAMETER_TYPES[spec.model]
    values = dict(spec.parameters or {})
    if spec.max_thrust is not None:
        if "max_thrust" not in {f.name for f in fields(cls)}:
            raise UvmsInputError("max_thrust follows from the Healey parameters (supply voltage); remove it",
                                 path=f"thrusters[{index}].max_thrust")
        values.setdefault("max_thrust", spec.max_thrust)
    known = {f.name for f in fields(cls)}
    for key in values:
        if key not in known:
            raise UvmsInputError(f"unknown {spec.model} parameter; expected one of: {', '.join(sorted(known))}",
                                 path=f"thrusters[{index}].parameters.{key}")
    try:
        parameters = cls(**values)
    except (TypeError, ValueError) as exc:
        raise UvmsInputError(str(exc), path=f"thrusters[{index}].parameters") from None
    return Thruster(spec.name, tuple(spec.position), tuple(spec.direction), spec.model, parameters)


def layout_names() -> tuple[str, ...]:
    """Names of the bundled layouts."""
    return tuple(sorted(_LAYOUTS))


def layout(name: str = DEFAULT_LAYOUT) -> tuple[Thruster, ...]:
    """The bundled layout ``name`` (an empty tuple for ``"ideal"``: body-wrench actuation)."""
    try:
        return _LAYOUTS[name]
    except KeyError:
        raise UvmsInputError(f"unknown thruster layout {name!r}; known: {', '.join(layout_names())}") from None


def layout_matrix(thrusters: tuple[Thruster, ...]) -> np.ndarray:
    """``Lambda`` (6, m) of a layout (paper Eq. 11); (6, 0) for no thrusters."""
    if not thrusters:
        return np.zeros((6, 0))
    return allocation_matrix(np.array([t.position for t in thrusters]), np.array([t.direction for t in thrusters]))


def thrust_limits(thrusters: tuple[Thruster, ...]) -> tuple[np.ndarray, np.ndarray]:
    """``(lower, upper)`` (m,) steady thrust limits [N] of a layout, for :func:`~uvms.thrusters.allocation.allocate`."""
    upper = np.array([t.max_thrust for t in thrusters], dtype=float)
    lower = np.array([t.min_thrust for t in thrusters], dtype=float)
    return lower, upper
