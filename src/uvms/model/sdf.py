"""SDF (SDFormat, gz-sim's model format) -> :class:`~uvms.model.model.Model` (``docs/models.md``, "UUV Simulator
and Gazebo files").

A model file (``<sdf><model>``) or a world file holding one model (``<sdf><world><model>``; static models such as
a ground plane are left out) is read with ``defusedxml`` (no DTD, no entities; at most :data:`MAX_SDF_BYTES` and
:data:`MAX_ELEMENTS` elements) and turned into the same kinematic tree as a URDF
(:func:`uvms.model.urdf.model_from_robot`), with its Gazebo systems (facts from the SDFormat specification and
gz-sim's ``Hydrodynamics.cc``, ``HydrodynamicsUtils.hh``, ``Thruster.cc``, ``Buoyancy.cc``, Apache-2.0):

* **Poses** (SDFormat "specify_pose"): a link's ``<pose>`` is in the model frame unless ``relative_to`` names
  another frame (a link, a joint, a ``<frame>`` or ``__model__``); a joint's in its child link's frame; a
  ``<frame>``'s in the frame it is ``attached_to``; ``x y z roll pitch yaw`` (``R = Rz(yaw) Ry(pitch) Rx(roll)``,
  ``degrees="true"`` allowed) or ``rotation_format="quat_xyzw"``. A joint's ``<axis><xyz>`` is in the joint
  frame (``expressed_in`` may name another frame; SDF 1.4-1.6's ``use_parent_model_frame`` the model frame).
  A child link's uvms frame is its joint's frame (the URDF rule): the same as the SDF link frame whenever the
  joint pose is the identity, as it almost always is.
* **Bodies**: ``<inertial>`` (mass, ``ixx`` ..., its ``<pose>``; SDFormat's defaults where absent: 1 kg, unit
  moments, as gz-sim uses them); joints ``revolute``, ``continuous``,
  ``prismatic``, ``fixed`` with ``<limit>`` and ``<dynamics damping friction>``; ``<fluid_added_mass>`` (SDF 1.11:
  ``xx xy ... rr``, the upper triangle of the symmetric linear-first matrix about the inertial frame) as the
  link's added mass.
* **Hydrodynamics system** (``gz::sim::systems::Hydrodynamics``, per ``link_name``): ``xDotU`` ... ``nDotR``
  (SNAME derivatives: ``M_A = -[xDotU ...]``), linear ``xU`` ..., quadratic ``xUabsU`` ... and every mixed
  ``xUabsV``, ``xUV`` (the force ``D(nu) nu`` with ``D(i, j) = lin[i, j] + sum_k quadAbs[i, j, k] |nu_k| +
  quad[i, j, k] nu_k``), all in the link's axes, linear-first, about the link origin; ``default_current``
  (world). uvms's diagonal ``F_a|a|`` terms hold ``quadAbs[i, j, j]``, the rest goes to the mixed damping
  (:attr:`uvms.model.model.Model.damping_cross`). The added mass goes into the articulated inertia, where gz-sim
  applies ``-M_A nu_dot`` from the previous step's finite difference (the term that blows up when ``M_A``
  approaches the rigid mass, gz-sim issue 1923); uvms's added-mass Coriolis force ``-(nu x*) M_A nu`` uses the
  whole matrix, gz-sim's only its diagonal (the same for a diagonal ``M_A``, reported otherwise).
  ``disable_coriolis`` and ``disable_added_mass`` cannot separate what uvms computes together (reported).
* **Thruster system** (``joint_name``): the thrust acts along the joint's axis at its child link's origin; it
  is an ``ideal`` uvms thruster limited by ``max_thrust_cmd`` / ``min_thrust_cmd`` (default +/-1000 N; the smaller
  magnitude); ``thrust_coefficient``, ``propeller_diameter``, ``fluid_density``, ``wake_fraction``, ``alpha_1``,
  ``alpha_2`` only turn the thrust into a propeller speed, which uvms does not need (read, not used); a thruster
  with ``use_angvel_cmd`` true (commanded by the propeller's angular velocity in gz-sim) is noted in the warning:
  uvms's command is the thrust.
* **Buoyancy system** (``gz-sim-buoyancy-system``, world): ``uniform_fluid_density`` times the volume of each
  link's box, sphere, cylinder and ellipsoid collisions at their volume centre (meshes, capsules and cones and
  ``graded_buoyancy`` are not mapped, reported). The world's ``<gravity>`` is read.
"""

