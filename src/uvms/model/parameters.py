"""Named scalar parameters of a built model: what ``uvms identify`` fits and a model file's ``identified:``
block sets (``docs/logs.md``, "Identification"; ``docs/models.md``, "Identified parameters").

A parameter name is ``[<body>:]<quantity>``; the body is the vehicle unless named (a body name of the model,
e.g. ``wrist:buoyancy``). Quantities, all of the *built* body (links merged into it by fixed joints and point
loads included), body axes, SI units:

| quantity | model field | unit |
| --- | --- | --- |
| ``buoyancy`` | ``buoyancy_mass[b]``, displaced-fluid mass ``m_f`` (paper Eq. 7) | kg |
| ``cob.x``, ``cob.y``, ``cob.z`` | ``cob[b]``, centre of buoyancy (Eq. 8) | m |
| ``damping.linear.<axis>`` | diagonal of Fossen's ``D_l`` of the body (``damping_linear[b]``) | N s/m, N m s/rad |
| ``damping.quadratic.<axis>`` | diagonal of ``D_q`` (``damping_quadratic[b]``) | N s^2/m^2, N m s^2/rad^2 |
| ``added_mass.<axis>`` | diagonal of the added-mass matrix about the body origin (``added_mass[b]``) | kg m^2, kg |
| ``disturbance.<axis>`` | vehicle only: ``disturbance_wrench``, body axes (may be negative) | N m, N |
| ``point_load:<name>.mass`` | point mass of the model's point load ``<name>`` (``point_loads``) | kg |
| ``point_load:<name>.fluid_mass`` | displaced-fluid mass of that point load | kg |
| ``point_load:<name>.x``, ``.y``, ``.z`` | its position, in the frame of the body it is on | m |

A ``point_load:`` parameter names a load of the model file's ``point_loads`` (its body is the load's); setting it
folds the old load out of its body and the new one in (:func:`uvms.model.loads.with_point_load_set`), so the
body's totals (mass, centre of mass, inertia, weight, ``buoyancy``, ``cob``) are those of the model built with
the new value. Point loads are set first, then the other quantities: a body's ``buoyancy`` or ``cob`` named too
replaces the total, the loads included.

``<axis>`` is one of ``roll, pitch, yaw, surge, sway, heave``, the entries of uvms's ``[angular; linear]``
6-vectors in that order (Fossen's ``K, M, N, X, Y, Z``). A damping or added-mass *matrix* keeps its
off-diagonal entries; only the named diagonal entry is set. Fossen damping acts about the body's damping point
(``damping_point[b]``), unchanged.

Setting a parameter replaces the built model's value; it never edits the file the model came from. The model's
frame convention is the one its numbers are in (:func:`frame_sign`: the vehicle's ``cob.y`` of a ``ned`` model is
``-cob.y`` of the same robot written ``enu``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from uvms.errors import UvmsInputError

AXES = ("roll", "pitch", "yaw", "surge", "sway", "heave")
"""Axis names of the entries of a ``[angular; linear]`` 6-vector, in order."""

_UNITS_6 = {"damping.linear": ("N m s/rad",) * 3 + ("N s/m",) * 3,
            "damping.quadratic": ("N m s^2/rad^2",) * 3 + ("N s^2/m^2",) * 3,
            "added_mass": ("kg m^2",) * 3 + ("kg",) * 3}
_FIELD_6 = {"damping.linear": "damping_linear", "damping.quadratic": "damping_quadratic",
            "added_mass": "added_mass"}
MAX_PARAMETERS = 64
"""Most parameters one model file or one identification may name."""


@dataclass(frozen=True)
class Parameter:
    """One scalar of a built model: ``body`` (index), ``field`` (the :class:`~uvms.model.Model` attribute),
    ``index`` (into that body's entry), its canonical ``name`` and ``unit``."""

    name: str
    body: int
    field: str
    index: tuple[int, ...]
    unit: str
    load: str | None = None
    """The point load's name, for the ``point_load.*`` fields (``field`` is then ``point_load.mass``,
    ``point_load.fluid_mass`` or ``point_load.position``)."""

    def value(self, model) -> float:
        """This parameter's value in ``model``."""
        if self.load is not None:
            from uvms.model.loads import point_load

            v = getattr(point_load(model, self.load), self.field.partition(".")[2])
            return float(v[self.index[0]] if self.index else v)
        if self.field == "disturbance_wrench":
            return float(model.disturbance_wrench[self.index[0]])
        return float(np.asarray(getattr(model, self.field))[(self.body, *self.index)])


def quantities() -> tuple[str, ...]:
    """Every quantity name a parameter may have (without a body prefix)."""
    out = ["buoyancy", "cob.x", "cob.y", "cob.z"]
    out += [f"{q}.{axis}" for q in _FIELD_6 for axis in AXES]
    out += [f"disturbance.{axis}" for axis in AXES]
    return tuple(out)


_UNITS_DISTURBANCE = ("N m",) * 3 + ("N",) * 3
POINT_LOAD = "point_load"
"""The prefix of a point load's parameters: ``point_load:<name>.mass`` (module docstring)."""


def _point_load_parameter(model, text: str, where: str) -> Parameter:
    """The parameter ``point_load:<name>.<mass|fluid_mass|x|y|z>``."""
    from uvms.model.loads import point_load

    name, _, attribute = text[len(POINT_LOAD) + 1:].rpartition(".")
    if attribute not in ("mass", "fluid_mass", "x", "y", "z") or not name:
        raise UvmsInputError(f"{where}: unknown parameter {text!r}; expected point_load:<name>.mass, "
                             f"point_load:<name>.fluid_mass or point_load:<name>.x|y|z")
    try:
        load = point_load(model, name)
    except UvmsInputError as exc:
        raise UvmsInputError(f"{where}: {text!r}: {exc.message}") from None
    if attribute in ("x", "y", "z"):
        return Parameter(text, load.body, "point_load.position", ("xyz".index(attribute),), "m", name)
    return Parameter(text, load.body, f"point_load.{attribute}", (), "kg", name)


def parameter(model, name: str, where: str = "parameter") -> Parameter:
    """The :class:`Parameter` called ``name`` in ``model``; an unknown name is one line listing the quantities."""
    if not isinstance(name, str) or not name.strip():
        raise UvmsInputError(f"{where}: expected a parameter name such as 'buoyancy' or 'cob.z', got {name!r}")
    text = name.strip()
    if text.startswith(POINT_LOAD + ":"):
        return _point_load_parameter(model, text, where)
    body_name, _, quantity = text.rpartition(":")
    body = 0
    if body_name:
        if body_name not in model.body_names:
            raise UvmsInputError(f"{where}: no body {body_name!r} in model {model.name!r} (bodies: "
                                 f"{', '.join(model.body_names)})")
        body = model.body_names.index(body_name)
    prefix = f"{body_name}:" if body_name else ""
    if quantity == "buoyancy":
        return Parameter(prefix + quantity, body, "buoyancy_mass", (), "kg")
    if quantity in ("cob.x", "cob.y", "cob.z"):
        return Parameter(prefix + quantity, body, "cob", ("xyz".index(quantity[-1]),), "m")
    group, _, axis = quantity.rpartition(".")
    if group == "disturbance" and axis in AXES:
        if body != 0:
            raise UvmsInputError(f"{where}: {text!r}: a disturbance wrench acts on the vehicle only (body "
                                 f"{model.body_names[0]!r}), not on {body_name!r}")
        return Parameter(quantity, 0, "disturbance_wrench", (AXES.index(axis),), _UNITS_DISTURBANCE[AXES.index(axis)])
    if group in _FIELD_6 and axis in AXES:
        k = AXES.index(axis)
        return Parameter(prefix + quantity, body, _FIELD_6[group], (k, k), _UNITS_6[group][k])
    raise UvmsInputError(f"{where}: unknown parameter {name!r}; expected [<body>:]<quantity> with quantity one of "
                         f"buoyancy, cob.x|y|z, damping.linear.<axis>, damping.quadratic.<axis>, "
                         f"added_mass.<axis>, disturbance.<axis> and <axis> one of {', '.join(AXES)}; or "
                         f"point_load:<name>.mass|fluid_mass|x|y|z")


def with_parameters(model, values: Mapping[str, float], where: str = "parameters"):
    """A copy of ``model`` with each named parameter set (``{name: value}``, SI units; see the module
    docstring). Values must be finite; a buoyancy, damping, added-mass diagonal or point-load mass must not be
    negative (a centre, a position or a disturbance may)."""
    if len(values) > MAX_PARAMETERS:
        raise UvmsInputError(f"{where}: expected at most {MAX_PARAMETERS} parameters, got {len(values)}")
    checked: list[tuple[Parameter, float]] = []
    seen: set[str] = set()
    for name, value in values.items():
        p = parameter(model, name, where)
        if p.name in seen:
            raise UvmsInputError(f"{where}: parameter {p.name!r} given twice")
        seen.add(p.name)
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise UvmsInputError(f"{where}.{name}: expected a number, got {value!r}") from None
        if not np.isfinite(v):
            raise UvmsInputError(f"{where}.{name}: expected a finite number, got {v}")
        if p.field not in _SIGNED and v < 0.0:
            raise UvmsInputError(f"{where}.{name}: expected a value >= 0 {p.unit}, got {v:g}")
        checked.append((p, v))
    model = _with_point_loads_set(model, [(p, v) for p, v in checked if p.load is not None])
    arrays: dict[str, np.ndarray] = {}
    for p, v in checked:
        if p.load is not None:
            continue
        if p.field not in arrays:
            arrays[p.field] = np.array(getattr(model, p.field), dtype=float)
        arrays[p.field][p.index if p.field == "disturbance_wrench" else (p.body, *p.index)] = v
    if "added_mass" in arrays:
        for b in range(model.n_bodies):
            eig = np.linalg.eigvalsh(0.5 * (arrays["added_mass"][b] + arrays["added_mass"][b].T))
            if eig.min() < -1e-9 * max(1.0, abs(eig).max()):
                raise UvmsInputError(f"{where}: the added-mass matrix of body {model.body_names[b]!r} is no longer "
                                     f"positive semi-definite (smallest eigenvalue {eig.min():.3g})")
    return model.replace(**arrays) if arrays else model


_SIGNED = ("cob", "point_load.position", "disturbance_wrench")
"""Fields whose parameters may be negative."""


def _with_point_loads_set(model, settings: list[tuple[Parameter, float]]):
    """``model`` with the point-load parameters set, one fold per load
    (:func:`uvms.model.loads.with_point_load_set`)."""
    from uvms.model.loads import point_load, with_point_load_set

    per_load: dict[str, dict] = {}
    for p, v in settings:
        change = per_load.setdefault(p.load, {})
        if p.field == "point_load.position":
            change.setdefault("position", np.array(point_load(model, p.load).position))[p.index[0]] = v
        else:
            change[p.field.partition(".")[2]] = v
    for name, change in per_load.items():
        model = with_point_load_set(model, name, **change)
    return model


def frame_sign(p: Parameter, source: str, target: str) -> float:
    """The factor that maps parameter ``p`` from frame convention ``source`` to ``target`` (:mod:`uvms.frames`,
    the half turn ``H = diag(1, -1, -1)`` of the world and the vehicle's axes): ``-1`` between different
    conventions for the vehicle's ``cob.y`` and ``cob.z``, a vehicle point load's ``.y`` and ``.z``, and the
    disturbance's ``pitch``, ``yaw``, ``sway`` and ``heave`` (``H6 w``), else ``1`` (a link's own frame is the
    same in both; a diagonal entry of ``H6 M H6`` equals that of ``M``; a mass is a scalar)."""
    from uvms.frames import check_frame

    if check_frame(source, "source frame") == check_frame(target, "target frame"):
        return 1.0
    if p.field in ("cob", "point_load.position") and p.body == 0 and p.index[0] in (1, 2):
        return -1.0
    if p.field == "disturbance_wrench" and p.index[0] in (1, 2, 4, 5):
        return -1.0
    return 1.0
