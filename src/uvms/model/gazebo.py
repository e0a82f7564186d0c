"""What Gazebo plugin tags give a robot description, and how they join uvms's model (``docs/models.md``,
"UUV Simulator and Gazebo files").

:mod:`uvms.model.uuv` (UUV Simulator's URDF plugins) and :mod:`uvms.model.sdf` (gz-sim's systems) read their
tags into one form, :class:`PluginTags`: per link hydrodynamics already in the link's own axes, uvms's
``[angular; linear]`` order and matrix-entry signs, thrusters by link and joint, the fluid and the world.
This module joins them to the robot's tree (:func:`uvms.model.urdf.model_from_robot`):

* a link the model YAML's additions describe keeps the additions' description (the file's tags are then
  ignored for it, reported); the vehicle's additions count only when they hold something;
* the frame convention of a bare file with plugin tags is ``enu`` (Gazebo's world is z up, its links x forward,
  y left, z up), gravity 9.81 m/s^2 down in it unless the file's world says otherwise;
* joints are frozen (made fixed) when their limits pin them (``lower = upper``: fixed at that value), when a
  thruster spins them (the rotor is not a degree of freedom of the vehicle), or when the body they move has
  no mass or no rotational inertia about their axis (a frame or a sensor mount the dynamics could not
  accelerate, ``docs/conventions.md`` decision 20); each is named in one warning (the thrusters' spin joints
  excepted: they are always frozen), with every tag not mapped.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from uvms.errors import UvmsInputError


@dataclass
class LinkTags:
    """The hydrodynamics a file's tags give one link, in the link's own frame and uvms's order and signs."""

    name: str
    added_mass: np.ndarray | None = None
    damping_linear: np.ndarray | None = None
    damping_quadratic: np.ndarray | None = None
    damping_cross: np.ndarray | None = None
    volume: float = 0.0
    neutrally_buoyant: bool = False
    center: np.ndarray = field(default_factory=lambda: np.zeros(3))
    shapes: list = field(default_factory=list)
    shape_added_mass: bool = True
    """Whether the shapes give the added mass (UUV's sphere, cylinder, spheroid) or not (gz's collisions)."""
    shape_buoyancy: bool = True
    """Whether the shapes give the buoyancy (when no volume is stated) or not."""
    origins: dict[str, str] = field(default_factory=dict)
    """Quantity -> the tag it came from (for ``uvms validate``)."""


@dataclass
class ThrusterTags:
    """One thruster: the link it pushes, the joint whose axis it pushes along, its kind and limit."""

    link: str
    joint: str
    thruster_id: int
    model: str                 # "ideal" or "first_order"
    max_thrust: float
    time_constant: float | None = None


@dataclass
class PluginTags:
    """What a robot description's Gazebo plugins say."""

    links: dict[str, LinkTags] = field(default_factory=dict)
    thrusters: list[ThrusterTags] = field(default_factory=list)
    fluid_density: float | None = None
    gravity: tuple | None = None
    """World gravity of an SDF world file [m/s^2], z up."""
    current: tuple | None = None
    ignored: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    z_up: bool = False
    """The file is a Gazebo description whatever its plugins (an SDF): ``enu`` by default."""

    @property
    def present(self) -> bool:
        return bool(self.links or self.thrusters or self.z_up)


def no_tags() -> PluginTags:
    return PluginTags()


def resolved_extras(extras, tags: PluginTags):
    """``extras`` with the frame, gravity, density and current the caller left to the file (``None``)."""
    from uvms.frames import default_gravity

    frame = extras.frame if extras.frame is not None else ("enu" if tags.present else "ned")
    gravity = extras.gravity
    if gravity is None:
        gravity = tuple(tags.gravity) if tags.gravity is not None else tuple(default_gravity(frame))
        if tags.gravity is not None and frame == "ned":
            gravity = (gravity[0], -gravity[1], -gravity[2])
    density = extras.density if extras.density is not None else (tags.fluid_density or 1000.0)
    current = extras.current
    if current is None:
        current = tuple(tags.current) if tags.current is not None else (0.0, 0.0, 0.0)
        if frame == "ned":
            current = (current[0], -current[1], -current[2])
    return replace(extras, frame=frame, gravity=gravity, density=density, current=current)


def pinned_pose(joint, value: float, R_o: np.ndarray, p_o: np.ndarray):
    """The pose of a pinned joint's child frame in its parent at ``q = value`` (URDF: origin, then the motion
    about / along the unit axis)."""
    from uvms.spatial import skew

    axis = np.array([1.0, 0.0, 0.0]) if joint.axis is None else np.asarray(joint.axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    if joint.type == "prismatic":
        return R_o, p_o + R_o @ (axis * value)
    K = skew(axis)
    rotation = np.eye(3) + math.sin(value) * K + (1.0 - math.cos(value)) * K @ K     # Rodrigues
    return R_o @ rotation, p_o


def thrusters_of(tags: PluginTags, frames, robot, source: str) -> tuple:
    """uvms thrusters of the plugin thrusters: along the joint's axis at its child link's origin, vehicle frame."""
    from uvms.thrusters.first_order import FirstOrderParameters
    from uvms.thrusters.ideal import IdealParameters
    from uvms.thrusters.layouts import Thruster

    joints = {j.name: j for j in robot.joints}
    by_link = {name: (b, R, p) for name, b, R, p, _ in frames}
    out = []
    for t in tags.thrusters:
        joint = joints[t.joint]
        link = t.link or joint.child
        if link not in by_link:
            raise UvmsInputError(f"the thruster plugin names link {link!r}, which the description does not have",
                                 source, f"thruster {t.thruster_id}")
        b, R, p = by_link[joint.child]
        if b != 0:
            raise UvmsInputError(f"thruster link {joint.child!r} is moved by a joint of the arm; uvms's thrusters "
                                 "push the vehicle (freeze the joint)", source, f"thruster {t.thruster_id}")
        axis = np.array([1.0, 0.0, 0.0]) if joint.axis is None else np.asarray(joint.axis, dtype=float)
        name = f"thruster_{t.thruster_id}"
        if t.model == "first_order":
            thruster = Thruster(name, tuple(p), tuple(R @ axis), "first_order",
                                FirstOrderParameters(time_constant=t.time_constant, max_thrust=t.max_thrust))
        else:
            thruster = Thruster(name, tuple(p), tuple(R @ axis), "ideal", IdealParameters(max_thrust=t.max_thrust))
        out.append(thruster)
    return tuple(out)


def warn_unmapped(source: str, notes: list[str], ignored: list[str]) -> None:
    """One warning line: what was frozen or approximated, and the tags not mapped."""
    parts: list[str] = []
    grouped: dict[tuple[str, str], list[str]] = {}
    for note in notes:                       # "thruster 3: <text>", "link 'a': <text>" of one text in one part
        head, _, text = note.partition(": ")
        kind, _, name = head.partition(" ")
        if kind in ("thruster", "link") and name and text:
            grouped.setdefault((kind, text), []).append(name)
        else:
            parts.append(note)
    parts += [f"{kind}{'s' if len(names) > 1 else ''} {', '.join(names[:6])}{' ...' if len(names) > 6 else ''}: "
              f"{text}" for (kind, text), names in grouped.items()]
    if ignored:
        unique = list(dict.fromkeys(ignored))
        parts.append(f"{len(unique)} tag(s) not mapped: {', '.join(unique[:12])}"
                     f"{' ...' if len(unique) > 12 else ''}")
    if parts:
        warnings.warn(f"{source}: {'; '.join(parts)} (docs/models.md, \"UUV Simulator and Gazebo files\")",
                      stacklevel=4)
