"""URDF (and xacro) robot descriptions -> :class:`~uvms.model.model.Model` (``docs/models.md``, "URDF").

The URDF is parsed by ``defusedxml`` (no DTD, no entities; at most :data:`MAX_URDF_BYTES` and :data:`MAX_LINKS`
links) and read by ``yourdfpy``; a xacro is expanded as data by :mod:`uvms.model.xacro` (without ROS). This
module turns the parsed links and joints into a kinematic tree and checks it:

* the root link (the one link that is no joint's child) is the vehicle: its frame is the vehicle frame and
  ``nu`` is that frame's body velocity ``[angular; linear]`` (it need not be the centre of mass);
* revolute, continuous and prismatic joints move a body about / along a unit axis of the joint frame (URDF
  default ``x`` when ``<axis>`` is absent); a fixed joint merges its child link into the parent body, adding its
  spatial inertia (Featherstone 2008, Sec. 2.13: inertias about one point add) and its hydrodynamics, and the
  child stays a named frame (as Pinocchio's URDF parser does);
* bodies and joints are in depth-first order from the root, children in file order: that is the order of ``q``;
* ``<dynamics damping friction>`` become joint damping and Coulomb friction, ``<limit>`` the joint limits;
* mimic joints, floating and planar joints, loops, several roots, non-finite origins, damping, friction and
  limits, ``lower > upper`` and unphysical inertias are refused with a one-line
  :class:`~uvms.errors.UvmsInputError` naming the file and the link or joint (an inertia breaking only the
  triangle inequality is balanced instead on request, :func:`balanced_inertia`).

Hydrodynamics cannot be written in URDF: a model YAML with ``urdf:`` adds them per link name
(:class:`uvms.model.schema.UrdfModelSpec`); a bare URDF gives a model with every hydrodynamic effect zero.
"""

from __future__ import annotations

import io
import logging
import math
import os
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from uvms.errors import UvmsInputError
from uvms.model.model import DEFAULT_FRICTION_SPEED, END_EFFECTOR, Frame, Model
from uvms.model.xacro import XacroOptions
from uvms.spatial import plucker, skew, spatial_inertia

URDF_SUFFIXES = (".urdf", ".xacro", ".sdf", ".world")
"""File suffixes read as robot descriptions (``.urdf.xacro`` ends in ``.xacro``; ``.sdf`` and ``.world`` are
read by :mod:`uvms.model.sdf`)."""

MOVING = ("revolute", "continuous", "prismatic")
RELATIVE_TOLERANCE = 1e-9
"""Relative tolerance of the inertia checks (as :data:`uvms.model.schema.RELATIVE_TOLERANCE`)."""
MAX_URDF_BYTES = 16 * 1024 * 1024
"""Largest ``.urdf`` file read [bytes] (checked before reading; a xacro file has its own limits)."""
MAX_LINKS = 1_000
"""Most ``<link>`` (and most ``<joint>``) elements of a robot description, counted while it is parsed."""


def is_robot_description(path: str | os.PathLike[str]) -> bool:
    """Whether a path names a URDF, xacro or SDF file (by its suffix)."""
    return str(path).lower().endswith(URDF_SUFFIXES)


def read_urdf_text(path: str | os.PathLike[str], xacro: XacroOptions | None = None) -> str:
    """The URDF text of a ``.urdf`` file (at most :data:`MAX_URDF_BYTES`), or of a ``.xacro`` file expanded as
    data by :func:`uvms.model.xacro.expand` under ``xacro`` (what it may read beyond its folder)."""
    path = Path(path)
    source = str(path)
    if not path.exists():
        raise UvmsInputError("no such file", source)
    if not path.is_file():
        raise UvmsInputError("expected a URDF file, found a directory" if path.is_dir()
                             else "expected a URDF file, found something that is not a regular file", source)
    if path.suffix.lower() == ".xacro":
        from uvms.model.xacro import expand

        return expand(path, xacro)
    size = path.stat().st_size
    if size > MAX_URDF_BYTES:
        raise UvmsInputError(f"URDF file of {size:,} bytes, over the limit of {MAX_URDF_BYTES:,}", source)
    try:
        return path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise UvmsInputError(f"cannot read URDF: {exc}", source) from None


def _parse(text: str, source: str):
    """``yourdfpy``'s robot of a URDF text, parsed by ``defusedxml`` (a DTD or entity is refused) and
    refused beyond :data:`MAX_LINKS` links or joints while it is read; XML syntax errors (which yourdfpy would
    try to recover from) and a document that is not a ``<robot>`` are refused first."""
    root = _xml_root(text, source)
    if root.tag != "robot":
        raise UvmsInputError(f"expected a <robot> element at the top level, found <{root.tag}>", source)
    _check_required(root, source)
    import yourdfpy

    try:
        with _quiet_logger("yourdfpy.urdf"), np.errstate(all="ignore"):   # NaN origins are refused later
            return yourdfpy.URDF._parse_robot(xml_element=root)
    except Exception as exc:  # yourdfpy's own errors on content it cannot read (bad numbers, ...)
        raise UvmsInputError(f"invalid URDF: {' '.join(str(exc).split()) or type(exc).__name__}", source) from None


def _xml_root(text: str, source: str):
    """The root element of a URDF text (``defusedxml``; counting links and joints as it goes)."""
    from xml.etree.ElementTree import ParseError

    from defusedxml import DefusedXmlException
    from defusedxml.ElementTree import iterparse

    counts = {"link": 0, "joint": 0}
    depth = 0
    events = iterparse(io.BytesIO(text.encode("utf-8")), events=("start", "end"), forbid_dtd=True)
    try:
        for event, element in events:
            depth += 1 if event == "start" else -1
            if event == "start" and depth == 2 and element.tag in counts:
                counts[element.tag] += 1
                if counts[element.tag] > MAX_LINKS:
                    raise UvmsInputError(f"more than {MAX_LINKS:,} <{element.tag}> elements (the limit of a "
                                         "robot description, docs/models.md)", source)
    except ParseError as exc:
        line, column = exc.position
        message = str(exc).split(":")[0]
        raise UvmsInputError(f"invalid XML: {message}", source, f"line {line}, column {column + 1}") from None
    except DefusedXmlException:
        raise UvmsInputError("a DTD or entity declaration (<!DOCTYPE ...>, <!ENTITY ...>) is not allowed in a "
                             "robot description", source) from None
    return events.root


