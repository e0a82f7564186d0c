"""What a 3-D view of a model shows, independent of the drawing library.

A :class:`Scene` is built once from a model by :func:`scene_from_model` (the one place that knows which model
attributes carry geometry): a list of :class:`Primitive` shapes (box, cylinder, sphere, ellipsoid, mesh), each
fixed to one body at a pose in that body's frame, plus the bodies' centres of mass and buoyancy, the joint axes
and the thrusters. :func:`pose_scene` places it at one pose of the system (the body poses of
:func:`uvms.forward_kinematics`) and returns a :class:`Snapshot`: triangle meshes, frame triads, points and
arrows in world coordinates, which :mod:`uvms.view.plotly_html` and :mod:`uvms.view.png` draw.

Frames (``docs/conventions.md``, "Frames"): the world is the model's convention (``Scene.frame``): x north,
y east, z down (ned) or z up (enu), with :attr:`Scene.up` the world's up direction; body 0 is the vehicle (its frame at the
reference point of the model file), body i the i-th link (modified-DH frame i, the joint axis is its z axis);
the end-effector frame follows the last link. Shapes follow the URDF conventions: a box and a sphere are centred
on their pose, a cylinder's axis is its local z axis through its centre.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

KINDS = ("box", "cylinder", "sphere", "ellipsoid", "mesh")

VEHICLE_COLOR = "#f2b705"
LINK_COLOR = "#4f6d8f"
VISUAL_COLOR = "#9aa5b1"
CYLINDER_SEGMENTS = 24
SPHERE_SEGMENTS = (12, 18)   # (latitude, longitude) bands


@dataclass(frozen=True, eq=False)
class Primitive:
    """One shape fixed to one body.

    Attributes:
        kind: ``"box"``, ``"cylinder"``, ``"sphere"``, ``"ellipsoid"`` or ``"mesh"``.
        body: index of the body it moves with (0 the vehicle, i the i-th link).
        size: box ``(lx, ly, lz)`` edge lengths; cylinder ``(radius, length)`` (axis = local z, centred);
            sphere ``(radius,)``; ellipsoid ``(a, b, c)`` semi-axes; mesh ``(sx, sy, sz)`` scale factors [m, -].
        rotation: (3, 3) orientation of the shape in the body frame.
        position: (3,) centre of the shape (the mesh's own origin) in the body frame [m].
        vertices, faces: a mesh's own triangles (``(V, 3)`` [m] before scaling, ``(F, 3)`` vertex indices).
        name: label shown on hover.
        role: ``"vehicle"``, ``"link"`` (the hydrodynamic shapes of the model) or ``"visual"`` (meshes).
        color, opacity: how it is drawn.
    """

    kind: str
    body: int
    size: tuple[float, ...]
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    position: np.ndarray = field(default_factory=lambda: np.zeros(3))
    vertices: np.ndarray | None = None
    faces: np.ndarray | None = None
    name: str = ""
    role: str = "visual"
    color: str = VISUAL_COLOR
    opacity: float = 1.0

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"shape kind must be one of {', '.join(KINDS)}, got {self.kind!r}")
        object.__setattr__(self, "rotation", np.array(self.rotation, dtype=float).reshape(3, 3))
        object.__setattr__(self, "position", np.array(self.position, dtype=float).reshape(3))
        object.__setattr__(self, "size", tuple(float(s) for s in np.atleast_1d(self.size)))
        if self.kind == "mesh" and (self.vertices is None or self.faces is None):
            raise ValueError("a mesh shape needs vertices and faces")

    def local_mesh(self) -> tuple[np.ndarray, np.ndarray]:
        """Triangles of the shape in its body's frame: vertices (V, 3) [m] and faces (F, 3)."""
        V, F = _unit_mesh(self)
        return V @ self.rotation.T + self.position, F


@dataclass(frozen=True)
class ThrusterArrow:
    """A thruster drawn as an arrow on the vehicle: ``position`` and unit ``direction`` in the vehicle frame."""

    name: str
    position: np.ndarray
    direction: np.ndarray


@dataclass(frozen=True, eq=False)
class Scene:
    """Everything a view draws of one model (poses excluded). Build with :func:`scene_from_model`.

    Attributes:
        name: the model's name.
        body_names: (nb,) names.
        primitives: the shapes.
        com, cob: (nb, 3) centres of mass and buoyancy in the body frames [m].
        parent: (nb,) parent body of each body (-1 for the vehicle).
        joint_axes: (n, 3) unit axis of joint i in the frame of body i.
        thrusters: thruster arrows (vehicle frame).
        length: a characteristic size of the system [m]: sets the lengths of triads and arrows.
        frame: the model's convention, ``"ned"`` or ``"enu"`` (:mod:`uvms.frames`).
    """

    name: str
    body_names: tuple[str, ...]
    primitives: tuple[Primitive, ...]
    com: np.ndarray
    cob: np.ndarray
    parent: np.ndarray
    joint_axes: np.ndarray
    thrusters: tuple[ThrusterArrow, ...]
    length: float
    frame: str = "ned"

    @property
    def up(self) -> np.ndarray:
        """(3,) the world's up direction in world coordinates (:data:`uvms.frames.UP`): drawn upwards."""
        from uvms.frames import UP

        return UP[self.frame].copy()

    @property
    def world_labels(self) -> tuple[str, str, str]:
        """Labels of the world x, y, z axes (:data:`uvms.frames.WORLD_AXES`)."""
        from uvms.frames import WORLD_AXES

        return WORLD_AXES[self.frame]

    @property
    def reversed_axes(self) -> tuple[bool, bool, bool]:
        """Which world axes a view draws reversed so that :attr:`up` points up on the screen, unmirrored: y and
        z in ned (a half turn about x, not a mirror), none in enu."""
        return (False, True, True) if self.frame == "ned" else (False, False, False)

    @property
    def n_bodies(self) -> int:
        return len(self.body_names)

    @property
    def triad_length(self) -> float:
        """Length of a body's axes triad [m]."""
        return 0.25 * self.length

    @property
    def world_axis_length(self) -> float:
        """Length of the world axes drawn at the origin [m] (long enough to reach out of the vehicle)."""
        return 0.75 * self.length

    @property
    def arrow_length(self) -> float:
        """Length of a thruster arrow at full thrust [m]."""
        return 0.35 * self.length


def _rotation_z_to(axis: np.ndarray) -> np.ndarray:
    """A rotation taking the local z axis onto the unit vector ``axis``."""
    z = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def scene_from_model(model, thrusters=None) -> Scene:
    """The scene of ``model``: its shapes, centres of mass and buoyancy, joint axes and thrusters.

    The only function that reads geometry from a model: the vehicle box (``vehicle_box``), the links' drag
    cylinders (``link_radius``, ``link_length``: along the link's x axis from the joint, as in
    :mod:`uvms.hydro.drag`) and every body's hydrodynamic shapes (``shape_drag``, :mod:`uvms.hydro.shapes`); shapes a model may carry later are read with defaults, so adding them is one line
    here: ``model.shapes`` (hydrodynamic shapes) and ``model.visuals`` (e.g. a URDF's visual meshes), each an
    iterable of :class:`Primitive` or of descriptions :func:`primitive_from` understands (a mesh whose file
    is missing is left out). ``thrusters`` (default: ``model.thrusters``) are objects with ``name``,
    ``position`` and ``direction`` in the vehicle frame.
    """
    nb = int(model.n_bodies)
    n = nb - 1
    names = tuple(getattr(model, "body_names", ())) or tuple(f"body{i}" for i in range(nb))
    prims: list[Primitive] = []
    box = np.asarray(getattr(model, "vehicle_box", np.zeros(3)), dtype=float)
    if box.shape == (3,) and np.all(box > 0):
        prims.append(Primitive("box", 0, tuple(box), name=f"{names[0]} (box)", role="vehicle",
                               color=VEHICLE_COLOR, opacity=0.35))
    radius = np.asarray(getattr(model, "link_radius", np.zeros(n)), dtype=float)
    length = np.asarray(getattr(model, "link_length", np.zeros(n)), dtype=float)
    along_x = _rotation_z_to(np.array([1.0, 0.0, 0.0]))
    for i in range(min(n, radius.size, length.size)):
        if radius[i] > 0 and length[i] > 0:
            prims.append(Primitive("cylinder", i + 1, (radius[i], length[i]), rotation=along_x,
                                   position=(0.5 * length[i], 0.0, 0.0), name=f"{names[i + 1]} (cylinder)",
                                   role="link", color=LINK_COLOR, opacity=1.0))
    prims += _hydrodynamic_shapes(model, names)
    for group in ("shapes", "visuals"):
        for item in getattr(model, group, ()) or ():
            prim = primitive_from(item, role="link" if group == "shapes" else "visual")
            if prim is not None:
                prims.append(prim)
    kernel = getattr(model, "kernel", None)
    parent = np.asarray(getattr(kernel, "parent", np.arange(nb) - 1), dtype=int)
    axes = np.asarray(getattr(model, "joint_axis", np.tile([0.0, 0.0, 1.0], (n, 1))), dtype=float).reshape(n, 3)
    thr = tuple(getattr(model, "thrusters", ()) or ()) if thrusters is None else tuple(thrusters)
    arrows = tuple(ThrusterArrow(str(t.name), np.asarray(t.position, dtype=float),
                                 np.asarray(t.direction, dtype=float) / np.linalg.norm(t.direction)) for t in thr)
    reach = float(np.sum(length)) if length.size else 0.0
    size = max(float(box.max()) if box.size else 0.0, reach, 0.2)
    return Scene(name=str(getattr(model, "name", "model")), body_names=names, primitives=tuple(prims),
                 com=np.asarray(model.com, dtype=float).reshape(nb, 3),
                 cob=np.asarray(getattr(model, "cob", model.com), dtype=float).reshape(nb, 3),
                 parent=parent, joint_axes=axes / np.linalg.norm(axes, axis=1, keepdims=True) if n else axes,
                 thrusters=arrows, length=size, frame=str(getattr(model, "convention", "ned")))


def _hydrodynamic_shapes(model, names) -> list[Primitive]:
    """The hydrodynamic shapes of every body (``model.shape_drag`` rows, :func:`uvms.hydro.shapes.drag_table`
    layout: kind, shape-to-body rotation, centre, dimensions; a cylinder's axis is the shape frame's x, the
    cylinder primitive's is z)."""
    from uvms.hydro import shapes as hs

    table = getattr(model, "shape_drag", None)
    count = getattr(model, "shape_count", None)
    if table is None or count is None:
        return []
    x_to_z = _rotation_z_to(np.array([1.0, 0.0, 0.0]))
    out = []
    for body, k in enumerate(np.asarray(count, dtype=int)):
        for row in np.asarray(table[body][:k], dtype=float):
            kind = int(row[hs.COL_KIND])
            R = row[hs.COL_ROTATION:hs.COL_ROTATION + 9].reshape(3, 3)
            p = row[hs.COL_POSITION:hs.COL_POSITION + 3]
            d = row[hs.COL_DIMENSIONS:hs.COL_DIMENSIONS + 3]
            common = dict(position=tuple(p), name=f"{names[body]} (shape)", role="link", color=LINK_COLOR,
                          opacity=0.6)
            if kind == hs.KIND_SPHERE:
                out.append(Primitive("sphere", body, (d[0],), rotation=R, **common))
            elif kind == hs.KIND_BOX:
                out.append(Primitive("box", body, tuple(2.0 * d), rotation=R, **common))
            elif kind == hs.KIND_CYLINDER:
                out.append(Primitive("cylinder", body, (d[0], d[1]), rotation=R @ x_to_z, **common))
            elif kind == hs.KIND_ELLIPSOID:
                out.append(Primitive("ellipsoid", body, tuple(d), rotation=R, **common))
    return out


def _field(item: Any, *names: str, default: Any = None) -> Any:
    for name in names:
        value = item.get(name) if isinstance(item, dict) else getattr(item, name, None)
        if value is not None:
            return value
    return default


def primitive_from(item: Any, *, role: str = "visual") -> Primitive | None:
    """A :class:`Primitive` from a shape description: a :class:`Primitive` itself, or a mapping/object with
    ``kind`` (or ``type``), ``body``, ``rotation`` and ``position`` in the body frame, and the size fields
    (``size``; ``radius``/``length``; ``semi_axes``; a mesh's ``filename`` and ``scale``, loaded with trimesh).
    ``None`` for a mesh whose file does not exist."""
    if isinstance(item, Primitive):
        return item
    kind = str(_field(item, "kind", "type", default="")).lower()
    body = int(_field(item, "body", "body_index", default=0))
    rotation = _field(item, "rotation", default=np.eye(3))
    position = _field(item, "position", "xyz", default=np.zeros(3))
    name = str(_field(item, "name", default=kind))
    color = str(_field(item, "color", default=VISUAL_COLOR if role == "visual" else LINK_COLOR))
    opacity = float(_field(item, "opacity", default=1.0 if role == "visual" else 0.6))
    common = dict(body=body, rotation=rotation, position=position, name=name, role=role, color=color,
                  opacity=opacity)
    if kind == "mesh":
        filename = _field(item, "filename", "path", "file")
        if filename is None or not Path(filename).is_file():
            return None
        V, F = load_mesh(filename)
        scale = _field(item, "scale", default=(1.0, 1.0, 1.0))
        return Primitive("mesh", size=tuple(np.broadcast_to(np.asarray(scale, dtype=float), 3)), vertices=V,
                         faces=F, **common)
    if kind == "cylinder":
        size = (float(_field(item, "radius")), float(_field(item, "length")))
    elif kind == "sphere":
        size = (float(_field(item, "radius")),)
    elif kind == "ellipsoid":
        size = tuple(_field(item, "semi_axes", "size"))
    else:
        size = tuple(_field(item, "size", default=()))
    return Primitive(kind, size=size, **common)


def load_mesh(filename) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) and triangle faces (F, 3) of a mesh file (STL, OBJ, DAE, PLY ..., read by trimesh)."""
    import trimesh

    mesh = trimesh.load(str(filename), force="mesh")
    return np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=int)


# ------------------------------------------------------------------------------------------- tessellation


def _unit_mesh(p: Primitive) -> tuple[np.ndarray, np.ndarray]:
    """Triangles of a primitive in its own frame (before its pose in the body)."""
    if p.kind == "box":
        s = np.asarray(p.size) / 2
        V = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * s
        F = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
        return V, F
    if p.kind == "cylinder":
        r, length = p.size
        return cylinder_mesh(r, length)
    if p.kind in ("sphere", "ellipsoid"):
        axes = (p.size[0],) * 3 if p.kind == "sphere" else p.size
        V, F = _sphere_mesh()
        return V * np.asarray(axes), F
    return np.asarray(p.vertices, dtype=float) * np.asarray(p.size), np.asarray(p.faces, dtype=int)


def cylinder_mesh(radius: float, length: float, segments: int = CYLINDER_SEGMENTS,
                  radius_top: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A closed cylinder (a cone when ``radius_top`` = 0) along z, from ``-length/2`` to ``+length/2``."""
    rt = radius if radius_top is None else radius_top
    a = np.linspace(0.0, 2 * np.pi, segments, endpoint=False)
    c, s = np.cos(a), np.sin(a)
    bottom = np.column_stack([radius * c, radius * s, np.full(segments, -length / 2)])
    top = np.column_stack([rt * c, rt * s, np.full(segments, length / 2)])
    V = np.vstack([bottom, top, [[0, 0, -length / 2], [0, 0, length / 2]]])
    k = np.arange(segments)
    k1 = (k + 1) % segments
    sides = np.vstack([np.column_stack([k, k1, segments + k1]), np.column_stack([k, segments + k1, segments + k])])
    caps = np.vstack([np.column_stack([np.full(segments, 2 * segments), k1, k]),
                      np.column_stack([np.full(segments, 2 * segments + 1), segments + k, segments + k1])])
    return V, np.vstack([sides, caps])


