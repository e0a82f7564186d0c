"""Point loads and dry weight folded into a model's bodies (``docs/models.md``, "Point loads and dry weight").

A **point load** on body ``b`` at ``r`` (body frame) is a point mass ``m_p`` and/or a displaced-fluid mass
``m_fp`` there. Folding it keeps the body's totals exact (first moments add; Featherstone 2008, Sec. 2.13):

    m' = m + m_p          c' = (m c + m_p r) / m'
    I_c' = I_c - m [c - c']x^2 - m_p [r - c']x^2           (parallel axes; a point has no inertia of its own)
    m_f' = m_f + m_fp     b' = (m_f b + m_fp r) / m_f'

An ``inertial=False`` load adds to the weight only: for a body whose inertia already holds that mass (a URDF
whose inertial masses were identified with everything on board).

The **weight** of a body is its own pair ``(weight_mass, weight_center)`` (:attr:`Model.weight_mass`,
:attr:`Model.weight_center`); it is the inertial ``(mass, com)`` unless a model says otherwise: the dry mass
of a URDF whose inertias include added mass, or weight-only point loads. Gravity, trim, the validate report and
the potential energy read only these two.

A built model remembers its named point loads (:class:`PointLoad`, :attr:`Model.point_loads`), so that one may
be changed afterwards (:func:`with_point_load_set`, the ``point_load:<name>.*`` parameters of
:mod:`uvms.model.parameters`): the first moments and the inertia about the body origin are linear in the point
mass, so folding the old load with a negative mass (and fluid mass) removes it exactly, and folding the new one
adds it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from uvms.errors import UvmsInputError
from uvms.spatial import skew


@dataclass(frozen=True, eq=False)
class PointLoad:
    """A named point load folded into a built model: on ``body`` (index) at ``position`` (body frame) [m], a
    point ``mass`` [kg] (with ``inertial`` also in the body's inertia, else in its weight only) and
    ``fluid_mass`` [kg] of displaced fluid centred there."""

    name: str
    body: int
    position: np.ndarray
    mass: float = 0.0
    fluid_mass: float = 0.0
    inertial: bool = True

    def __post_init__(self) -> None:
        position = np.array(self.position, dtype=float).reshape(3)
        position.setflags(write=False)
        object.__setattr__(self, "position", position)
        object.__setattr__(self, "body", int(self.body))
        object.__setattr__(self, "mass", float(self.mass))
        object.__setattr__(self, "fluid_mass", float(self.fluid_mass))


def _point_inertia(mass: float, r: np.ndarray) -> np.ndarray:
    """Rotational inertia of a point mass at offset ``r`` [m]: ``-m [r x]^2`` [kg m^2]."""
    S = skew(r)
    return -mass * S @ S


def _add_first_moment(mass: float, centre: np.ndarray, m_p: float, r: np.ndarray) -> tuple[float, np.ndarray]:
    """The total mass and the centre of ``mass`` at ``centre`` plus ``m_p`` at ``r`` (the origin if both are zero)."""
    total = mass + m_p
    return total, ((mass * centre + m_p * r) / total if total > 0.0 else np.zeros(3))


def with_point_load(model, body: int, position, *, mass: float = 0.0, fluid_mass: float = 0.0,
                    inertial: bool = True, name: str | None = None):
    """A copy of ``model`` with a point load on ``body`` at ``position`` (body frame) [m]: a point mass ``mass``
    [kg] (added to the weight, and with ``inertial`` to the rigid-body mass, centre of mass and inertia) and
    ``fluid_mass`` [kg] of displaced fluid centred there (module docstring). A ``name`` (unique in the model)
    makes the model remember the load (:attr:`Model.point_loads`)."""
    out = _fold(model, body, position, mass, fluid_mass, inertial)
    if name is None:
        return out
    if any(p.name == name for p in model.point_loads):
        raise ValueError(f"the model already has a point load named {name!r}")
    return out.replace(point_loads=model.point_loads + (PointLoad(name, body, position, mass, fluid_mass, inertial),))


def point_load(model, name: str) -> PointLoad:
    """The point load called ``name`` of ``model``; an unknown name is one line listing the model's loads."""
    for p in model.point_loads:
        if p.name == name:
            return p
    raise UvmsInputError(f"no point load {name!r} in model {model.name!r} (point loads: "
                         f"{', '.join(p.name for p in model.point_loads) or 'none'})")


def with_point_load_set(model, name: str, *, mass: float | None = None, fluid_mass: float | None = None,
                        position=None):
    """A copy of ``model`` whose point load ``name`` has the given ``mass``, ``fluid_mass`` [kg] and/or
    ``position`` (body frame) [m] (the others kept): the old load is folded out with negative masses and the new
    one folded in (module docstring), so the result equals the model built with the new load."""
    old = point_load(model, name)
    new = replace(old, mass=old.mass if mass is None else mass,
                  fluid_mass=old.fluid_mass if fluid_mass is None else fluid_mass,
                  position=old.position if position is None else position)
    if np.array_equal(new.position, old.position):
        out = _fold(model, old.body, old.position, new.mass - old.mass, new.fluid_mass - old.fluid_mass,
                    old.inertial)
    else:
        out = _fold(model, old.body, old.position, -old.mass, -old.fluid_mass, old.inertial)
        out = _fold(out, new.body, new.position, new.mass, new.fluid_mass, new.inertial)
    return out.replace(point_loads=tuple(new if p.name == name else p for p in model.point_loads))


def _fold(model, body: int, position, mass: float, fluid_mass: float, inertial: bool):
    """``model`` with a point mass ``mass`` and fluid mass ``fluid_mass`` folded into ``body`` at ``position``
    (module docstring); negative masses fold a load out."""
    r = np.asarray(position, dtype=float)
    changes: dict = {}
    dry = model.dry_mass is not None or (mass != 0.0 and not inertial)
    if mass != 0.0:
        weight, centre = np.array(model.weight_mass, dtype=float), np.array(model.weight_center, dtype=float)
        weight[body], centre[body] = _add_first_moment(weight[body], centre[body], mass, r)
        if dry:
            changes.update(dry_mass=weight, dry_com=centre)
        if inertial:
            m = np.array(model.mass, dtype=float)
            com = np.array(model.com, dtype=float)
            inertia = np.array(model.inertia_com, dtype=float)
            m0, c0 = m[body], com[body].copy()
            m[body], com[body] = _add_first_moment(m0, c0, mass, r)
            inertia[body] = inertia[body] + _point_inertia(m0, c0 - com[body]) + _point_inertia(mass, r - com[body])
            changes.update(mass=m, com=com, inertia_com=inertia)
    if fluid_mass != 0.0:
        fluid, cob = np.array(model.buoyancy_mass, dtype=float), np.array(model.cob, dtype=float)
        fluid[body], cob[body] = _add_first_moment(fluid[body], cob[body], fluid_mass, r)
        changes.update(buoyancy_mass=fluid, cob=cob)
    return model.replace(**changes) if changes else model


def _frame_point(model, name: str, position, source, where: str) -> tuple[int, np.ndarray]:
    """``(body, point in the body frame)`` of a point given in the frame of the link ``name``."""
    frame = next((f for f in model.frames if f.name == name), None)
    if frame is None:
        links = ", ".join(n for n in model.frame_names if n != "end_effector")
        raise UvmsInputError(f"names {name!r}, which is not a body or link of the model (links: {links})",
                             source, where)
    return frame.body, frame.position + frame.rotation @ np.asarray(position, dtype=float)


def with_point_loads(model, loads, source: str | None = None):
    """``model`` with the schema's point loads (:class:`uvms.model.schema.PointLoadSpec`) folded in, in order."""
    for k, load in enumerate(loads):
        body, r = _frame_point(model, load.body, load.position, source, f"point_loads[{k}].body")
        model = with_point_load(model, body, r, mass=float(load.mass or 0.0),
                                fluid_mass=load.fluid_mass(model.density), inertial=load.inertial, name=load.name)
    return model


def with_dry_weight(model, weights, source: str | None = None):
    """A URDF model whose inertial masses include added mass, weighed by its dry mass: ``weights`` is pairs of
    a link name (``None``: the root link, the vehicle) and its :class:`uvms.model.schema.WeightSpec` (``mass`` at
    ``center``, link frame); each body's weight is
    the sum over its links (the first moments add). The inertias are kept; the added mass is zero (it is in
    them). A body none of whose links has a weight is refused."""
    nb = model.n_bodies
    weight, moment, given = np.zeros(nb), np.zeros((nb, 3)), np.zeros(nb, dtype=bool)
    for name, spec in weights:
        name = model.body_names[0] if name is None else name
        body, r = _frame_point(model, name, spec.center, source, f"{_where(model, name)}.weight")
        weight[body] += spec.mass
        moment[body] += spec.mass * r
        given[body] = True
    for i in np.flatnonzero(~given):
        raise UvmsInputError(f"expected the dry weight of body {model.body_names[i]!r} (its inertia includes added "
                             "mass: inertia_includes_added_mass is true), found none on it or the links fixed to it",
                             source, f"{_where(model, model.body_names[i])}.weight")
    centre = np.divide(moment, weight[:, None], out=np.zeros((nb, 3)), where=weight[:, None] > 0.0)
    return model.replace(dry_mass=weight, dry_com=centre, added_mass=np.zeros_like(model.added_mass))


def _where(model, link: str) -> str:
    """The additions file's key of a link: ``vehicle`` for the root link, else ``links.<link>``."""
    return "vehicle" if link == model.body_names[0] else f"links.{link}"