def _check_required(root, source: str) -> None:
    """The attributes and elements URDF requires of the robot, its links and joints, by name (yourdfpy would
    stop on them with a Python error)."""
    if not root.get("name"):
        raise UvmsInputError("expected a name attribute on <robot>", source)
    for k, element in enumerate(root):
        name = element.get("name")
        if element.tag in ("link", "joint") and not name:
            raise UvmsInputError(f"expected a name attribute on <{element.tag}> number {k + 1}", source)
        if element.tag != "joint":
            continue
        if not element.get("type"):
            raise UvmsInputError("expected a type attribute", source, f"joint {name!r}")
        for role in ("parent", "child"):
            item = element.find(role)
            if item is None or not item.get("link"):
                raise UvmsInputError(f"expected a <{role} link=...> element", source, f"joint {name!r}")


@contextmanager
def _quiet_logger(name: str):
    """Keep a library's log records (yourdfpy's recovery notes) off the terminal while parsing."""
    logger = logging.getLogger(name)
    drop = logging.Filter("\0")            # matches no logger name: every record is dropped
    logger.addFilter(drop)
    try:
        yield
    finally:
        logger.removeFilter(drop)


def _pose(origin: Any, source: str | None = None, where: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``(R, p)`` of a yourdfpy 4x4 origin (identity when absent); a non-finite ``xyz`` or ``rpy`` is refused."""
    if origin is None:
        return np.eye(3), np.zeros(3)
    T = np.asarray(origin, dtype=float)
    if not np.all(np.isfinite(T)):
        raise UvmsInputError("expected a finite <origin xyz rpy>, found NaN or infinity", source, where)
    return T[:3, :3].copy(), T[:3, 3].copy()


def check_link_inertia(mass: float, inertia: np.ndarray, source: str | None, where: str,
                       balance: bool = False) -> np.ndarray:
    """A link's mass ``>= 0`` and rotational inertia about its CoM symmetric positive semi-definite with
    ``I1 + I2 >= I3`` (relative tolerance :data:`RELATIVE_TOLERANCE`); a massless link (a frame) may have
    zero inertia. Returns the inertia: unchanged, or with ``balance`` and the triangle inequality broken,
    :func:`balanced_inertia` of it."""
    if not math.isfinite(mass) or mass < 0.0:
        raise UvmsInputError(f"expected a mass >= 0, found {mass:g}", source, where)
    if not np.all(np.isfinite(inertia)):
        raise UvmsInputError("expected a finite inertia", source, where)
    scale = max(float(np.abs(inertia).max()), 1e-300)
    if np.abs(inertia - inertia.T).max() > RELATIVE_TOLERANCE * scale:
        raise UvmsInputError("expected a symmetric inertia", source, where)
    moments = np.linalg.eigvalsh(0.5 * (inertia + inertia.T))
    tol = RELATIVE_TOLERANCE * max(float(np.sum(np.abs(moments))), 1e-300)
    if moments[0] < -tol:
        raise UvmsInputError("expected a positive semi-definite inertia, found principal moments "
                             f"[{', '.join(f'{m:.6g}' for m in moments)}]", source, where)
    if moments[0] + moments[1] < moments[2] - tol and not balance:
        raise UvmsInputError("expected principal moments with I1 + I2 >= I3 (triangle inequality), found "
                             f"[{', '.join(f'{m:.6g}' for m in moments)}]; balance_inertia: true accepts it "
                             "with the moments set to their mean (docs/models.md)", source, where)
    if mass == 0.0 and moments[2] > 0.0:
        raise UvmsInputError("expected zero inertia for a link of zero mass, found principal moments "
                             f"[{', '.join(f'{m:.6g}' for m in moments)}]", source, where)
    if moments[0] + moments[1] < moments[2] - tol:
        return balanced_inertia(inertia)
    return inertia


def balanced_inertia(inertia: np.ndarray) -> np.ndarray:
    """MuJoCo's ``balanceinertia`` (MJCF reference, ``compiler/balanceinertia``: "the compiler will silently
    set all three diagonal elements to their average value whenever the above condition", ``A + B >= C``,
    "is violated"), applied to the principal moments: the rotational inertia ``(I1 + I2 + I3) / 3 * 1`` [kg m^2],
    the same in every axis, so the principal axes no longer matter. The trace (the polar moment about the CoM)
    is kept."""
    return np.trace(inertia) / 3.0 * np.eye(3)


@dataclass
class LinkHydro:
    """Hydrodynamics of one link, in its own frame (from the YAML additions): added mass about the link
    origin (6x6, ``[angular; linear]``), displaced-fluid mass and centre, an optional drag cylinder."""

    added_mass: np.ndarray = field(default_factory=lambda: np.zeros((6, 6)))
    fluid_mass: float = 0.0
    center: np.ndarray = field(default_factory=lambda: np.zeros(3))
    cylinder: tuple[np.ndarray, np.ndarray, float, float, float] | None = None
    """``(rotation with x along the axis, origin, radius, length, drag coefficient)``, link frame."""
    damping: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
    """Fossen damping ``(D_l, D_q, point)``, link axes, the point in the link frame."""
    damping_cross: np.ndarray | None = None
    """Mixed quadratic damping (2, 6, 6, 6) at the damping point (:attr:`Model.damping_cross`), or ``None``."""
    shapes: list = field(default_factory=list)
    """:mod:`uvms.hydro.shapes` shapes posed in the link frame."""
    from_collision: float | None = None
    """Drag coefficient of the link's collision primitives taken as shapes, or ``None`` (not taken)."""
    explicit_added_mass: bool = False
    explicit_buoyancy: bool = False
    density: float = 1000.0
    """Whether ``added_mass`` / ``fluid_mass`` were given: they then override the shapes'."""


