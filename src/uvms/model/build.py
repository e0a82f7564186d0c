"""Validated schema -> frozen :class:`~uvms.model.model.Model` (body 0 = vehicle, bodies 1..n = links).

:func:`build_model` builds a modified-DH model file; :func:`build_urdf_model` a URDF with its YAML additions.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from uvms.checks import check_joint_axis_inertia
from uvms.errors import UvmsInputError
from uvms.frames import check_gravity, default_gravity
from uvms.hydro.added_mass import cylinder_added_mass
from uvms.model.loads import with_dry_weight, with_point_loads
from uvms.model.model import Model
from uvms.model.schema import ArmSpec, LinkSpec, ModelSpec, UrdfModelSpec, VehicleSpec, inertia_com
from uvms.rotations import rotation_from_euler
from uvms.spatial import modified_dh_pose, plucker, shift_spatial_inertia
from uvms.thrusters.layouts import thruster_from_spec


def _added_mass(body: VehicleSpec | LinkSpec, density: float) -> np.ndarray:
    """6x6 ``I_A`` about the body-frame origin (Eq. 2); ``from_geometry`` uses cylinder strip theory; none given:
    the sum of the body's shapes' added masses (:func:`uvms.hydro.shapes.total_added_mass`)."""
    from uvms.hydro.shapes import total_added_mass

    spec = body.added_mass
    if spec is None:
        return total_added_mass(shape_objects(body.shapes), density)
    if spec == "from_geometry":
        assert isinstance(body, LinkSpec)
        return cylinder_added_mass(density, body.cylinder.radius, body.cylinder.length)
    I_A = spec.value()
    return shift_spatial_inertia(I_A, np.array(body.com)) if spec.about == "com" else I_A


def _buoyancy(body: VehicleSpec | LinkSpec, density: float) -> tuple[float, np.ndarray]:
    """Displaced fluid mass ``m_f`` [kg] and centre of buoyancy [m] (Eqs. 7-8): as stated, else from the body's
    shapes (``rho V`` at their volume-weighted centre, :func:`uvms.hydro.shapes.buoyancy`)."""
    from uvms.hydro.shapes import buoyancy

    if body.buoyancy is not None:
        return body.buoyancy.mass, np.array(body.buoyancy.center, dtype=float)
    volume, centre = buoyancy(shape_objects(body.shapes))
    return density * volume, np.asarray(centre, dtype=float)


def shape_objects(specs) -> list:
    """:mod:`uvms.hydro.shapes` objects of schema shapes (``from_collision`` entries left out)."""
    from uvms.hydro import shapes as hs
    from uvms.model.schema import (
        BoxShapeSpec,
        CylinderShapeSpec,
        EllipsoidShapeSpec,
        SphereShapeSpec,
    )

    out = []
    for s in specs:
        if not isinstance(s, (SphereShapeSpec, BoxShapeSpec, CylinderShapeSpec, EllipsoidShapeSpec)):
            continue
        pose = {"rotation": s.rotation(), "position": np.array(s.position)}
        if isinstance(s, SphereShapeSpec):
            out.append(hs.Sphere(s.radius, s.drag_coefficient, **pose))
        elif isinstance(s, BoxShapeSpec):
            out.append(hs.Box(tuple(s.size), tuple(s.drag_coefficients), **pose))
        elif isinstance(s, CylinderShapeSpec):
            out.append(hs.Cylinder(s.radius, s.length, s.drag_coefficient, s.axial_drag_coefficient, **pose))
        elif isinstance(s, EllipsoidShapeSpec):
            out.append(hs.Ellipsoid(tuple(s.semi_axes), s.drag_coefficient, s.axial_drag_coefficient, **pose))
    return out


def gravity_of(spec: ModelSpec | UrdfModelSpec, source: str | None) -> np.ndarray:
    """The model file's gravity [m/s^2]: ``environment.gravity`` if given (refused when it points up in the
    file's ``frame``, :func:`uvms.frames.check_gravity`), else 9.81 m/s^2 down in that frame."""
    if spec.environment.gravity is None:
        return default_gravity(spec.frame)
    return check_gravity(spec.environment.gravity, spec.frame, source, "environment.gravity")


def _thrusters(spec: ModelSpec | UrdfModelSpec, source: str | None) -> tuple:
    """The thrusters of a model file; a table thruster's CSV is read beside the file."""
    from pathlib import Path

    base = Path(source).parent if source is not None else None
    return tuple(thruster_from_spec(t, i, base=base, source=source) for i, t in enumerate(spec.thrusters))