def _sphere_mesh() -> tuple[np.ndarray, np.ndarray]:
    n_lat, n_lon = SPHERE_SEGMENTS
    lat = np.linspace(0.0, np.pi, n_lat + 1)
    lon = np.linspace(0.0, 2 * np.pi, n_lon, endpoint=False)
    V = np.array([[np.sin(t) * np.cos(f), np.sin(t) * np.sin(f), np.cos(t)] for t in lat for f in lon])
    F = []
    for i in range(n_lat):
        for j in range(n_lon):
            a, b = i * n_lon + j, i * n_lon + (j + 1) % n_lon
            c, d = a + n_lon, b + n_lon
            F += [[a, c, d], [a, d, b]]
    return V, np.array(F)


# ------------------------------------------------------------------------------------------------- posing


@dataclass(frozen=True)
class Snapshot:
    """A scene placed at one pose, in world coordinates [m].

    Attributes:
        meshes: per primitive, (vertices (V, 3), faces (F, 3)).
        frame_origin: (nb + 1, 3) origins of the body frames and the end-effector frame.
        frame_axes: (nb + 1, 3, 3) their axes as columns (body-to-world rotations).
        joint_axis: (n, 2, 3) a segment along each joint axis, centred on the joint.
        com, cob: (nb, 3) centres of mass and buoyancy.
        thruster_base: (m, 3) thruster positions; thruster_tip: (m, 3) arrow tips.
        vehicle: (3,) vehicle position; end_effector: (3,) end-effector position.
    """

    meshes: tuple[tuple[np.ndarray, np.ndarray], ...]
    frame_origin: np.ndarray
    frame_axes: np.ndarray
    joint_axis: np.ndarray
    com: np.ndarray
    cob: np.ndarray
    thruster_base: np.ndarray
    thruster_tip: np.ndarray

    @property
    def vehicle(self) -> np.ndarray:
        return self.frame_origin[0]

    @property
    def end_effector(self) -> np.ndarray:
        return self.frame_origin[-1]

    def points(self) -> np.ndarray:
        """Every drawn point (for the axis ranges)."""
        parts = [V for V, _ in self.meshes] + [self.frame_origin, self.com, self.cob, self.thruster_base,
                                              self.thruster_tip, self.joint_axis.reshape(-1, 3)]
        return np.vstack([p for p in parts if p.size])