@dataclass
class VehicleExtras:
    """What the YAML additions give beyond the URDF (all optional; zero hydrodynamics by default)."""

    name: str | None = None
    frame: str | None = "ned"
    """The convention the URDF and the additions are written in (``ned`` or ``enu``, :mod:`uvms.frames`);
    ``None``: the file's (``enu`` for a file with Gazebo plugin tags, else ``ned``; :mod:`uvms.model.gazebo`)."""
    density: float | None = 1000.0
    """Fluid density [kg/m^3]; ``None``: the file's plugin tags', else 1000."""
    gravity: tuple | None = (0.0, 0.0, 9.81)
    """World gravity [m/s^2], in ``frame``'s world axes; ``None``: the file's world's, else 9.81 down."""
    current: tuple | None = (0.0, 0.0, 0.0)
    fluid_acceleration: tuple = (0.0, 0.0, 0.0)
    vehicle_drag_area: tuple = (0.0, 0.0, 0.0)
    vehicle_drag_coefficient: tuple = (0.0, 0.0, 0.0)
    vehicle_rotational_drag_side: float = 0.0
    vehicle_rotational_drag_coefficient: float = 0.0
    vehicle_box: tuple = (0.0, 0.0, 0.0)
    vehicle_hydro: LinkHydro | None = None
    """Added mass and buoyancy of the vehicle, in the root link's frame (its drag is given above)."""
    links: dict[str, LinkHydro] = field(default_factory=dict)
    joints: dict[str, dict[str, float]] = field(default_factory=dict)
    end_effector: str | None = None
    fixed_joints: tuple[str, ...] = ()
    """Joints treated as fixed at their zero position (e.g. mimic joints of a gripper)."""
    thrusters: tuple = ()
    source: str | None = None
    """The additions file (named in errors about its link names)."""
    xacro: XacroOptions | None = None
    """What a xacro description may read beyond its folder (package folders, the environment, arguments)."""
    balance_inertia: bool = False
    """Accept inertias breaking the triangle inequality, balanced (:func:`balanced_inertia`), with a warning."""


@dataclass
class _Body:
    link: str
    joint: Any = None                  # yourdfpy joint moving this body (None for the root)
    parent: int = -1
    R_joint: np.ndarray = field(default_factory=lambda: np.eye(3))   # joint frame in the parent body
    p_joint: np.ndarray = field(default_factory=lambda: np.zeros(3))
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((6, 6)))
    added_mass: np.ndarray = field(default_factory=lambda: np.zeros((6, 6)))
    fluid_mass: float = 0.0
    fluid_moment: np.ndarray = field(default_factory=lambda: np.zeros(3))   # sum of m_f * centre
    cylinder: tuple | None = None
    cylinder_link: str | None = None
    damping: tuple | None = None            # Fossen (D_l, D_q, point), body axes and frame
    damping_cross: np.ndarray | None = None   # mixed quadratic damping at the damping point
    shapes: list = field(default_factory=list)   # hydrodynamic shapes posed in the body frame
    damping_link: str | None = None


def _tree(robot, source: str):
    """Checked tree: ``(root link name, children by link: [(joint, child)...], parent joint by link)``."""
    links = [link.name for link in robot.links]
    seen: set[str] = set()
    for name in links:
        if name in seen:
            raise UvmsInputError("link defined twice", source, f"link {name!r}")
        seen.add(name)
    children: dict[str, list] = {name: [] for name in links}
    parent_joint: dict[str, Any] = {}
    joint_names: set[str] = set()
    for joint in robot.joints:
        where = f"joint {joint.name!r}"
        if joint.name in joint_names:
            raise UvmsInputError("joint defined twice", source, where)
        joint_names.add(joint.name)
        for role, link in (("parent", joint.parent), ("child", joint.child)):
            if link not in seen:
                raise UvmsInputError(f"its {role} link {link!r} is not defined", source, where)
        if joint.child in parent_joint:
            raise UvmsInputError(f"link {joint.child!r} is already the child of joint "
                                 f"{parent_joint[joint.child].name!r} (a loop: a URDF is a tree)", source, where)
        parent_joint[joint.child] = joint
        children[joint.parent].append(joint)
    roots = [name for name in links if name not in parent_joint]
    if not links:
        raise UvmsInputError("expected at least one <link>, found none", source)
    if len(roots) > 1:
        raise UvmsInputError(f"expected one root link, found {len(roots)}: {', '.join(map(repr, roots[:4]))}"
                             f"{' ...' if len(roots) > 4 else ''} (every other link must be a joint's child)", source)
    if not roots:
        raise UvmsInputError("expected one root link, found none: the joints form a loop", source)
    reached = {roots[0]}
    stack = [roots[0]]
    while stack:
        for joint in children[stack.pop()]:
            reached.add(joint.child)
            stack.append(joint.child)
    if len(reached) != len(links):
        lost = next(name for name in links if name not in reached)
        raise UvmsInputError("the joints form a loop that does not reach the root link", source,
                             f"joint {parent_joint[lost].name!r}")
    return roots[0], children


