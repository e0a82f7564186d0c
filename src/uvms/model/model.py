"""The frozen model: every physical parameter of a vehicle-manipulator system, in SI units.

A :class:`Model` is built once from a validated model file (:mod:`uvms.model.build`, or a URDF through
:mod:`uvms.model.urdf`) and never mutated. Bodies form a kinematic tree rooted at the vehicle (body 0);
body ``i >= 1`` moves with joint ``i - 1`` (revolute, continuous or prismatic) relative to its parent body
``joint_parent[i - 1] < i``, so bodies are in depth-first order and the joint order is the order of ``q``.
Every per-body array has a leading axis of length ``n_bodies = n_joints + 1``; per-joint arrays have length
``n_joints``. Spatial quantities are ``[angular; linear]`` and expressed in the body's own frame, about its
frame origin (the vehicle's reference point, or the link's joint), unless a name says otherwise.
Named frames (:class:`Frame`) are fixed in a body: every body, every link merged into a body by a fixed
joint, and the end effector (``docs/models.md``).

The compiled kernels read flat arrays derived from the fields below (:class:`uvms.dynamics.kernel_model.KernelModel`),
built by the dynamics from the model at their first use (:func:`uvms.dynamics.plant.kernel_model`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np


def _frozen(a: Any, dtype=float) -> np.ndarray:
    out = np.array(a, dtype=dtype, copy=True)
    out.setflags(write=False)
    return out


JOINT_TYPES = ("revolute", "continuous", "prismatic")
"""Joint types of a model (URDF names); a fixed joint merges its child into the parent body instead."""

END_EFFECTOR = "end_effector"
"""Name of the end-effector frame."""


@dataclass(frozen=True, eq=False)
class Frame:
    """A named frame fixed in a body: ``rotation`` (frame to body axes) and ``position`` [m] in the body frame."""

    name: str
    body: int
    rotation: np.ndarray
    position: np.ndarray

    def __post_init__(self) -> None:
        object.__setattr__(self, "body", int(self.body))
        object.__setattr__(self, "rotation", _frozen(np.reshape(self.rotation, (3, 3))))
        object.__setattr__(self, "position", _frozen(np.reshape(self.position, 3)))


@dataclass(frozen=True, eq=False)
class Model:
    """A vehicle-manipulator system (frozen; build with :func:`uvms.load_model`).

    Shapes use ``nb = n_joints + 1`` bodies.

    Attributes:
        name: model name.
        source: the file it was loaded from, or ``None``.
        body_names: (nb,) names, body 0 is the vehicle.
        mass: (nb,) rigid-body mass [kg].
        com: (nb, 3) centre of mass in the body frame [m].
        inertia_com: (nb, 3, 3) rotational inertia about the centre of mass, body axes [kg m^2].
        added_mass: (nb, 6, 6) added-mass matrix about the body-frame origin, ``[angular; linear]``
            [kg, kg m, kg m^2] (paper Eq. 2).
        buoyancy_mass: (nb,) mass of displaced fluid ``m_f`` [kg] (paper Eq. 7).
        cob: (nb, 3) centre of buoyancy in the body frame [m] (paper Eq. 8).
        vehicle_drag_area: (3,) frontal areas ``A_j`` per body axis [m^2] (paper Eq. 3).
        vehicle_drag_coefficient: (3,) drag coefficients ``Cd_j`` per body axis [-] (paper Eq. 3).
        vehicle_rotational_drag_side: cube side ``a`` used by the strip-integrated rotational drag [m] (Eq. 4).
        vehicle_rotational_drag_coefficient: drag coefficient of the strips [-] (Eq. 4).
        vehicle_box: (3,) box dimensions of the vehicle [m] (for plots and geometry helpers).
        link_radius: (n,) cylinder radius of each link [m] (Eq. 6).
        link_length: (n,) cylinder length along its axis, from its origin [m] (Eq. 6).
        link_drag_coefficient: (n,) normal-flow drag coefficient of each link [-] (Eq. 6).
        joint_rotation: (n, 3, 3) orientation of joint frame i in its parent body's frame at ``q_i = 0``
            (mount transform and modified-DH ``RotX(alpha_prev)``, or the URDF joint origin).
        joint_position: (n, 3) origin of joint frame i in its parent body's frame [m].
        theta_offset: (n,) joint offset: the joint moves by ``q + theta_offset`` (modified-DH ``theta_offset``)
            [rad or m].
        ee_rotation: (3, 3) end-effector frame orientation in the frame of body ``ee_body``.
        ee_position: (3,) end-effector origin in the frame of body ``ee_body`` [m].
        density: fluid density ``rho`` [kg/m^3].
        gravity: (3,) gravitational acceleration in the world frame [m/s^2] (down: +z in ned, -z in enu).
        current: (3,) default constant current velocity in the world frame [m/s].
        fluid_acceleration: (3,) default fluid acceleration in the world frame [m/s^2].
        thrusters: thruster layout (tuple of thruster descriptions; empty for ideal actuation).
        joint_names: (n,) joint names in tree order (the order of ``q``); ``joint1..n`` by default.
        joint_parent: (n,) parent body of joint i's child body ``i + 1`` (``< i + 1``); a chain by default.
        joint_type: (n,) ``"revolute"``, ``"continuous"`` or ``"prismatic"`` (:data:`JOINT_TYPES`).
        joint_axis: (n, 3) unit joint axis in the joint frame (z by default, as in modified DH).
        joint_damping: (n,) viscous joint damping ``b`` [N m s/rad or N s/m].
        joint_friction: (n,) Coulomb joint friction ``F_c`` [N m or N].
        joint_friction_speed: (n,) regularisation speed ``v_s`` of the Coulomb law [rad/s or m/s]:
            ``tau_f = -F_c clip(qd / v_s, -1, 1)`` (``docs/models.md``, "Joint damping and friction").
        joint_limits: (n, 4) ``[lower, upper, effort, velocity]`` (``inf`` where none).
        link_cylinder_rotation: (n, 3, 3) cylinder axes in the link frame (the cylinder runs along its x
            column; identity for DH links).
        link_cylinder_origin: (n, 3) where the cylinder starts, link frame [m] (zero for DH links).
        ee_body: body the end effector is fixed in (the last body by default).
        damping_linear: (nb, 6, 6) Fossen's linear damping ``D_l`` of each body, ``[angular; linear]`` matrix
            entries [N s/m, N m s/rad, N s, N m s/m] (zero by default; ``docs/models.md``, "Fossen damping").
        damping_quadratic: (nb, 6, 6) Fossen's quadratic damping ``D_q`` [N s^2/m^2, N m s^2/rad^2, ...].
        shape_drag: (nb, k, DRAG_ROW) drag table rows of each body's hydrodynamic shapes
            (:func:`uvms.hydro.shapes.drag_table` at unit density, body frame; the kernels multiply the
            coefficients by ``density``), padded with zero rows; ``k`` may be 0.
        shape_count: (nb,) number of real rows of ``shape_drag`` per body (0: no shape drag).
        damping_point: (nb, 3) point the damping coefficients hold about, body frame [m]: the force is
            ``-(D_l + D_q diag|nu_p|) nu_p`` with ``nu_p`` that point's velocity relative to the fluid.
        damping_cross: (nb, 2, 6, 6, 6) mixed quadratic damping (gz-sim's ``xUabsV``, ``xUV``; UUV Simulator's
            forward-speed damping): ``f_i -= C[0, i, j, k] nu_j |nu_k| + C[1, i, j, k] nu_j nu_k`` at
            ``damping_point``, ``[angular; linear]`` indices, matrix entries (zero by default;
            :func:`uvms.hydro.fossen.fossen_cross_damping_force`).
        frames: named frames (:class:`Frame`); by default one per body (its own frame) and the end effector.
        dry_mass: (nb,) the mass that weighs [kg], when it is not ``mass`` (a URDF whose inertial masses include
            added mass, or weights without inertia of their own; ``docs/models.md``, "Point loads and dry
            weight"), else ``None``. Read it through :attr:`weight_mass`.
        dry_com: (nb, 3) where that weight acts, body frame [m] (with ``dry_mass``); read :attr:`weight_center`.
        convention: the world/body convention every number above is written in (:mod:`uvms.frames`,
            ``docs/conventions.md``, "Frames"): ``"ned"`` (world z down, vehicle forward-right-down, the default)
            or ``"enu"`` (world z up, vehicle forward-left-up, ROS REP 103). :meth:`in_frame` rewrites a model
            in the other one.
        point_loads: the named point loads folded into the bodies (:class:`uvms.model.loads.PointLoad`: name,
            body, position in the body frame, mass, fluid mass, inertial), remembered so that a parameter can
            change one (:func:`uvms.model.loads.with_point_load_set`); empty by default.
        disturbance_wrench: (6,) constant external wrench on the vehicle, body axes, ``[moment; force]``
            ``[K M N X Y Z]`` [N m, N] (zero by default): added to the held body wrench in every simulation's
            state derivative (:func:`uvms.sim.integrate.stage_inputs`; ``docs/conventions.md``, "Where a model's
            disturbance wrench enters").
    """

    name: str
    source: str | None
    body_names: tuple[str, ...]
    mass: np.ndarray
    com: np.ndarray
    inertia_com: np.ndarray
    added_mass: np.ndarray
    buoyancy_mass: np.ndarray
    cob: np.ndarray
    vehicle_drag_area: np.ndarray
    vehicle_drag_coefficient: np.ndarray
    vehicle_rotational_drag_side: float
    vehicle_rotational_drag_coefficient: float
    vehicle_box: np.ndarray
    link_radius: np.ndarray
    link_length: np.ndarray
    link_drag_coefficient: np.ndarray
    joint_rotation: np.ndarray
    joint_position: np.ndarray
    theta_offset: np.ndarray
    ee_rotation: np.ndarray
    ee_position: np.ndarray
    density: float
    gravity: np.ndarray
    current: np.ndarray
    fluid_acceleration: np.ndarray
    thrusters: tuple = ()
    joint_names: tuple[str, ...] | None = None
    joint_parent: Any = None
    joint_type: tuple[str, ...] | None = None
    joint_axis: Any = None
    joint_damping: Any = None
    joint_friction: Any = None
    joint_friction_speed: Any = None
    joint_limits: Any = None
    link_cylinder_rotation: Any = None
    link_cylinder_origin: Any = None
    ee_body: int | None = None
    frames: tuple[Frame, ...] | None = None
    damping_linear: Any = None
    damping_quadratic: Any = None
    damping_point: Any = None
    damping_cross: Any = None
    shape_drag: Any = None
    shape_count: Any = None
    dry_mass: Any = None
    dry_com: Any = None
    convention: str = "ned"
    point_loads: Any = ()
    disturbance_wrench: Any = None
    hydro_sources: tuple[tuple[str, str], ...] = ()
    """``(("<link>: <quantity>", "<tag>"), ...)``: which tag of a Gazebo file each hydrodynamic number came
    from (``uvms validate`` lists them; empty for other files)."""

    def __post_init__(self) -> None:
        n = int(np.shape(self.mass)[0]) - 1
        defaults = {
            "joint_names": tuple(f"joint{i + 1}" for i in range(n)),
            "joint_parent": np.arange(n),
            "joint_type": ("revolute",) * n,
            "joint_axis": np.tile([0.0, 0.0, 1.0], (n, 1)),
            "joint_damping": np.zeros(n),
            "joint_friction": np.zeros(n),
            "joint_friction_speed": np.full(n, DEFAULT_FRICTION_SPEED),
            "joint_limits": np.tile([-np.inf, np.inf, np.inf, np.inf], (n, 1)),
            "link_cylinder_rotation": np.tile(np.eye(3), (n, 1, 1)),
            "link_cylinder_origin": np.zeros((n, 3)),
            "ee_body": n,
            "damping_linear": np.zeros((n + 1, 6, 6)),
            "damping_quadratic": np.zeros((n + 1, 6, 6)),
            "damping_point": np.zeros((n + 1, 3)),
            "damping_cross": np.zeros((n + 1, 2, 6, 6, 6)),
            "shape_drag": np.zeros((n + 1, 0, 19)),
            "shape_count": np.zeros(n + 1, dtype=np.int64),
            "disturbance_wrench": np.zeros(6),
            "point_loads": (),
        }
        for name, value in defaults.items():
            if getattr(self, name) is None:
                object.__setattr__(self, name, value)
        if self.frames is None:
            object.__setattr__(self, "frames", tuple(Frame(b, i, np.eye(3), np.zeros(3))
                                                     for i, b in enumerate(self.body_names))
                               + (Frame(END_EFFECTOR, self.ee_body, self.ee_rotation, self.ee_position),))
        object.__setattr__(self, "joint_names", tuple(str(j) for j in self.joint_names))
        object.__setattr__(self, "joint_type", tuple(str(j) for j in self.joint_type))
        object.__setattr__(self, "frames", tuple(self.frames))
        object.__setattr__(self, "ee_body", int(self.ee_body))
        object.__setattr__(self, "joint_parent", _frozen(np.reshape(self.joint_parent, n), dtype=np.int64))
        for name in ("mass", "com", "inertia_com", "added_mass", "buoyancy_mass", "cob", "vehicle_drag_area",
                     "vehicle_drag_coefficient", "vehicle_box", "link_radius", "link_length",
                     "link_drag_coefficient", "joint_rotation", "joint_position", "theta_offset", "ee_rotation",
                     "ee_position", "gravity", "current", "fluid_acceleration", "joint_axis", "joint_damping",
                     "joint_friction", "joint_friction_speed", "joint_limits", "link_cylinder_rotation",
                     "link_cylinder_origin", "damping_linear", "damping_quadratic", "damping_point", "damping_cross",
                     "shape_drag", "disturbance_wrench"):
            object.__setattr__(self, name, _frozen(getattr(self, name)))
        object.__setattr__(self, "point_loads", tuple(self.point_loads))
        object.__setattr__(self, "shape_count", _frozen(np.reshape(self.shape_count, n + 1), dtype=np.int64))
        if (self.dry_mass is None) != (self.dry_com is None):
            raise ValueError("dry_mass and dry_com are given together or not at all")
        if self.dry_mass is not None:
            object.__setattr__(self, "dry_mass", _frozen(np.reshape(self.dry_mass, n + 1)))
            object.__setattr__(self, "dry_com", _frozen(np.reshape(self.dry_com, (n + 1, 3))))
        self._check_tree(n)
        object.__setattr__(self, "vehicle_rotational_drag_side", float(self.vehicle_rotational_drag_side))
        object.__setattr__(self, "vehicle_rotational_drag_coefficient",
                           float(self.vehicle_rotational_drag_coefficient))
        object.__setattr__(self, "density", float(self.density))
        from uvms.checks import check_joint_axis_inertia
        from uvms.frames import check_frame

        check_frame(self.convention, "model convention")

        check_joint_axis_inertia(self.mass, self.com, self.inertia_com, self.added_mass, joint_axis=self.joint_axis,
                                 joint_type=self.joint_type, source=self.source,
                                 where=lambda j: f"link {self.body_names[j + 1]!r} (body {j + 1})")

    def _check_tree(self, n: int) -> None:
        """Programming-error checks of the tree arrays (user files are checked when they are read)."""
        if len(self.joint_names) != n or len(self.joint_type) != n or len(self.body_names) != n + 1:
            raise ValueError("joint_names, joint_type and body_names must have n, n and n + 1 entries")
        if any(not 0 <= int(p) <= i for i, p in enumerate(self.joint_parent)):
            raise ValueError("joint_parent[i] must be a body before body i + 1 (depth-first order)")
        if any(t not in JOINT_TYPES for t in self.joint_type):
            raise ValueError(f"joint_type entries must be one of {JOINT_TYPES}")
        if self.joint_axis.shape != (n, 3) or np.any(np.abs(np.linalg.norm(self.joint_axis, axis=1) - 1) > 1e-12):
            raise ValueError("joint_axis must be (n, 3) unit vectors")
        if not 0 <= self.ee_body <= n or any(not 0 <= f.body <= n for f in self.frames):
            raise ValueError("ee_body and every frame's body must be a body index")
        names = [f.name for f in self.frames]
        if len(set(names)) != len(names):
            raise ValueError("frame names must be unique")

    @property
    def weight_mass(self) -> np.ndarray:
        """(nb,) the mass gravity acts on [kg]: ``dry_mass`` when given, else ``mass``. The one source of every
        weight in uvms (the dynamics' gravity force, trim, the validate report, the potential energy)."""
        return self.mass if self.dry_mass is None else self.dry_mass

    @property
    def weight_center(self) -> np.ndarray:
        """(nb, 3) where each body's weight acts, body frame [m]: ``dry_com`` when given, else ``com``."""
        return self.com if self.dry_com is None else self.dry_com

    @property
    def frame_names(self) -> tuple[str, ...]:
        """Names of every frame (bodies, merged links, the end effector), in tree order."""
        return tuple(f.name for f in self.frames)

    def frame(self, name: str) -> Frame:
        """The named frame; ``KeyError`` listing the names when there is none."""
        for f in self.frames:
            if f.name == name:
                return f
        raise KeyError(f"model {self.name!r} has no frame {name!r}; frames: {', '.join(self.frame_names)}")

    def joint_index(self, name: str) -> int:
        """Index of a joint in ``q``; ``KeyError`` listing the names when there is none."""
        try:
            return self.joint_names.index(name)
        except ValueError:
            raise KeyError(f"model {self.name!r} has no joint {name!r}; joints: "
                           f"{', '.join(self.joint_names) or '(none)'}") from None

    def with_end_effector(self, frame: str) -> "Model":
        """A copy whose end effector (for ``ee_wrench`` and the end-effector metrics) is the named frame."""
        f = self.frame(frame)
        frames = tuple(x for x in self.frames if x.name != END_EFFECTOR) + (
            Frame(END_EFFECTOR, f.body, f.rotation, f.position),)
        return self.replace(ee_body=f.body, ee_rotation=f.rotation, ee_position=f.position, frames=frames)

    @property
    def n_joints(self) -> int:
        """Number of joints ``n`` (the size of ``q``)."""
        return int(self.mass.shape[0] - 1)

    @property
    def n_bodies(self) -> int:
        """Number of bodies ``n + 1`` (vehicle and links)."""
        return int(self.mass.shape[0])

    @property
    def n_dof(self) -> int:
        """Generalized velocity size ``6 + n``."""
        return 6 + self.n_joints

    def replace(self, **changes: Any) -> "Model":
        """A new model with some fields changed (the model itself is never mutated).

        When ``mass`` changes the number of bodies, the joint and frame fields that are not given are reset to
        their defaults (a chain of revolute z joints, one frame per body and the end effector on the last).
        """
        if "mass" in changes and np.shape(changes["mass"])[0] != self.n_bodies:
            for name in _TREE_FIELDS:
                changes.setdefault(name, None)
        return replace(self, **changes)

    def with_effects(self, *, added_mass: bool = True, drag: bool = True, buoyancy: bool = True,
                     gravity: bool = True, current: bool = True, joint_friction: bool = True) -> "Model":
        """A copy with some physical effects switched off (their parameters set to zero).

        ``joint_friction=False`` removes joint damping and Coulomb friction.

        ``buoyancy=False`` removes the displaced-fluid force of Eqs. 7-8 (buoyancy and fluid acceleration).
        """
        changes: dict[str, Any] = {}
        if not added_mass:
            changes["added_mass"] = np.zeros_like(self.added_mass)
        if not drag:
            changes["vehicle_drag_coefficient"] = np.zeros(3)
            changes["vehicle_rotational_drag_coefficient"] = 0.0
            changes["link_drag_coefficient"] = np.zeros_like(self.link_drag_coefficient)
            changes["damping_linear"] = np.zeros_like(self.damping_linear)
            changes["damping_quadratic"] = np.zeros_like(self.damping_quadratic)
            changes["damping_cross"] = np.zeros_like(self.damping_cross)
            changes["shape_drag"] = _scale_shape_drag(self.shape_drag, 0.0)
        if not buoyancy:
            changes["buoyancy_mass"] = np.zeros_like(self.buoyancy_mass)
        if not gravity:
            changes["gravity"] = np.zeros(3)
        if not current:
            changes["current"] = np.zeros(3)
            changes["fluid_acceleration"] = np.zeros(3)
        if not joint_friction:
            changes["joint_damping"] = np.zeros_like(self.joint_damping)
            changes["joint_friction"] = np.zeros_like(self.joint_friction)
        return self.replace(**changes)

    def with_hydrodynamics_scaled(self, *, added_mass: float = 1.0, drag: float = 1.0) -> "Model":
        """A copy with every added-mass matrix and drag coefficient multiplied by a factor.

        Used for the controller's own model: the paper's "60 % error" is ``added_mass=0.4, drag=0.4``.
        """
        if added_mass < 0 or drag < 0:
            raise ValueError("hydrodynamic scale factors must be non-negative")
        return self.replace(
            added_mass=self.added_mass * added_mass,
            vehicle_drag_coefficient=self.vehicle_drag_coefficient * drag,
            vehicle_rotational_drag_coefficient=self.vehicle_rotational_drag_coefficient * drag,
            link_drag_coefficient=self.link_drag_coefficient * drag,
            damping_linear=self.damping_linear * drag,
            damping_quadratic=self.damping_quadratic * drag,
            damping_cross=self.damping_cross * drag,
            shape_drag=_scale_shape_drag(self.shape_drag, drag),
        )

    def vehicle_only(self) -> "Model":
        """The vehicle alone (body 0, no arm): for vehicle-only controller models and Fossen comparisons."""
        return Model(
            name=f"{self.name}-vehicle", source=self.source, body_names=self.body_names[:1],
            mass=self.mass[:1], com=self.com[:1], inertia_com=self.inertia_com[:1], added_mass=self.added_mass[:1],
            buoyancy_mass=self.buoyancy_mass[:1], cob=self.cob[:1], vehicle_drag_area=self.vehicle_drag_area,
            vehicle_drag_coefficient=self.vehicle_drag_coefficient,
            vehicle_rotational_drag_side=self.vehicle_rotational_drag_side,
            vehicle_rotational_drag_coefficient=self.vehicle_rotational_drag_coefficient,
            vehicle_box=self.vehicle_box, link_radius=np.zeros(0), link_length=np.zeros(0),
            link_drag_coefficient=np.zeros(0), joint_rotation=np.zeros((0, 3, 3)), joint_position=np.zeros((0, 3)),
            theta_offset=np.zeros(0), ee_rotation=np.eye(3), ee_position=np.zeros(3), density=self.density,
            gravity=self.gravity, current=self.current, fluid_acceleration=self.fluid_acceleration,
            thrusters=self.thrusters, damping_linear=self.damping_linear[:1],
            damping_quadratic=self.damping_quadratic[:1], damping_point=self.damping_point[:1],
            damping_cross=self.damping_cross[:1],
            shape_drag=self.shape_drag[:1], shape_count=self.shape_count[:1],
            dry_mass=None if self.dry_mass is None else self.dry_mass[:1],
            dry_com=None if self.dry_com is None else self.dry_com[:1],
            convention=self.convention, point_loads=tuple(p for p in self.point_loads if p.body == 0),
            disturbance_wrench=self.disturbance_wrench,
        )

    def in_frame(self, frame: str) -> "Model":
        """The same robot written in convention ``frame`` (``"ned"`` or ``"enu"``; itself if already so).

        The half turn about x (:mod:`uvms.frames`) is applied to the world and to the vehicle's body axes: world
        vectors (gravity, current, fluid acceleration) and everything given in the vehicle frame (centres of
        mass and buoyancy, inertia, added mass, damping and its point, shapes, thrusters, the poses of the
        joints, links and named frames fixed in the vehicle) change; each link's own frame is the model's
        (DH rows, URDF joint origins) and stays, so a link's numbers, ``q`` and ``qd`` are unchanged. Motion
        maps with :func:`uvms.frames.convert_state`.
        """
        from dataclasses import replace as replace_dataclass

        from uvms import frames as fr
        from uvms.hydro.shapes import COL_POSITION, COL_ROTATION

        fr.check_frame(frame)
        if frame == self.convention:
            return self
        src = self.convention

        def body0(a: np.ndarray, convert) -> np.ndarray:
            out = np.array(a, dtype=float)
            out[0] = convert(out[0], src, frame)
            return out

        on_vehicle = np.flatnonzero(self.joint_parent == 0)
        joint_rotation, joint_position = np.array(self.joint_rotation), np.array(self.joint_position)
        joint_rotation[on_vehicle] = fr.convert_frame_rotations(joint_rotation[on_vehicle], src, frame)
        joint_position[on_vehicle] = fr.convert_vectors(joint_position[on_vehicle], src, frame)
        shape_drag = np.array(self.shape_drag)
        k = int(self.shape_count[0])
        rotations = shape_drag[0, :k, COL_ROTATION:COL_ROTATION + 9].reshape(k, 3, 3)
        shape_drag[0, :k, COL_ROTATION:COL_ROTATION + 9] = fr.convert_frame_rotations(rotations, src,
                                                                                       frame).reshape(k, 9)
        shape_drag[0, :k, COL_POSITION:COL_POSITION + 3] = fr.convert_vectors(
            shape_drag[0, :k, COL_POSITION:COL_POSITION + 3], src, frame)

        def fixed_frame(f: Frame) -> Frame:
            if f.body != 0 or f.name == self.body_names[0]:
                return f            # a link's frame, or the vehicle's own (which is the new convention's axes)
            return Frame(f.name, 0, fr.convert_frame_rotations(f.rotation, src, frame),
                         fr.convert_vectors(f.position, src, frame))

        ee_rotation, ee_position = self.ee_rotation, self.ee_position
        if self.ee_body == 0:
            ee_rotation = fr.convert_frame_rotations(ee_rotation, src, frame)
            ee_position = fr.convert_vectors(ee_position, src, frame)
        thrusters = tuple(replace_dataclass(t, position=tuple(fr.convert_vectors(t.position, src, frame)),
                                            direction=tuple(fr.convert_vectors(t.direction, src, frame)))
                          for t in self.thrusters)
        point_loads = tuple(replace_dataclass(p, position=fr.convert_vectors(p.position, src, frame))
                            if p.body == 0 else p for p in self.point_loads)
        H = fr.HALF_TURN
        inertia = np.array(self.inertia_com)
        inertia[0] = H @ inertia[0] @ H
        return self.replace(
            com=body0(self.com, fr.convert_vectors), cob=body0(self.cob, fr.convert_vectors), inertia_com=inertia,
            added_mass=body0(self.added_mass, fr.convert_spatial_matrix),
            damping_linear=body0(self.damping_linear, fr.convert_spatial_matrix),
            damping_quadratic=body0(self.damping_quadratic, fr.convert_spatial_matrix),
            damping_point=body0(self.damping_point, fr.convert_vectors),
            damping_cross=body0(self.damping_cross, fr.convert_damping_tensor),
            joint_rotation=joint_rotation, joint_position=joint_position, shape_drag=shape_drag,
            ee_rotation=ee_rotation, ee_position=ee_position, frames=tuple(fixed_frame(f) for f in self.frames),
            thrusters=thrusters, gravity=fr.convert_vectors(self.gravity, src, frame),
            current=fr.convert_vectors(self.current, src, frame),
            fluid_acceleration=fr.convert_vectors(self.fluid_acceleration, src, frame), convention=frame,
            dry_com=None if self.dry_com is None else body0(self.dry_com, fr.convert_vectors),
            point_loads=point_loads, disturbance_wrench=fr.convert_twists(self.disturbance_wrench, src, frame))

    # -- short summaries for the console and notebooks (not kilobytes of arrays)

    def __repr__(self) -> str:
        frame = "" if self.convention == "ned" else f", convention={self.convention!r}"
        return (f"Model({self.name!r}, {self.n_joints} joints, {float(self.mass.sum()):.4g} kg, "
                f"{len(getattr(self, 'thrusters', ()))} thrusters{frame}, source={self.source!r})")

    def _repr_html_(self) -> str:
        import html

        rows = [("name", self.name), ("source", self.source or "-"),
                ("bodies", ", ".join(self.body_names)),
                ("mass", f"{float(self.mass.sum()):.4g} kg (vehicle {float(self.mass[0]):.4g} kg)"),
                ("displaced fluid", f"{float(self.buoyancy_mass.sum()):.4g} kg"),
                ("vehicle box", " x ".join(f"{v:.4g}" for v in getattr(self, "vehicle_box", ())) + " m"),
                ("thrusters", ", ".join(t.name for t in getattr(self, "thrusters", ())) or "none"),
                ("fluid density", f"{self.density:.6g} kg/m^3")]
        body = "".join(f"<tr><th style='text-align:left'>{html.escape(a)}</th>"
                       f"<td style='text-align:left'>{html.escape(b)}</td></tr>" for a, b in rows)
        return f"<div><b>uvms Model</b> (uvms.show(model) draws it)<table>{body}</table></div>"

_TREE_FIELDS = ("joint_names", "joint_parent", "joint_type", "joint_axis", "joint_damping", "joint_friction",
                "joint_friction_speed", "joint_limits", "link_cylinder_rotation", "link_cylinder_origin", "ee_body",
                "frames", "damping_linear", "damping_quadratic", "damping_point", "damping_cross", "shape_drag",
                "shape_count",
                "dry_mass", "dry_com", "point_loads")

def _scale_shape_drag(table: np.ndarray, factor: float) -> np.ndarray:
    """A copy of shape drag tables with the drag coefficients (columns ``COL_COEFFICIENTS..``) scaled."""
    from uvms.hydro.shapes import COL_COEFFICIENTS

    out = np.array(table, dtype=float)
    out[..., COL_COEFFICIENTS:] *= factor
    return out


DEFAULT_FRICTION_SPEED = 0.01
"""Default regularisation speed ``v_s`` of the joint Coulomb friction [rad/s or m/s] (``docs/models.md``)."""