from __future__ import annotations

import io
import math
import os
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from uvms.errors import UvmsInputError
from uvms.model.gazebo import LinkTags, PluginTags, ThrusterTags

MAX_SDF_BYTES = 16 * 1024 * 1024
"""Largest ``.sdf`` file read [bytes] (checked before reading)."""
MAX_ELEMENTS = 200_000
"""Most XML elements of an SDF file, counted while it is parsed."""
SDF_SUFFIXES = (".sdf", ".world")
MOMENT = "xyzkmn"
VELOCITY = "UVWPQR"
_REORDER = np.array([3, 4, 5, 0, 1, 2])          # uvms index -> gz (linear-first) index
HYDRODYNAMICS = "Hydrodynamics"
THRUSTER = "Thruster"
BUOYANCY = "Buoyancy"


def _xml(path: Path, source: str):
    from xml.etree.ElementTree import ParseError

    from defusedxml import DefusedXmlException
    from defusedxml.ElementTree import iterparse

    if not path.is_file():
        raise UvmsInputError("no such file" if not path.exists() else "expected an SDF file", source)
    size = path.stat().st_size
    if size > MAX_SDF_BYTES:
        raise UvmsInputError(f"SDF file of {size:,} bytes, over the limit of {MAX_SDF_BYTES:,}", source)
    count = 0
    events = iterparse(io.BytesIO(path.read_bytes()), events=("start",), forbid_dtd=True)
    try:
        for _ in events:
            count += 1
            if count > MAX_ELEMENTS:
                raise UvmsInputError(f"more than {MAX_ELEMENTS:,} XML elements (the limit of an SDF file)", source)
    except ParseError as exc:
        line, column = exc.position
        raise UvmsInputError(f"invalid XML: {str(exc).split(':')[0]}", source, f"line {line}, column {column + 1}") \
            from None
    except DefusedXmlException:
        raise UvmsInputError("a DTD or entity declaration (<!DOCTYPE ...>, <!ENTITY ...>) is not allowed in an SDF "
                             "file", source) from None
    return events.root


def _floats(text: str | None, n: int | None, source: str, where: str) -> np.ndarray:
    words = (text or "").split()
    try:
        values = np.array([float(w) for w in words])
    except ValueError:
        raise UvmsInputError(f"expected numbers, found {' '.join(words)[:60]!r}", source, where) from None
    if n is not None and values.size != n:
        raise UvmsInputError(f"expected {n} numbers, found {values.size}", source, where)
    if not np.all(np.isfinite(values)):
        raise UvmsInputError("expected finite numbers, found NaN or infinity", source, where)
    return values


def _scalar(parent, tag: str, default: float, source: str, where: str) -> float:
    element = parent.find(tag)
    if element is None:
        return default
    return float(_floats(element.text, 1, source, f"{where}.{tag}")[0])


def _pose_of(element, source: str, where: str) -> tuple[np.ndarray, np.ndarray, str | None]:
    """``(R, p, relative_to)`` of an element's ``<pose>`` (identity when absent)."""
    from uvms.rotations import rotation_from_euler, rotation_from_quaternion  # numba: not before the file parsed

    pose = element.find("pose")
    if pose is None:
        return np.eye(3), np.zeros(3), None
    fmt = pose.get("rotation_format", "euler_rpy")
    if fmt == "quat_xyzw":
        v = _floats(pose.text, 7, source, f"{where}.pose")
        q = v[[6, 3, 4, 5]]
        R = rotation_from_quaternion(q / np.linalg.norm(q))
    elif fmt == "euler_rpy":
        v = _floats(pose.text, 6, source, f"{where}.pose")
        angles = np.radians(v[3:]) if pose.get("degrees", "false").strip().lower() == "true" else v[3:]
        R = rotation_from_euler(np.array([angles[0], angles[1], angles[2]]))
    else:
        raise UvmsInputError(f"expected rotation_format euler_rpy or quat_xyzw, found {fmt[:30]!r}", source,
                             f"{where}.pose")
    return R, v[:3].copy(), pose.get("relative_to") or None