def _check_joint(joint, source: str, frozen: tuple[str, ...] = ()) -> np.ndarray | None:
    """The joint's unit axis (moving joints) or ``None`` (fixed, or frozen by the YAML additions' ``fixed_joints``
    at its zero position), after checking its type and mimic."""
    where = f"joint {joint.name!r}"
    if joint.name in frozen:
        return None
    if joint.mimic is not None:
        raise UvmsInputError(f"mimic joints are not supported (it mimics {joint.mimic.joint!r}); freeze it with "
                             "'fixed_joints' in a model YAML, or make it fixed or independent", source, where)
    if joint.type == "fixed":
        return None
    if joint.type not in MOVING:
        known = "revolute, continuous, prismatic or fixed"
        kind = "unsupported" if joint.type in ("floating", "planar") else "unknown"
        raise UvmsInputError(f"{kind} joint type {joint.type!r}; expected {known}", source, where)
    axis = np.array([1.0, 0.0, 0.0]) if joint.axis is None else np.asarray(joint.axis, dtype=float)
    norm = float(np.linalg.norm(axis))
    if not math.isfinite(norm) or norm < 1e-12:
        raise UvmsInputError(f"expected a non-zero joint axis, found {list(map(float, axis))}", source, where)
    return axis / norm


def _link_inertia(link, source: str, balanced: list | None = None) -> np.ndarray:
    """6x6 spatial inertia of a link about its own origin, in its own axes (zero without ``<inertial>``).
    With ``balanced`` (a list), an inertia breaking the triangle inequality is balanced
    (:func:`balanced_inertia`) and ``(link name, principal moments before, after)`` appended to it."""
    inertial = link.inertial
    if inertial is None:
        return np.zeros((6, 6))
    mass = float(inertial.mass) if inertial.mass is not None else 0.0
    I = np.zeros((3, 3)) if inertial.inertia is None else np.asarray(inertial.inertia, dtype=float)
    where = f"link {link.name!r}"
    checked = check_link_inertia(mass, I, source, where, balance=balanced is not None)
    if checked is not I:
        balanced.append((link.name, np.linalg.eigvalsh(0.5 * (I + I.T)), float(checked[0, 0])))
    R, c = _pose(inertial.origin, source, f"{where}: inertial")
    return spatial_inertia(mass, c, R @ checked @ R.T)


def _warn_balanced(balanced: list, source: str) -> None:
    """One warning line naming the links whose inertia ``balance_inertia`` changed, and by how much."""
    if not balanced:
        return
    items = [f"{name!r} [{', '.join(f'{m:.6g}' for m in before)}] -> {after:.6g} each"
             for name, before, after in balanced[:3]]
    more = f" and {len(balanced) - 3} more" if len(balanced) > 3 else ""
    warnings.warn(f"{source}: balance_inertia: principal moments [kg m^2] set to their mean (they broke "
                  f"I1 + I2 >= I3) on {len(balanced)} link(s): {'; '.join(items)}{more}", stacklevel=3)


def _to_body(I_link: np.ndarray, R: np.ndarray, p: np.ndarray) -> np.ndarray:
    """A 6x6 inertia about a link's origin in link axes, moved to the body frame in which the link has pose
    ``(R, p)``: ``X^T I X`` with ``X`` the body-to-link motion transform (Featherstone Eq. 2.66)."""
    X = plucker(R.T, p)
    return X.T @ I_link @ X