def pose_scene(scene: Scene, rotation: np.ndarray, position: np.ndarray, thrust_scale=None,
               _local: list | None = None) -> Snapshot:
    """Place ``scene`` at the body poses ``rotation`` (nb + 1, 3, 3; body to world) and ``position``
    (nb + 1, 3) of :func:`uvms.forward_kinematics` (bodies, then the end effector).

    ``thrust_scale``: (m,) arrow lengths as fractions of :attr:`Scene.arrow_length` (negative: reversed
    thrust); default 1 (the direction only)."""
    R = np.asarray(rotation, dtype=float)
    p = np.asarray(position, dtype=float)
    local = _local if _local is not None else [prim.local_mesh() for prim in scene.primitives]
    meshes = tuple((V @ R[prim.body].T + p[prim.body], F) for prim, (V, F) in zip(scene.primitives, local))
    nb = scene.n_bodies
    com = np.einsum("bij,bj->bi", R[:nb], scene.com) + p[:nb]
    cob = np.einsum("bij,bj->bi", R[:nb], scene.cob) + p[:nb]
    half = 0.5 * scene.triad_length
    axis_w = np.einsum("bij,bj->bi", R[1:nb], scene.joint_axes)
    joint = np.stack([p[1:nb] - half * axis_w, p[1:nb] + half * axis_w], axis=1) if nb > 1 else np.zeros((0, 2, 3))
    m = len(scene.thrusters)
    scale = np.ones(m) if thrust_scale is None else np.asarray(thrust_scale, dtype=float).reshape(m)
    base = np.array([R[0] @ t.position + p[0] for t in scene.thrusters]).reshape(m, 3)
    tip = base + np.array([R[0] @ t.direction for t in scene.thrusters]).reshape(m, 3) * (
        scene.arrow_length * scale)[:, None]
    return Snapshot(meshes=meshes, frame_origin=p, frame_axes=R, joint_axis=joint, com=com, cob=cob,
                    thruster_base=base, thruster_tip=tip)