def _model(root, source: str, tags: PluginTags):
    """The one ``<model>`` of a model or world file, and its world (or ``None``)."""
    if root.tag != "sdf":
        raise UvmsInputError(f"expected an <sdf> element at the top level, found <{root.tag}>", source)
    worlds = root.findall("world")
    if len(worlds) > 1:
        raise UvmsInputError(f"expected one <world>, found {len(worlds)}", source)
    world = worlds[0] if worlds else None
    scope = world if world is not None else root
    if scope.find("include") is not None:
        uri = (scope.find("include").findtext("uri") or "").strip()
        raise UvmsInputError(f"an <include> ({uri[:80]}) is not read: uvms reads no model from outside the file; "
                             "put the model's SDF in the file", source, "include")
    models = [m for m in scope.findall("model") if (m.findtext("static") or "false").strip().lower()
              not in ("true", "1")]
    static = [m.get("name") for m in scope.findall("model") if m not in models]
    if static:
        tags.ignored.append(f"static model(s) {', '.join(map(str, static[:3]))}")
    if len(models) != 1:
        raise UvmsInputError(f"expected one (non-static) <model>, found {len(models)}", source)
    model = models[0]
    for nested in ("model", "include"):
        if model.find(nested) is not None:
            raise UvmsInputError(f"a nested <{nested}> is not supported: write its links in the model", source,
                                 f"model {model.get('name')!r}")
    return model, world


class _Frames:
    """Poses of the model's frames in the model frame (SDFormat's pose-frame semantics)."""

    def __init__(self, model, source: str) -> None:
        self.source = source
        self.defs: dict[str, tuple] = {}
        self.done: dict[str, tuple[np.ndarray, np.ndarray]] = {"__model__": (np.eye(3), np.zeros(3))}
        for link in model.findall("link"):
            R, p, rel = _pose_of(link, source, f"link {link.get('name')!r}")
            self.defs[link.get("name")] = (R, p, rel or "__model__")
        for joint in model.findall("joint"):
            R, p, rel = _pose_of(joint, source, f"joint {joint.get('name')!r}")
            self.defs[joint.get("name")] = (R, p, rel or (joint.findtext("child") or "").strip())
        for frame in model.findall("frame"):
            R, p, rel = _pose_of(frame, source, f"frame {frame.get('name')!r}")
            self.defs[frame.get("name")] = (R, p, rel or frame.get("attached_to") or "__model__")

    def pose(self, name: str, seen: tuple = ()) -> tuple[np.ndarray, np.ndarray]:
        if name in self.done:
            return self.done[name]
        if name not in self.defs:
            raise UvmsInputError(f"a pose is relative to {name!r}, which is not a frame of the model", self.source)
        if name in seen:
            raise UvmsInputError(f"the poses relative to {name!r} form a loop", self.source)
        R, p, rel = self.defs[name]
        R0, p0 = self.pose(rel, (*seen, name))
        self.done[name] = (R0 @ R, p0 + R0 @ p)
        return self.done[name]

    def of(self, element, default: str, where: str) -> tuple[np.ndarray, np.ndarray]:
        """The pose in the model frame of a nested element's ``<pose>`` (relative to ``default``)."""
        R, p, rel = _pose_of(element, self.source, where)
        R0, p0 = self.pose(rel or default)
        return R0 @ R, p0 + R0 @ p


def _origin(R: np.ndarray, p: np.ndarray):
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


def _relative(frame_R, frame_p, R, p):
    """Pose ``(R, p)`` (model frame) in the frame ``(frame_R, frame_p)``."""
    return frame_R.T @ R, frame_R.T @ (p - frame_p)


def _geometry(collision, source: str, where: str):
    g = collision.find("geometry")
    if g is None:
        return None
    for kind in ("box", "sphere", "cylinder", "ellipsoid", "capsule", "mesh", "cone", "plane"):
        e = g.find(kind)
        if e is not None:
            return kind, e
    return None