def _mass_properties(I: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """``(mass, com, inertia about the com)`` of a 6x6 spatial inertia about the body origin."""
    m = float(I[3, 3])
    if m <= 0.0:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    C = I[0:3, 3:6] / m                           # m skew(c)
    c = np.array([C[2, 1], C[0, 2], C[1, 0]])
    I_com = I[0:3, 0:3] - m * skew(c) @ skew(c).T
    return m, c, 0.5 * (I_com + I_com.T)


def model_from_urdf(path: str | os.PathLike[str], extras: VehicleExtras | None = None, *,
                    xacro: XacroOptions | None = None, balance_inertia: bool | None = None) -> Model:
    """The :class:`Model` of a URDF or xacro file, with the hydrodynamics and environment of ``extras``.

    ``xacro`` (what a xacro may read beyond its folder) and ``balance_inertia`` (accept an inertia breaking
    the triangle inequality with its principal moments set to their mean, :func:`balanced_inertia`) replace
    those of ``extras`` when given.

    Raises:
        UvmsInputError: unreadable or invalid description, or additions naming links it lacks (one line).
    """
    source = str(path)
    extras = extras or VehicleExtras()
    xacro = extras.xacro if xacro is None else xacro
    text = read_urdf_text(path, xacro)
    robot = _parse(text, source)
    _warn_missing_meshes(robot, Path(path).parent, source)
    from uvms.model.uuv import read_uuv_tags

    return model_from_robot(robot, source, extras, read_uuv_tags(text, source),
                            extras.balance_inertia if balance_inertia is None else balance_inertia)


def model_from_robot(robot, source: str, extras: VehicleExtras, tags=None, balance_inertia: bool = False) -> Model:
    """The :class:`Model` of a parsed robot (``yourdfpy``'s, or :mod:`uvms.model.sdf`'s in the same form) with
    the additions of ``extras`` and the Gazebo plugin tags ``tags`` (:class:`uvms.model.uuv.UuvTags`, or
    ``None``): UUV Simulator's hydrodynamics go to the links the additions do not describe, its thrusters are
    used when the additions give none; pinned joints (``lower = upper``), the thrusters' spin joints and joints
    moving no mass or no inertia about their axis are frozen (one warning lists them and the ignored tags).
    Which tag each hydrodynamic number came from is kept in :attr:`Model.hydro_sources`."""
    from dataclasses import replace

    from uvms.model import gazebo

    tags = tags if tags is not None else gazebo.no_tags()
    origins: dict[str, str] = {}
    extras = gazebo.resolved_extras(extras, tags)
    balanced: list | None = [] if balance_inertia else None
    root, children = _tree(robot, source)
    links = {link.name: link for link in robot.links}
    joint_names = {joint.name for joint in robot.joints}
    extras = replace(extras, links=dict(extras.links))
    _add_link_hydro(extras, tags, robot, root, source, origins)
    frozen, pinned, notes = _frozen_joints(robot, children, links, root, extras, tags, source)
    extras = replace(extras, fixed_joints=tuple(extras.fixed_joints) + tuple(frozen))
    for k, name in enumerate(extras.fixed_joints):
        if name not in joint_names:
            raise UvmsInputError(f"names joint {name!r}, which the URDF {source} does not have", extras.source,
                                 f"fixed_joints[{k}]")
    for name in extras.links:
        if name not in links:
            raise UvmsInputError(f"names link {name!r}, which the URDF {source} does not have", extras.source,
                                 f"links.{name}")

    bodies: list[_Body] = []
    frames: list[tuple[str, int, np.ndarray, np.ndarray, int]] = []    # name, body, R, p, depth
    axes: list[np.ndarray] = []
    # depth first over the links, children in file order; a moving joint's child starts a new body when visited
    stack: list[tuple] = [(root, None, np.eye(3), np.zeros(3), 0, None)]
    while stack:
        name, b, R, p, depth, moving = stack.pop()
        if b is None:
            b = len(bodies)
            if moving is None:
                bodies.append(_Body(link=name))
            else:
                joint, parent, R_joint, p_joint, axis = moving
                bodies.append(_Body(link=name, joint=joint, parent=parent, R_joint=R_joint, p_joint=p_joint))
                axes.append(axis)
        frames.append((name, b, R, p, depth))
        body = bodies[b]
        body.inertia = body.inertia + _to_body(_link_inertia(links[name], source, balanced), R, p)
        hydro = extras.links.get(name)
        if hydro is not None:
            hydro.density = extras.density
            _merge_hydro(body, hydro, _Placement(name, R, p, b, root, links[name]), (source, extras.source))
        pending = []
        for joint in children[name]:
            axis = _check_joint(joint, source, extras.fixed_joints)
            R_o, p_o = _pose(joint.origin, source, f"joint {joint.name!r}")
            if joint.name in pinned:
                R_o, p_o = gazebo.pinned_pose(joint, pinned[joint.name], R_o, p_o)
            if axis is None:
                pending.append((joint.child, b, R @ R_o, p + R @ p_o, depth + 1, None))
            else:
                pending.append((joint.child, None, np.eye(3), np.zeros(3), depth + 1,
                                (joint, b, R @ R_o, p + R @ p_o, axis)))
        stack.extend(reversed(pending))
    if extras.vehicle_hydro is not None:
        extras.vehicle_hydro.density = extras.density
        _merge_hydro(bodies[0], extras.vehicle_hydro, _Placement(root, np.eye(3), np.zeros(3), 0, root, links[root]),
                     (source, extras.source))
    if tags.thrusters and not extras.thrusters:
        extras = replace(extras, thrusters=gazebo.thrusters_of(tags, frames, robot, source))
    model = _assemble(bodies, axes, frames, extras, robot.name, source, tuple(origins.items()))
    _warn_balanced(balanced or [], source)
    gazebo.warn_unmapped(source, notes + tags.notes, tags.ignored)
    return model


# -- Gazebo plugin tags (uvms.model.gazebo) joined to the tree

def _empty(hydro) -> bool:
    return hydro is None or not (np.any(hydro.added_mass) or hydro.fluid_mass or hydro.damping is not None
                                 or hydro.shapes or hydro.from_collision is not None or hydro.cylinder is not None)


def _lumped_mass(robot, name: str) -> float:
    """Mass of link ``name`` and of the links fixed to it (Gazebo lumps them into one link)."""
    links = {link.name: link for link in robot.links}
    total, stack = 0.0, [name]
    while stack:
        link = links[stack.pop()]
        if link.inertial is not None and link.inertial.mass is not None:
            total += float(link.inertial.mass)
        stack.extend(j.child for j in robot.joints if j.parent == link.name and j.type == "fixed")
    return total


def _add_link_hydro(extras, tags, robot, root: str, source: str, origins: dict | None) -> None:
    """The links' tag hydrodynamics into ``extras.links`` (a fresh dict), except where the additions give them."""
    names = {link.name for link in robot.links}
    for name, tag in tags.links.items():
        if name not in names:
            raise UvmsInputError(f"the plugin names link {name!r}, which the description does not have", source,
                                 f"gazebo/plugin/link {name!r}")
        described = name in extras.links or (name == root and not _empty(extras.vehicle_hydro))
        if described:
            tags.ignored.append(f"{name}/* (described by {extras.source})")
            continue
        hydro = LinkHydro(density=extras.density)
        if tag.added_mass is not None:
            hydro.added_mass = np.array(tag.added_mass)
        hydro.explicit_added_mass = tag.added_mass is not None or not tag.shape_added_mass
        if tag.neutrally_buoyant:
            hydro.fluid_mass = _lumped_mass(robot, name)
        elif tag.volume > 0.0:
            hydro.fluid_mass = float(extras.density * tag.volume)
        hydro.explicit_buoyancy = tag.neutrally_buoyant or tag.volume > 0.0 or not tag.shape_buoyancy
        hydro.center = np.array(tag.center, dtype=float)
        if tag.damping_linear is not None or tag.damping_quadratic is not None or tag.damping_cross is not None:
            zero = np.zeros((6, 6))
            hydro.damping = (zero if tag.damping_linear is None else np.array(tag.damping_linear),
                             zero if tag.damping_quadratic is None else np.array(tag.damping_quadratic), np.zeros(3))
            hydro.damping_cross = None if tag.damping_cross is None else np.array(tag.damping_cross)
        hydro.shapes = list(tag.shapes)
        extras.links[name] = hydro
        if origins is not None:
            for quantity, origin in tag.origins.items():
                origins[f"{name}: {quantity}"] = origin


def _subtree_body_inertia(links, children, joint, frozen: set[str], source: str) -> np.ndarray:
    """6x6 rigid inertia, about the joint's child frame, of the body the joint moves: its child link and every
    link fixed (or frozen) to it (inertias breaking the triangle inequality balanced here: they are refused or
    balanced with their message when the tree is built)."""
    total = np.zeros((6, 6))
    stack = [(joint.child, np.eye(3), np.zeros(3))]
    while stack:
        name, R, p = stack.pop()
        total += _to_body(_link_inertia(links[name], source, []), R, p)
        for j in children[name]:
            if j.type == "fixed" or j.name in frozen:
                R_o, p_o = _pose(j.origin)
                stack.append((j.child, R @ R_o, p + R @ p_o))
    return total


def _carried_masses(robot, children, root: str) -> dict[str, float]:
    """Mass of each link and of everything it carries, by link name."""
    links = {link.name: link for link in robot.links}
    order, stack = [], [root]
    while stack:
        name = stack.pop()
        order.append(name)
        stack.extend(j.child for j in children[name])
    carried: dict[str, float] = {}
    for name in reversed(order):
        inertial = links[name].inertial
        own = float(inertial.mass) if inertial is not None and inertial.mass is not None else 0.0
        carried[name] = own + sum(carried[j.child] for j in children[name])
    return carried


def _frozen_joints(robot, children, links, root: str, extras, tags, source: str):
    """``(joints to freeze, {pinned joint: its value}, notes)``: pinned joints (``lower = upper``, revolute or
    prismatic), thrusters' spin joints, and joints moving no mass or no inertia about their axis."""
    already = set(extras.fixed_joints)
    frozen: list[str] = []
    pinned: dict[str, float] = {}
    notes: list[str] = []
    spin = {t.joint for t in tags.thrusters}
    names = {j.name for j in robot.joints}
    for t in tags.thrusters:
        if t.joint not in names:
            raise UvmsInputError(f"the thruster plugin names joint {t.joint!r}, which the description does not "
                                 "have", source, f"thruster {t.thruster_id}")
    reasons: dict[str, list[str]] = {"pinned by its limits (lower = upper)": [], "a thruster's spin joint": [],
                                     "moves no mass or no inertia about its axis": []}
    for joint in robot.joints:
        if joint.type not in MOVING or joint.name in already or joint.mimic is not None:
            continue
        lim = joint.limit
        if (joint.type != "continuous" and lim is not None and lim.lower is not None and lim.upper is not None
                and float(lim.lower) == float(lim.upper) and math.isfinite(float(lim.lower))):
            pinned[joint.name] = float(lim.lower)
            reasons["pinned by its limits (lower = upper)"].append(joint.name)
        elif joint.name in spin:
            reasons["a thruster's spin joint"].append(joint.name)
        else:
            continue
        frozen.append(joint.name)
    done = already | set(frozen)
    carried = _carried_masses(robot, children, root)
    for joint in robot.joints:
        if joint.type not in MOVING or joint.name in done or joint.mimic is not None:
            continue
        axis = np.array([1.0, 0.0, 0.0]) if joint.axis is None else np.asarray(joint.axis, dtype=float)
        norm = float(np.linalg.norm(axis))
        if not norm > 0:
            continue                     # refused later with its own message
        axis = axis / norm
        I = _subtree_body_inertia(links, children, joint, done, source)
        if joint.type == "prismatic":
            along, scale = float(I[3, 3]), float(I[3, 3])
        else:
            along, scale = float(axis @ I[:3, :3] @ axis), float(np.trace(I[:3, :3]))
        if carried[joint.child] <= 0.0 or not along > 1e-9 * max(scale, 1e-300):
            frozen.append(joint.name)
            reasons["moves no mass or no inertia about its axis"].append(joint.name)
    for reason, joints in reasons.items():
        if joints and reason != "a thruster's spin joint":      # expected: frozen without a note
            notes.append(f"froze {len(joints)} joint(s) {reason}: {', '.join(joints[:4])}"
                         f"{' ...' if len(joints) > 4 else ''}")
    return frozen, pinned, notes


def collision_shapes(link, drag_coefficient: float, source: str | None = None) -> list:
    """The box, cylinder and sphere ``<collision>`` primitives of a yourdfpy link as :mod:`uvms.hydro.shapes`
    shapes in the link frame, each with ``drag_coefficient`` (a URDF cylinder runs along its z axis, a shape
    cylinder along its x: the shape frame is turned so). Meshes are skipped with a warning."""
    from uvms.hydro import shapes as hs

    out = []
    to_x = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])   # columns: shape x, y, z = URDF z, x, y
    for item in link.collisions or []:
        R, p = _pose(item.origin)
        g = item.geometry
        try:
            if g.box is not None:
                out.append(hs.Box(tuple(float(x) for x in g.box.size), (drag_coefficient,) * 3, rotation=R, position=p))
            elif g.cylinder is not None:
                out.append(hs.Cylinder(float(g.cylinder.radius), float(g.cylinder.length), drag_coefficient,
                                       rotation=R @ to_x, position=p))
            elif g.sphere is not None:
                out.append(hs.Sphere(float(g.sphere.radius), drag_coefficient, rotation=R, position=p))
            else:
                warnings.warn(f"{source}: link {link.name!r}: collision mesh skipped by from_collision (only box, "
                              "cylinder and sphere are shapes)", stacklevel=2)
        except ValueError as exc:
            raise UvmsInputError(f"collision primitive: {exc}", source, f"link {link.name!r}") from None
    return out