def arrow_head(base: np.ndarray, tip: np.ndarray, size: float) -> tuple[np.ndarray, np.ndarray]:
    """A cone (vertices, faces) with its point at ``tip``, pointing from ``base`` to ``tip``, ``size`` long
    (shorter for a short arrow); a collapsed cone (all vertices at ``tip``) for a zero-length arrow."""
    d = np.asarray(tip, dtype=float) - np.asarray(base, dtype=float)
    L = float(np.linalg.norm(d))
    V, F = cylinder_mesh(0.35 * size, size, segments=12, radius_top=0.0)
    if L < 1e-9:
        return np.tile(tip, (V.shape[0], 1)), F
    h = min(size, 0.6 * L) / size
    V = V * h
    R = _rotation_z_to(d / L)
    return (V - [0.0, 0.0, 0.5 * size * h]) @ R.T + tip, F


def equal_ranges(points: np.ndarray, pad: float = 0.08) -> np.ndarray:
    """(3, 2) axis limits of a cube that holds ``points`` with a margin (so that 1 m looks the same on every
    axis)."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre = 0.5 * (lo + hi)
    half = 0.5 * float(np.max(hi - lo)) * (1 + 2 * pad) + 1e-3
    return np.column_stack([centre - half, centre + half])


def body_poses(model, state) -> tuple[np.ndarray, np.ndarray]:
    """(rotation, position) of every body and the end effector at ``state`` (:func:`uvms.forward_kinematics`)."""
    from uvms.dynamics.poses import forward_kinematics

    poses = forward_kinematics(model, state)
    return poses.rotation, poses.position