def _robot(model, source: str, tags: PluginTags, added: dict, shapes: dict):
    """The model as a ``yourdfpy``-shaped robot (links with inertials and collisions, joints with origins in
    their parent's uvms frame), uvms frames being the SDF link frame (root) or the joint frame (children)."""
    from uvms.hydro import shapes as hs

    frames = _Frames(model, source)
    links, joints = model.findall("link"), model.findall("joint")
    names = [link.get("name") for link in links]
    if any(not n for n in names):
        raise UvmsInputError("expected a name attribute on every <link>", source)
    child_joint: dict[str, object] = {}
    for joint in joints:
        name = joint.get("name")
        where = f"joint {name!r}"
        if not name or not joint.get("type"):
            raise UvmsInputError("expected name and type attributes", source, where)
        for role in ("parent", "child"):
            if not (joint.findtext(role) or "").strip():
                raise UvmsInputError(f"expected a <{role}> link", source, where)
        child_joint[(joint.findtext("child") or "").strip()] = joint
    uvms_frame: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for name in names:   # a child link's uvms frame is its joint's frame
        joint = child_joint.get(name)
        uvms_frame[name] = frames.pose(joint.get("name") if joint is not None else name)
    out_links, out_joints = [], []
    for link in links:
        name = link.get("name")
        where = f"link {name!r}"
        R_u, p_u = uvms_frame[name]
        R_l, p_l = frames.pose(name)
        element = link.find("inertial")
        if element is None:                     # SDFormat's defaults: 1 kg, unit inertia
            inertial = SimpleNamespace(mass=1.0, inertia=np.eye(3), origin=_origin(*_relative(R_u, p_u, R_l, p_l)))
        else:
            R_i, p_i = frames.of(element, name, f"{where}.inertial")
            R_i, p_i = _relative(R_u, p_u, R_i, p_i)
            mass = _scalar(element, "mass", 1.0, source, f"{where}.inertial")
            I = np.eye(3)
            inertia = element.find("inertia")
            if inertia is not None:
                v = {k: _scalar(inertia, k, 1.0 if k in ("ixx", "iyy", "izz") else 0.0, source,
                                f"{where}.inertial.inertia") for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
                I = np.array([[v["ixx"], v["ixy"], v["ixz"]], [v["ixy"], v["iyy"], v["iyz"]],
                              [v["ixz"], v["iyz"], v["izz"]]])
            inertial = SimpleNamespace(mass=mass, inertia=I, origin=_origin(R_i, p_i))
            fam = element.find("fluid_added_mass")
            if fam is not None:
                M = np.zeros((6, 6))
                axes = "xyzpqr"
                for a in range(6):
                    for b in range(a, 6):
                        M[a, b] = M[b, a] = _scalar(fam, axes[a] + axes[b], 0.0, source, f"{where}.fluid_added_mass")
                from uvms.spatial import plucker

                A = M[np.ix_(_REORDER, _REORDER)]                  # [angular; linear], inertial frame
                X = plucker(R_i.T, p_i)                            # uvms link frame -> inertial frame
                added[name] = (X.T @ A @ X, "inertial/fluid_added_mass")
        collisions, primitives = [], []
        for k, collision in enumerate(link.findall("collision")):
            geometry = _geometry(collision, source, where)
            if geometry is None:
                continue
            kind, g = geometry
            R_c, p_c = _relative(R_u, p_u, *frames.of(collision, name, f"{where}.collision"))
            cw = f"{where}.collision[{k}].{kind}"
            none = {"box": None, "cylinder": None, "sphere": None, "mesh": None}
            if kind == "box":
                size = _floats(g.findtext("size"), 3, source, f"{cw}.size")
                collisions.append(hs.Box(tuple(size), (0.0, 0.0, 0.0), rotation=R_c, position=p_c))
                geometry = {**none, "box": SimpleNamespace(size=size)}
            elif kind == "sphere":
                radius = _scalar(g, "radius", 1.0, source, cw)
                collisions.append(hs.Sphere(radius, 0.0, rotation=R_c, position=p_c))
                geometry = {**none, "sphere": SimpleNamespace(radius=radius)}
            elif kind == "cylinder":
                to_x = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])   # SDF cylinders run along z
                radius, length = _scalar(g, "radius", 1.0, source, cw), _scalar(g, "length", 1.0, source, cw)
                collisions.append(hs.Cylinder(radius, length, 0.0, rotation=R_c @ to_x, position=p_c))
                geometry = {**none, "cylinder": SimpleNamespace(radius=radius, length=length)}
            elif kind == "ellipsoid":
                radii = _floats(g.findtext("radii"), 3, source, f"{cw}.radii")
                collisions.append(hs.Ellipsoid(tuple(radii), 0.0, rotation=R_c, position=p_c))
            elif kind != "plane":
                tags.ignored.append(f"{name}/collision {kind} (no volume for buoyancy)")
            if kind in ("box", "sphere", "cylinder"):    # for a model YAML's shapes: [{type: from_collision}]
                primitives.append(SimpleNamespace(origin=_origin(R_c, p_c), geometry=SimpleNamespace(**geometry)))
        shapes[name] = collisions
        out_links.append(SimpleNamespace(name=name, inertial=inertial, collisions=primitives, visuals=[]))
    for joint in joints:
        name = joint.get("name")
        where = f"joint {name!r}"
        parent, child = (joint.findtext("parent") or "").strip(), (joint.findtext("child") or "").strip()
        if parent == "world":
            raise UvmsInputError("a joint to the world fixes the vehicle: uvms's vehicle is free (clamp it with "
                                 "fixed_base instead)", source, where)
        for link in (parent, child):
            if link not in uvms_frame:
                raise UvmsInputError(f"names link {link!r}, which the model does not have", source, where)
        R_j, p_j = _relative(*uvms_frame[parent], *uvms_frame[child])
        kind = joint.get("type")
        axis, limit, dynamics = None, None, None
        element = joint.find("axis")
        if kind in ("revolute", "continuous", "prismatic"):
            if element is None:
                raise UvmsInputError(f"expected an <axis> for a {kind} joint", source, where)
            xyz = element.find("xyz")
            axis = _floats(xyz.text if xyz is not None else "0 0 1", 3, source, f"{where}.axis.xyz")
            expressed = xyz.get("expressed_in") if xyz is not None else None
            if (element.findtext("use_parent_model_frame") or "").strip().lower() in ("1", "true"):
                expressed = "__model__"
            if expressed:
                R_e, _ = frames.pose(expressed)
                axis = uvms_frame[child][0].T @ (R_e @ axis)
            lim = element.find("limit")
            if lim is not None:
                lower = _scalar(lim, "lower", -1e16, source, f"{where}.axis.limit")
                upper = _scalar(lim, "upper", 1e16, source, f"{where}.axis.limit")
                limit = SimpleNamespace(lower=None if lower <= -1e16 else lower, upper=None if upper >= 1e16 else upper,
                                        effort=_scalar(lim, "effort", -1.0, source, where),
                                        velocity=_scalar(lim, "velocity", -1.0, source, where))
            dyn = element.find("dynamics")
            if dyn is not None:
                dynamics = SimpleNamespace(damping=_scalar(dyn, "damping", 0.0, source, where),
                                           friction=_scalar(dyn, "friction", 0.0, source, where))
        elif kind not in ("fixed",):
            raise UvmsInputError(f"unsupported joint type {kind!r}; expected revolute, continuous, prismatic or "
                                 "fixed", source, where)
        out_joints.append(SimpleNamespace(name=name, type=kind, parent=parent, child=child, origin=_origin(R_j, p_j),
                                          axis=axis, limit=limit, dynamics=dynamics, mimic=None))
    return SimpleNamespace(name=model.get("name") or "model", links=out_links, joints=out_joints)


