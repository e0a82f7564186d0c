"""The frozen model: every physical parameter of a vehicle-manipulator system, in SI units.

A :class:`Model` is built once from a validated model file (:mod:`uvms.model.build`) and never mutated.
Bodies are numbered as in the paper: 0 is the vehicle, 1..n the arm links (link i moves with joint i).
Every per-body array has a leading axis of length ``n_bodies = n_joints + 1``; per-joint arrays have length
``n_joints``. Spatial quantities are ``[angular; linear]`` and expressed in the body's own frame, about its
frame origin (the vehicle's reference point, or the link's joint), unless a name says otherwise.

The compiled kernels read :attr:`Model.kernel`, a :class:`uvms.dynamics.kernel_model.KernelModel` of flat
arrays derived from the fields below when the model is built.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np


def _frozen(a: Any, dtype=float) -> np.ndarray:
    out = np.array(a, dtype=dtype, copy=True)
    out.setflags(write=False)
    return out


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
        link_length: (n,) cylinder length along the link x axis, from the joint [m] (Eq. 6).
        link_drag_coefficient: (n,) normal-flow drag coefficient of each link [-] (Eq. 6).
        joint_rotation: (n, 3, 3) orientation of joint frame i in its parent frame before the joint angle
            (mount transform and modified-DH ``RotX(alpha_prev)``).
        joint_position: (n, 3) origin of joint frame i in its parent frame [m].
        theta_offset: (n,) modified-DH ``theta_offset``; the link rotates by ``q + theta_offset`` about z [rad].
        ee_rotation: (3, 3) end-effector frame orientation in the last link's frame.
        ee_position: (3,) end-effector origin in the last link's frame [m].
        density: fluid density ``rho`` [kg/m^3].
        gravity: (3,) gravitational acceleration in the world frame (z down) [m/s^2].
        current: (3,) default constant current velocity in the world frame [m/s].
        fluid_acceleration: (3,) default fluid acceleration in the world frame [m/s^2].
        thrusters: thruster layout (tuple of thruster descriptions; empty for ideal actuation).
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
    kernel: Any = field(init=False, repr=False)

    def __post_init__(self) -> None:
        for name in ("mass", "com", "inertia_com", "added_mass", "buoyancy_mass", "cob", "vehicle_drag_area",
                     "vehicle_drag_coefficient", "vehicle_box", "link_radius", "link_length",
                     "link_drag_coefficient", "joint_rotation", "joint_position", "theta_offset", "ee_rotation",
                     "ee_position", "gravity", "current", "fluid_acceleration"):
            object.__setattr__(self, name, _frozen(getattr(self, name)))
        object.__setattr__(self, "vehicle_rotational_drag_side", float(self.vehicle_rotational_drag_side))
        object.__setattr__(self, "vehicle_rotational_drag_coefficient",
                           float(self.vehicle_rotational_drag_coefficient))
        object.__setattr__(self, "density", float(self.density))
        from uvms.checks import check_joint_axis_inertia
        from uvms.dynamics.kernel_model import kernel_model_from

        check_joint_axis_inertia(self.mass, self.com, self.inertia_com, self.added_mass, source=self.source,
                                 where=lambda j: f"link {self.body_names[j + 1]!r} (body {j + 1})")

        object.__setattr__(self, "kernel", kernel_model_from(self))

    @property
    def n_joints(self) -> int:
        """Number of revolute arm joints ``n``."""
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
        """A new model with some fields changed (the model itself is never mutated)."""
        return replace(self, **changes)

    def with_effects(self, *, added_mass: bool = True, drag: bool = True, buoyancy: bool = True,
                     gravity: bool = True, current: bool = True) -> "Model":
        """A copy with some physical effects switched off (their parameters set to zero).

        ``buoyancy=False`` removes the displaced-fluid force of Eqs. 7-8 (buoyancy and fluid acceleration).
        """
        changes: dict[str, Any] = {}
        if not added_mass:
            changes["added_mass"] = np.zeros_like(self.added_mass)
        if not drag:
            changes["vehicle_drag_coefficient"] = np.zeros(3)
            changes["vehicle_rotational_drag_coefficient"] = 0.0
            changes["link_drag_coefficient"] = np.zeros_like(self.link_drag_coefficient)
        if not buoyancy:
            changes["buoyancy_mass"] = np.zeros_like(self.buoyancy_mass)
        if not gravity:
            changes["gravity"] = np.zeros(3)
        if not current:
            changes["current"] = np.zeros(3)
            changes["fluid_acceleration"] = np.zeros(3)
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
            thrusters=self.thrusters,
        )

    # -- short summaries for the console and notebooks (not kilobytes of arrays)

    def __repr__(self) -> str:
        return (f"Model({self.name!r}, {self.n_joints} joints, {float(self.mass.sum()):.4g} kg, "
                f"{len(getattr(self, 'thrusters', ()))} thrusters, source={self.source!r})")

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