class _Placement(NamedTuple):
    """Where a URDF link sits: its name, its pose ``(R, p)`` in the moving body ``b`` that carries it, the root
    link's name, and the yourdfpy link (for its collision primitives)."""

    link: str
    R: np.ndarray
    p: np.ndarray
    b: int
    root: str
    urdf_link: Any


def _merge_hydro(body: _Body, hydro: LinkHydro, place: _Placement, sources: tuple[str, str | None]) -> None:
    """Add a link's hydrodynamics (link frame) to the body that carries it (``place``: its pose in the body);
    ``sources`` = (the URDF file, the additions file) for messages.

    Shapes (and ``from_collision`` primitives of ``urdf_link``) add their volume at their centre and their
    added mass unless the link gives those explicitly, and their drag table rows to the body's.
    """
    from dataclasses import replace

    from uvms.hydro.shapes import added_mass as shape_added_mass
    from uvms.hydro.shapes import buoyancy as shape_buoyancy

    link, R, p, b, root, urdf_link = place
    source, extras_source = sources
    shapes = list(hydro.shapes)
    if hydro.from_collision is not None and urdf_link is not None:
        shapes += collision_shapes(urdf_link, hydro.from_collision, source)
    added, fluid_mass, center = hydro.added_mass, hydro.fluid_mass, hydro.center
    if shapes:
        if not hydro.explicit_added_mass:
            added = sum(shape_added_mass(s, hydro.density) for s in shapes)
        if not hydro.explicit_buoyancy:
            total, center = shape_buoyancy(shapes)
            fluid_mass = float(hydro.density * total)
        body.shapes = body.shapes + [replace(s, rotation=R @ s.rotation, position=p + R @ s.position)
                                     for s in shapes]
    body.added_mass = body.added_mass + _to_body(added, R, p)
    body.fluid_mass += fluid_mass
    body.fluid_moment = body.fluid_moment + fluid_mass * (p + R @ center)
    if hydro.cylinder is not None:
        where = f"links.{link}.cylinder"
        if b == 0:
            raise UvmsInputError(f"link {link!r} is part of the vehicle (the root link {root!r} or fixed to it): "
                                 "give the vehicle's drag under vehicle.drag", extras_source, where)
        if body.cylinder is not None:
            raise UvmsInputError(f"link {link!r} is fixed to link {body.cylinder_link!r}, which already has a drag "
                                 "cylinder: one cylinder per moving body", extras_source, where)
        C, o, radius, length, cd = hydro.cylinder
        body.cylinder = (R @ C, p + R @ o, radius, length, cd)
        body.cylinder_link = link
    if hydro.damping is not None:
        where = f"links.{link}.damping" if b != 0 or link != root else "vehicle.damping"
        if body.damping is not None:
            raise UvmsInputError(f"link {link!r} is fixed to link {body.damping_link!r}, which already has Fossen "
                                 "damping: one damping table per moving body", extras_source, where)
        D_l, D_q, point = hydro.damping
        rotated = not np.allclose(R, np.eye(3), rtol=0.0, atol=1e-12)
        if rotated and (np.any(D_q) or hydro.damping_cross is not None):
            raise UvmsInputError(f"link {link!r} is fixed to its body with a rotation: quadratic damping "
                                 "(D_q diag|nu|) does not rotate into the body's axes; give it on the moving link",
                                 extras_source, where)
        B = np.zeros((6, 6))                 # link-to-body rotation of [angular; linear] vectors
        B[:3, :3] = B[3:, 3:] = R
        body.damping = (B @ D_l @ B.T, D_q, p + R @ point)
        body.damping_cross = hydro.damping_cross
        body.damping_link = link