def _hydrodynamics(plugin, tags: PluginTags, source: str) -> None:
    """One Hydrodynamics system into ``tags.links`` (gz-sim's ``Configure``: SNAME names)."""
    link = (plugin.findtext("link_name") or "").strip()
    where = f"plugin Hydrodynamics ({link})"
    if not link:
        raise UvmsInputError("expected a <link_name>", source, "plugin Hydrodynamics")
    known = {"link_name", "default_current", "disable_coriolis", "disable_added_mass", "water_density", "namespace"}
    Ma, lin = np.zeros((6, 6)), np.zeros((6, 6))
    quad_abs, quad = np.zeros((6, 6, 6)), np.zeros((6, 6, 6))
    for i in range(6):
        for j in range(6):
            name = MOMENT[i] + VELOCITY[j]
            for array, tag in ((lin, name), (Ma, f"{MOMENT[i]}Dot{VELOCITY[j]}")):
                array[i, j] = _scalar(plugin, tag, 0.0, source, where)
                known.add(tag)
            for k in range(6):
                quad_abs[i, j, k] = _scalar(plugin, f"{name}abs{VELOCITY[k]}", 0.0, source, where)
                quad[i, j, k] = _scalar(plugin, f"{name}{VELOCITY[k]}", 0.0, source, where)
                known.update((f"{name}abs{VELOCITY[k]}", f"{name}{VELOCITY[k]}"))
    tags.ignored.extend(f"Hydrodynamics/{c.tag}" for c in plugin if c.tag not in known)
    entry = tags.links.setdefault(link, LinkTags(link, shape_added_mass=False))
    flag = {key: (plugin.findtext(key) or "false").strip().lower() in ("1", "true")
            for key in ("disable_added_mass", "disable_coriolis")}
    ix = np.ix_(_REORDER, _REORDER)
    if np.any(Ma):
        if flag["disable_added_mass"]:
            tags.notes.append(f"{link}: disable_added_mass: the plugin's added mass is left out (with its Coriolis "
                              "force, which uvms does not separate)")
        else:
            entry.added_mass = -0.5 * (Ma + Ma.T)[ix]
            entry.origins["added mass"] = "Hydrodynamics xDotU ... nDotR"
            if np.any(Ma != Ma.T):
                tags.notes.append(f"{link}: Hydrodynamics added mass made symmetric")
            if flag["disable_coriolis"]:
                tags.notes.append(f"{link}: disable_coriolis not mapped (uvms keeps the added mass's Coriolis force)")
            if np.any(Ma - np.diag(np.diag(Ma))):
                tags.notes.append(f"{link}: uvms's added-mass Coriolis force uses the whole matrix, gz-sim's only "
                                  "its diagonal")
    entry.damping_linear = -lin[ix]
    diag = np.array([[quad_abs[i, j, j] for j in range(6)] for i in range(6)])
    entry.damping_quadratic = -diag[ix]
    C = np.zeros((2, 6, 6, 6))
    mixed = quad_abs.copy()
    for j in range(6):
        mixed[:, j, j] = 0.0
    tx = np.ix_(_REORDER, _REORDER, _REORDER)
    C[0], C[1] = -mixed[tx], -quad[tx]
    if np.any(C):
        entry.damping_cross = C
        entry.origins["mixed quadratic damping"] = "Hydrodynamics xUabsV ..., xUV ..."
    if np.any(lin):
        entry.origins["linear damping"] = "Hydrodynamics xU ... nR"
    if np.any(diag):
        entry.origins["quadratic damping"] = "Hydrodynamics xUabsU ... nRabsR"
    if plugin.find("default_current") is not None:
        tags.current = tuple(_floats(plugin.findtext("default_current"), 3, source, f"{where}.default_current"))
    if plugin.find("water_density") is not None and tags.fluid_density is None:
        tags.fluid_density = _scalar(plugin, "water_density", 1000.0, source, where)