def _joints(arm: ArmSpec | None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per-joint ``(rotation, position, theta_offset)`` and the end-effector pose, from modified-DH rows."""
    if arm is None:
        return np.zeros((0, 3, 3)), np.zeros((0, 3)), np.zeros(0), np.eye(3), np.zeros(3)
    rotations, positions = [], []
    for link in arm.links:
        R, p = modified_dh_pose(link.dh.alpha_prev, link.dh.a_prev, link.dh.d, 0.0)
        rotations.append(R)
        positions.append(p)
    R_M = rotation_from_euler(np.array(arm.mount.rotation_rpy))
    rotations[0], positions[0] = R_M @ rotations[0], np.array(arm.mount.position) + R_M @ positions[0]
    ee = arm.end_effector.dh
    ee_rotation, ee_position = modified_dh_pose(ee.alpha_prev, ee.a_prev, ee.d, ee.theta_offset)
    offsets = np.array([link.dh.theta_offset for link in arm.links])
    return np.array(rotations), np.array(positions), offsets, ee_rotation, ee_position


def build_model(spec: ModelSpec, source: str | None = None) -> Model:
    """The frozen :class:`Model` of a validated model file; ``source`` is recorded as ``Model.source``."""
    from uvms.hydro.shapes import shape_drag_tables

    env, vehicle = spec.environment, spec.vehicle
    links = spec.arm.links if spec.arm is not None else ()
    bodies: list[VehicleSpec | LinkSpec] = [vehicle, *links]
    joint_rotation, joint_position, theta_offset, ee_rotation, ee_position = _joints(spec.arm)
    mass = np.array([b.mass for b in bodies])
    com = np.array([b.com for b in bodies]).reshape(-1, 3)
    inertia = np.array([inertia_com(b.mass, b.com, b.inertia) for b in bodies])
    added_mass = np.array([_added_mass(b, env.density) for b in bodies])
    check_joint_axis_inertia(mass, com, inertia, added_mass, source=source, where=lambda j: f"arm.links[{j}].inertia")
    damping = [(b.damping.matrices(), b.damping.about) if b.damping is not None else None for b in bodies]
    buoyancy = [_buoyancy(b, env.density) for b in bodies]
    shapes = [shape_objects(b.shapes) for b in bodies]
    model = Model(
        name=spec.name,
        source=source,
        body_names=("vehicle", *(link.name for link in links)),
        mass=mass,
        com=com,
        inertia_com=inertia,
        added_mass=added_mass,
        buoyancy_mass=np.array([m_f for m_f, _ in buoyancy]),
        cob=np.array([b for _, b in buoyancy]).reshape(-1, 3),
        vehicle_drag_area=np.array(vehicle.drag.area),
        vehicle_drag_coefficient=np.array(vehicle.drag.coefficient),
        vehicle_rotational_drag_side=vehicle.drag.rotational.side,
        vehicle_rotational_drag_coefficient=vehicle.drag.rotational.coefficient,
        vehicle_box=np.array(vehicle.box),
        link_radius=np.array([link.cylinder.radius for link in links]),
        link_length=np.array([link.cylinder.length for link in links]),
        link_drag_coefficient=np.array([link.drag_coefficient for link in links]),
        joint_rotation=joint_rotation,
        joint_position=joint_position,
        theta_offset=theta_offset,
        ee_rotation=ee_rotation,
        ee_position=ee_position,
        density=env.density,
        gravity=gravity_of(spec, source),
        current=np.array(env.current),
        fluid_acceleration=np.array(env.fluid_acceleration),
        thrusters=_thrusters(spec, source),
        damping_linear=np.array([d[0][0] if d else np.zeros((6, 6)) for d in damping]),
        damping_quadratic=np.array([d[0][1] if d else np.zeros((6, 6)) for d in damping]),
        damping_point=np.array([d[1] if d else (0.0, 0.0, 0.0) for d in damping]).reshape(-1, 3),
        shape_drag=shape_drag_tables(shapes),
        shape_count=np.array([len(x) for x in shapes]),
        convention=spec.frame,
    )
    return with_disturbance(with_point_loads(model, spec.point_loads, source), spec.disturbance_wrench)


def _cylinder_rotation(axis) -> np.ndarray:
    """A rotation whose x column is the unit ``axis``; y is the link's y (or z, for an axis near y) made
    orthogonal to it, so that an axis along x gives the identity (Eq. 6's drag is axisymmetric anyway)."""
    x = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    helper = np.eye(3)[1] if abs(x[1]) < 0.9 else np.eye(3)[2]
    y = helper - (helper @ x) * x
    y /= np.linalg.norm(y)
    return np.column_stack([x, y, np.cross(x, y)])


def _shapes_into(hydro, spec) -> None:
    """A link's (or the vehicle's) shapes into its :class:`~uvms.model.urdf.LinkHydro`; explicit added mass and
    buoyancy override the shapes' (``docs/models.md``, "Shapes")."""
    from uvms.model.schema import FromCollisionSpec

    hydro.shapes = shape_objects(spec.shapes)
    collision = [s for s in spec.shapes if isinstance(s, FromCollisionSpec)]
    hydro.from_collision = collision[0].drag_coefficient if collision else None
    hydro.explicit_added_mass = spec.added_mass is not None
    hydro.explicit_buoyancy = spec.buoyancy is not None


def _explicit_hydro_into(hydro, spec, rho: float, *, added_mass: bool) -> None:
    """A URDF body's stated buoyancy, damping (and added mass, if ``added_mass``) and its shapes into its
    :class:`~uvms.model.urdf.LinkHydro`."""
    if added_mass and spec.added_mass is not None:
        hydro.added_mass = spec.added_mass.value()
    if spec.buoyancy is not None:
        hydro.fluid_mass = spec.buoyancy.fluid_mass(rho)
        hydro.center = np.array(spec.buoyancy.center)
    if spec.damping is not None:
        hydro.damping = (*spec.damping.matrices(), np.array(spec.damping.about))
    _shapes_into(hydro, spec)


def build_urdf_model(spec: UrdfModelSpec, urdf_path, source: str | None = None, granted: frozenset = frozenset()):
    """The :class:`Model` of a URDF (``urdf_path``, resolved by the caller) with the additions of ``spec``;
    ``granted``: the fields of ``spec`` that the caller set, not the file (:func:`xacro_options`)."""
    from uvms.model.urdf import LinkHydro, VehicleExtras, model_from_urdf

    env = spec.environment
    rho = env.density
    links: dict[str, LinkHydro] = {}
    for name, link in spec.links.items():
        hydro = LinkHydro()
        if link.cylinder is not None:
            c = link.cylinder
            C = _cylinder_rotation(c.axis)
            hydro.cylinder = (C, np.array(c.origin), c.radius, c.length, c.drag_coefficient)
        if link.added_mass == "from_geometry":
            c = link.cylinder
            X = plucker(C.T, np.array(c.origin))        # link-to-cylinder motion transform
            hydro.added_mass = X.T @ cylinder_added_mass(rho, c.radius, c.length) @ X
        elif link.added_mass is not None:
            hydro.added_mass = link.added_mass.value()
        _explicit_hydro_into(hydro, link, rho, added_mass=False)
        links[name] = hydro
    vehicle = spec.vehicle
    vehicle_hydro = LinkHydro()
    _explicit_hydro_into(vehicle_hydro, vehicle, rho, added_mass=True)
    drag = vehicle.drag
    extras = VehicleExtras(
        name=spec.name, density=rho, gravity=tuple(gravity_of(spec, source)), current=env.current, frame=spec.frame,
        fluid_acceleration=env.fluid_acceleration,
        vehicle_drag_area=drag.area if drag else (0.0, 0.0, 0.0),
        vehicle_drag_coefficient=drag.coefficient if drag else (0.0, 0.0, 0.0),
        vehicle_rotational_drag_side=drag.rotational.side if drag else 0.0,
        vehicle_rotational_drag_coefficient=drag.rotational.coefficient if drag else 0.0,
        vehicle_box=vehicle.box, vehicle_hydro=vehicle_hydro, links=links,
        joints={name: {k: v for k, v in j.model_dump().items() if v is not None} for name, j in spec.joints.items()},
        end_effector=spec.end_effector, fixed_joints=spec.fixed_joints,
        thrusters=_thrusters(spec, source), source=source,
        xacro=xacro_options(spec, source, granted), balance_inertia=spec.balance_inertia,
    )
    from uvms.model.sdf import is_sdf, model_from_sdf

    model = model_from_sdf(urdf_path, extras) if is_sdf(urdf_path) else model_from_urdf(urdf_path, extras)
    if spec.inertia_includes_added_mass:
        weights = [(None, vehicle.weight)] if vehicle.weight is not None else []
        weights += [(name, link.weight) for name, link in spec.links.items() if link.weight is not None]
        model = with_dry_weight(model, weights, source)
    return with_disturbance(with_point_loads(model, spec.point_loads, source), spec.disturbance_wrench)


def xacro_options(spec: UrdfModelSpec, source: str | None, granted: frozenset = frozenset()):
    """What the additions file lets its xacro read (docs/models.md, "What a xacro may do").

    A model file is data and cannot widen what it may read: its own ``package_paths`` (relative to the file)
    must lie inside the file's folder, and ``allow_environment: true`` is refused. ``granted`` names the fields
    set by the caller (the keywords of :func:`uvms.model.load.load_model`), which may name any folder."""
    from uvms.model.xacro import XacroOptions

    base = (Path(source).parent if source else Path(".")).resolve()
    packages = {name: (base / path).resolve() for name, path in spec.package_paths.items()}
    if "package_paths" not in granted:
        for name, folder in packages.items():
            if folder != base and base not in folder.parents:
                raise UvmsInputError(f"package folder {spec.package_paths[name]!r} is outside this file's folder "
                                     f"{base}; a model file may name only folders inside its own (name others with "
                                     "uvms.load_model(..., package_paths=...) or ROS_PACKAGE_PATH)",
                                     source, f"package_paths.{name}")
    if spec.allow_environment and "allow_environment" not in granted:
        raise UvmsInputError("a model file cannot allow its xacro to read the environment; pass "
                             "allow_environment=True to uvms.load_model if you trust the xacro",
                             source, "allow_environment")
    return XacroOptions(package_paths=packages, allow_environment=spec.allow_environment,
                        args=dict(spec.xacro_args))


def with_disturbance(model, wrench):
    """``model`` with the file's ``disturbance_wrench`` (6 values, vehicle body axes, ``[moment; force]``)
    [N m, N]; the model itself when it is zero (``docs/models.md``, "Disturbance wrench")."""
    w = np.array(wrench, dtype=float)
    return model.replace(disturbance_wrench=w) if np.any(w != 0.0) else model