def _assemble(bodies: list[_Body], axes, frames, extras: VehicleExtras, robot_name: str, source: str,
              hydro_sources: tuple = ()) -> Model:
    """The :class:`Model` of the bodies (in tree order), their joints' axes and the frames (``hydro_sources``:
    :attr:`Model.hydro_sources`)."""
    from uvms.hydro.shapes import shape_drag_tables

    nb = len(bodies)
    n = nb - 1
    mass = np.zeros(nb)
    com = np.zeros((nb, 3))
    inertia_com = np.zeros((nb, 3, 3))
    cob = np.zeros((nb, 3))
    for i, body in enumerate(bodies):
        mass[i], com[i], inertia_com[i] = _mass_properties(body.inertia)
        if body.fluid_mass > 0.0:
            cob[i] = body.fluid_moment / body.fluid_mass
    carried = mass.copy()                      # mass of each body and everything it carries
    for i in range(nb - 1, 0, -1):
        carried[bodies[i].parent] += carried[i]
    for i in range(1, nb):
        if carried[i] <= 0.0:
            body = bodies[i]
            raise UvmsInputError(f"expected mass > 0 on link {body.link!r} (moved by joint {body.joint.name!r}) "
                                 "or on the links it carries, found none: a joint must move some mass", source,
                                 f"link {body.link!r}")
    joints = [b.joint for b in bodies[1:]]
    joint_axis = np.array(axes).reshape(n, 3)
    limits = np.tile([-np.inf, np.inf, np.inf, np.inf], (n, 1))
    damping, friction = np.zeros(n), np.zeros(n)
    speed = np.full(n, np.nan)
    for k, joint in enumerate(joints):
        where = f"joint {joint.name!r}"
        if joint.limit is not None:
            limits[k] = _joint_limits(joint, source, where)
        dyn = joint.dynamics
        if dyn is not None:
            damping[k] = float(dyn.damping or 0.0)
            friction[k] = float(dyn.friction or 0.0)
        for key, value in extras.joints.get(joint.name, {}).items():
            {"damping": damping, "friction": friction, "friction_speed": speed}[key][k] = value
        if not (math.isfinite(damping[k]) and math.isfinite(friction[k]) and damping[k] >= 0.0
                and friction[k] >= 0.0):
            raise UvmsInputError(f"expected finite damping and friction >= 0, found {damping[k]:g} and "
                                 f"{friction[k]:g}", source, where)
    speed[np.isnan(speed)] = DEFAULT_FRICTION_SPEED
    for name in extras.joints:
        if name not in [j.name for j in joints]:
            raise UvmsInputError(f"names joint {name!r}, which is not a moving joint of the URDF {source}",
                                 extras.source, f"joints.{name}")

    cyl_R = np.tile(np.eye(3), (n, 1, 1))
    cyl_o = np.zeros((n, 3))
    radius, length, cd = np.zeros(n), np.zeros(n), np.zeros(n)
    for i, body in enumerate(bodies[1:]):
        if body.cylinder is not None:
            cyl_R[i], cyl_o[i], radius[i], length[i], cd[i] = body.cylinder
    frame_list = [Frame(name, b, R, p) for name, b, R, p, _ in frames]
    if any(f.name == END_EFFECTOR for f in frame_list):
        raise UvmsInputError(f"a link may not be named {END_EFFECTOR!r} (the name of the end-effector frame)",
                             source, f"link {END_EFFECTOR!r}")
    if extras.end_effector is not None:
        ee = next((f for f in frame_list if f.name == extras.end_effector), None)
        if ee is None:
            raise UvmsInputError(f"names link {extras.end_effector!r}, which the URDF {source} does not have",
                                 extras.source, "end_effector")
    else:   # the deepest link, the first one in depth-first order on a tie
        deepest = max(range(len(frames)), key=lambda k: (frames[k][4], -k))
        ee = frame_list[deepest]
    frame_list.append(Frame(END_EFFECTOR, ee.body, ee.rotation, ee.position))
    return Model(
        name=extras.name or robot_name or Path(source).stem,
        source=extras.source or source,
        body_names=tuple(b.link for b in bodies),
        mass=mass, com=com, inertia_com=inertia_com,
        added_mass=np.array([b.added_mass for b in bodies]),
        buoyancy_mass=np.array([b.fluid_mass for b in bodies]), cob=cob,
        vehicle_drag_area=np.array(extras.vehicle_drag_area),
        vehicle_drag_coefficient=np.array(extras.vehicle_drag_coefficient),
        vehicle_rotational_drag_side=extras.vehicle_rotational_drag_side,
        vehicle_rotational_drag_coefficient=extras.vehicle_rotational_drag_coefficient,
        vehicle_box=np.array(extras.vehicle_box),
        link_radius=radius, link_length=length, link_drag_coefficient=cd,
        joint_rotation=np.array([b.R_joint for b in bodies[1:]]).reshape(n, 3, 3),
        joint_position=np.array([b.p_joint for b in bodies[1:]]).reshape(n, 3),
        theta_offset=np.zeros(n),
        ee_rotation=ee.rotation, ee_position=ee.position,
        density=extras.density, gravity=np.array(extras.gravity), current=np.array(extras.current),
        fluid_acceleration=np.array(extras.fluid_acceleration), thrusters=tuple(extras.thrusters),
        joint_names=tuple(j.name for j in joints),
        joint_parent=np.array([b.parent for b in bodies[1:]], dtype=np.int64),
        joint_type=tuple(j.type for j in joints),
        joint_axis=joint_axis, joint_damping=damping, joint_friction=friction, joint_friction_speed=speed,
        joint_limits=limits, link_cylinder_rotation=cyl_R, link_cylinder_origin=cyl_o, ee_body=ee.body,
        frames=tuple(frame_list),
        damping_linear=np.array([b.damping[0] if b.damping else np.zeros((6, 6)) for b in bodies]),
        damping_quadratic=np.array([b.damping[1] if b.damping else np.zeros((6, 6)) for b in bodies]),
        damping_point=np.array([b.damping[2] if b.damping else np.zeros(3) for b in bodies]).reshape(nb, 3),
        damping_cross=np.array([b.damping_cross if b.damping_cross is not None else np.zeros((2, 6, 6, 6))
                                for b in bodies]),
        shape_drag=shape_drag_tables([b.shapes for b in bodies]),
        shape_count=np.array([len(b.shapes) for b in bodies]),
        convention=extras.frame, hydro_sources=hydro_sources,
    )