def _thruster(plugin, tags: PluginTags, source: str) -> None:
    joint = (plugin.findtext("joint_name") or "").strip()
    where = f"plugin Thruster ({joint})"
    if not joint:
        raise UvmsInputError("expected a <joint_name>", source, "plugin Thruster")
    high = _scalar(plugin, "max_thrust_cmd", 1000.0, source, where)
    low = _scalar(plugin, "min_thrust_cmd", -1000.0, source, where)
    if high < low:
        raise UvmsInputError(f"expected max_thrust_cmd >= min_thrust_cmd, found {high:g} < {low:g}", source, where)
    limit = min(abs(high), abs(low))
    if abs(high) != abs(low):
        tags.notes.append(f"thruster {joint}: limits {high:g} N, {low:g} N; uvms uses +/-{limit:g} N")
    if (plugin.findtext("use_angvel_cmd") or "").strip().lower() in ("1", "true"):
        tags.notes.append(f"thruster {joint}: use_angvel_cmd: gz-sim commands it by the propeller's angular velocity "
                          "(thrust = thrust_coefficient rho D^4 omega |omega|), uvms by the thrust [N]")
    known = {"joint_name", "thrust_coefficient", "propeller_diameter", "fluid_density", "wake_fraction", "alpha_1",
             "alpha_2", "max_thrust_cmd", "min_thrust_cmd", "namespace", "topic", "use_angvel_cmd"}
    tags.ignored.extend(f"Thruster/{c.tag}" for c in plugin if c.tag not in known)
    tags.thrusters.append(ThrusterTags("", joint, len(tags.thrusters), "ideal", limit if limit > 0 else math.inf))


def _buoyancy(plugin, tags: PluginTags, shapes: dict, source: str) -> None:
    if plugin.find("graded_buoyancy") is not None:
        tags.ignored.append("Buoyancy/graded_buoyancy")
    rho = _scalar(plugin, "uniform_fluid_density", 1000.0, source, "plugin Buoyancy")
    if not rho > 0:
        raise UvmsInputError("expected a uniform_fluid_density > 0", source, "plugin Buoyancy")
    tags.fluid_density = rho
    for name, items in shapes.items():
        if items:
            entry = tags.links.setdefault(name, LinkTags(name, shape_added_mass=False))
            entry.shapes = list(items)
            entry.origins["buoyancy"] = "Buoyancy system: collision volumes"


def read_sdf(path: str | os.PathLike[str]):
    """``(robot, tags, added masses)`` of an SDF file (see the module's docstring)."""
    source = str(path)
    root = _xml(Path(path), source)
    tags = PluginTags(z_up=True)
    model, world = _model(root, source, tags)
    added: dict = {}
    shapes: dict = {}
    robot = _robot(model, source, tags, added, shapes)
    plugins = list(model.findall("plugin")) + (list(world.findall("plugin")) if world is not None else [])
    buoyancy = None
    for plugin in plugins:
        name = plugin.get("name") or ""
        filename = plugin.get("filename") or ""
        if name.endswith(HYDRODYNAMICS) or "hydrodynamics" in filename:
            _hydrodynamics(plugin, tags, source)
        elif name.endswith(THRUSTER) or "thruster" in filename:
            _thruster(plugin, tags, source)
        elif name.endswith(BUOYANCY) or "buoyancy-system" in filename:
            buoyancy = plugin
        elif not any(word in name for word in ("Physics", "SceneBroadcaster", "UserCommands", "Sensors")):
            tags.ignored.append(f"plugin {name or filename}")
    if buoyancy is not None:
        _buoyancy(buoyancy, tags, shapes, source)
    for name, (A, origin) in added.items():
        entry = tags.links.setdefault(name, LinkTags(name, shape_added_mass=False))
        if entry.added_mass is not None:
            raise UvmsInputError(f"link {name!r} has <fluid_added_mass> and Hydrodynamics added mass: it would "
                                 "count twice (give one, or disable_added_mass)", source, f"link {name!r}")
        entry.added_mass = A
        entry.origins["added mass"] = origin
    for entry in tags.links.values():
        entry.shape_buoyancy = buoyancy is not None
    if world is not None and world.find("gravity") is not None:
        tags.gravity = tuple(_floats(world.findtext("gravity"), 3, source, "world.gravity"))
    elif world is not None:
        tags.gravity = (0.0, 0.0, -9.8)          # SDFormat's default world gravity
    return robot, tags


def model_from_sdf(path: str | os.PathLike[str], extras=None, *, balance_inertia: bool = False):
    """The :class:`~uvms.model.model.Model` of an SDF model or world file (with a model YAML's ``extras``)."""
    from uvms.model.urdf import VehicleExtras, model_from_robot

    robot, tags = read_sdf(path)
    extras = extras if extras is not None else VehicleExtras(frame=None, gravity=None, density=None, current=None)
    return model_from_robot(robot, str(path), extras, tags, balance_inertia or extras.balance_inertia)


def is_sdf(path: str | os.PathLike[str]) -> bool:
    """Whether a path names an SDF file (by its suffix)."""
    return str(path).lower().endswith(SDF_SUFFIXES)