def _joint_limits(joint, source: str, where: str) -> np.ndarray:
    """``[lower, upper, effort, velocity]`` of a joint's ``<limit>`` (``inf`` where absent; a continuous joint
    has no position limits, an effort or velocity ``<= 0`` means none); NaN, ``lower > upper`` and infinite
    effort or velocity written out are refused."""
    lim = joint.limit
    out = np.array([-np.inf, np.inf, np.inf, np.inf])
    values = {key: None if getattr(lim, key) is None else float(getattr(lim, key))
              for key in ("lower", "upper", "effort", "velocity")}
    for key, value in values.items():
        if value is not None and math.isnan(value):
            raise UvmsInputError(f"expected a number for <limit {key}>, found NaN", source, where)
    if joint.type != "continuous":              # a continuous joint has no position limits
        lower, upper = values["lower"], values["upper"]
        out[0] = -np.inf if lower is None else lower
        out[1] = np.inf if upper is None else upper
        if out[0] > out[1]:
            raise UvmsInputError(f"expected <limit lower> <= upper, found lower {out[0]:g} > upper {out[1]:g}",
                                 source, where)
    for column, key in ((2, "effort"), (3, "velocity")):
        value = values[key]
        if value is not None and value > 0.0:
            if math.isinf(value):
                raise UvmsInputError(f"expected a finite <limit {key}>, found {value:g} (leave it out or "
                                     "give 0 for none)", source, where)
            out[column] = value
    return out


def _warn_missing_meshes(robot, base: Path, source: str) -> None:
    """Warn (never fail) about visual or collision mesh files that do not exist: the dynamics does not use them.
    ``package://`` and ``file://`` names are looked up relative to the URDF's folder and its parents."""
    missing: list[str] = []
    for link in robot.links:
        for item in list(link.visuals or []) + list(link.collisions or []):
            mesh = getattr(getattr(item, "geometry", None), "mesh", None)
            if mesh is None or not mesh.filename:
                continue
            name = mesh.filename
            if name.startswith("file://"):
                candidates = [Path(name[len("file://"):])]
            elif name.startswith("package://"):
                rest = name[len("package://"):]
                tail = rest.split("/", 1)[1] if "/" in rest else rest
                candidates = [d / tail for d in [base, *base.parents]][:6] + \
                             [d / rest for d in [base, *base.parents]][:6]
            else:
                candidates = [base / name]
            if not any(c.exists() for c in candidates):
                missing.append(name)
    if missing:
        warnings.warn(f"{source}: {len(missing)} mesh file(s) not found (not needed for the dynamics), e.g. "
                      f"{missing[0]}", stacklevel=3)
