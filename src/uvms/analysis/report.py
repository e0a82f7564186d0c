"""What a modeller needs to know next about a model at rest: mass and buoyancy, trim, thrust, controller fit.

The statics, the rest attitude and the controller-fit check are :mod:`uvms.analysis.trim`'s (shared with
``uvms trim``); this module adds the static moment, the thrust available per axis and the layout rank.

:func:`model_report` computes every number of ``uvms validate`` (the command only prints
:meth:`ModelReport.table` or :meth:`ModelReport.to_dict`). All quantities are for the system at rest, the arm
at the joint values ``q``, vectors in the vehicle frame of the model's convention (``model.convention``: x forward,
y starboard, z down in ned; x forward, y port, z up in enu; ``docs/conventions.md``, "Frames") and moments about
the vehicle-frame origin.

Mass and buoyancy (paper Eqs. 7-8)
    ``m = sum m_i``, ``m_f = sum m_f,i``; net buoyancy ``(m_f - m) |a_g|`` [N], positive when the system rises.
    Centre of mass ``r_G = sum m_i p_Gi / m`` and centre of buoyancy ``r_B = sum m_f,i p_Bi / m_f`` with the
    body points placed by :func:`uvms.forward_kinematics` (level vehicle at the origin).

Static moment
    Weight at every centre of mass and buoyancy at every centre of buoyancy, vehicle level::

        M_static = (m r_G - m_f r_B) x a_g            [K, M, N] [N m], about the vehicle origin

Trim (the roll and pitch it settles to)
    The attitude at which the weight through ``r_G`` and the buoyancy through ``r_B`` act on one vertical line,
    with the centre of buoyancy above the centre of mass (the stable one of the two). In body axes this is
    ``R^T a_g / |a_g| = d / |d|`` with ``d = r_G - r_B``; for gravity along world +z (ned; in enu along -z, and
    ``d`` enters with its sign flipped) and ZYX Euler angles with yaw 0,
    ``R^T e_z = (-sin theta, sin phi cos theta, cos phi cos theta)``, so (closed form)::

        phi = atan2(d_y, d_z)       theta = atan2(-d_x, sqrt(d_y^2 + d_z^2))

    ``d`` does not depend on the vehicle's attitude (the arm's pose in the vehicle frame is fixed by ``q``),
    so this is exact, not a linearisation. The righting moment about the centre of mass at a tilt ``alpha``
    away from trim is ``m_f |a_g| |d| sin(alpha)``; :attr:`ModelReport.righting_moment_Nm` is its amplitude
    ``m_f |a_g| |d|``. When ``d = 0`` (centres coincide) or there is no buoyancy or gravity there is no
    righting moment and no stable attitude. (Decision: the trim is taken about the centre of mass, so it also
    holds for a model that is not neutrally buoyant and rises or sinks while it rights itself; for a neutral
    model it is the attitude at which the static moment about the origin vanishes.)

Thrust available per body axis (paper Eq. 11, ``f_0 = Lambda T``)
    For each axis ``j`` (surge X, sway Y, heave Z [N]; roll K, pitch M, yaw N [N m]) the largest wrench
    component ``+/- w_j`` that thrusts within their steady limits produce **with every other wrench component
    held at zero**, by linear programming (:func:`scipy.optimize.linprog`, HiGHS)::

        max  +/- Lambda_j T    subject to  Lambda_k T = 0 (k != j),  T_min <= T <= T_max

    Limits: ``parameters.max_thrust`` forward (the steady thrust at the supply voltage for a Healey thruster),
    ``parameters.min_thrust`` in reverse when the model has one (datasheet tables), else ``-max_thrust`` (the
    models are odd). An infinite limit (ideal thruster without one) gives ``inf``.

Thruster layout rank
    ``rank(Lambda)`` of the (6, m) allocation matrix with columns ``[r x e; e]``. An axis is named *missing*
    when its pure unit wrench is outside the column space of ``Lambda`` (whatever the thrust limits); this
    test does not depend on the units chosen for moments and forces.

Sliding-mode controller fit (paper Eqs. 27-29)
    Effective mass or inertia of axis ``j``: ``1 / (M^-1)_jj`` of the joint-space mass matrix ``M``
    (:func:`uvms.mass_matrix`, rigid body and added mass) at ``q`` -- the inertia a force on that axis meets
    when every other vehicle axis and every joint is free (the vehicle block of ``M^-1`` is the inverse of the
    articulated inertia at the vehicle, as in :func:`uvms.reproduce.plant_effective_inertia`). A warning is
    raised for each controlled axis (surge, sway, yaw) whose value lies outside the controller's
    ``[b_min, b_max]`` (default: the paper's, :class:`uvms.control.smc.SlidingModeParameters`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from uvms.analysis.trim import (AXES, CONTROLLED_AXES, INERTIA_UNITS, WRENCH_ROW, b_bounds_check,  # noqa: F401
                                centres, effective_inertia, joint_values, rest_attitude, statics, trim_attitude)
from uvms.frames import VEHICLE_AXES

AXIS_UNITS: tuple[str, ...] = ("N", "N", "N", "N m", "N m", "N m")
"""Units of the thrust available along or about each axis of :data:`AXES`."""
THRUST_METHOD = "linear programming over thrusts within their limits, the other five axes held at zero"
"""How :attr:`ModelReport.thrust_forward_N` and :attr:`ModelReport.thrust_reverse_N` are computed."""
_TOL = 1e-9


@dataclass(frozen=True, eq=False)
class ModelReport:
    """The statics, actuation and controller-fit report of a model at rest (:func:`model_report`).

    Per-axis arrays follow :data:`AXES` (surge, sway, heave, roll, pitch, yaw). Vectors are in the vehicle
    frame, level, arm at ``q``; moments are about the vehicle origin.

    Attributes:
        model_name: the model's name.
        joint_names: joint order of ``q``.
        q: (n,) joint values of the report [rad or m].
        gravity_m_s2: ``|a_g|`` [m/s^2].
        mass_kg: total rigid-body mass ``m`` [kg].
        displaced_mass_kg: total displaced-fluid mass ``m_f`` [kg].
        net_buoyancy_N: ``(m_f - m) |a_g|`` [N], positive up (the system rises).
        center_of_mass_m: (3,) total centre of mass ``r_G`` [m].
        center_of_buoyancy_m: (3,) total centre of buoyancy ``r_B`` [m] (NaN without displaced fluid).
        static_moment_Nm: (3,) ``[K, M, N]`` of weight and buoyancy about the vehicle origin, level [N m].
        righting_moment_Nm: amplitude ``m_f |a_g| |r_G - r_B|`` of the righting moment [N m] (0: none).
        trim_roll_rad, trim_pitch_rad: ZYX roll and pitch the system settles to [rad], or ``None``.
        trim_note: why there is no trim attitude, or ``""``.
        thrust_forward_N: (6,) largest thrust along/about each axis in the + sense [N or N m] (``inf``: no limit).
        thrust_reverse_N: (6,) largest in the - sense, as a positive number [N or N m].
        thrust_method: how the two above are computed (:data:`THRUST_METHOD`).
        n_thrusters: number of thrusters.
        allocation_rank: rank of the (6, m) allocation matrix.
        missing_axes: axes whose pure wrench no thrust can produce.
        effective_inertia: (6,) ``1 / (M^-1)_jj`` per axis [kg or kg m^2].
        b_bounds: ``{axis: (b_min, b_max)}`` of the sliding-mode controller checked against.
        warnings: human-readable warnings (effective inertia outside the ``b`` bounds).
    """

    model_name: str
    joint_names: tuple[str, ...]
    q: np.ndarray
    gravity_m_s2: float
    mass_kg: float
    displaced_mass_kg: float
    net_buoyancy_N: float
    center_of_mass_m: np.ndarray
    center_of_buoyancy_m: np.ndarray
    static_moment_Nm: np.ndarray
    righting_moment_Nm: float
    trim_roll_rad: float | None
    trim_pitch_rad: float | None
    trim_note: str
    thrust_forward_N: np.ndarray
    thrust_reverse_N: np.ndarray
    thrust_method: str
    n_thrusters: int
    allocation_rank: int
    missing_axes: tuple[str, ...]
    effective_inertia: np.ndarray
    b_bounds: dict[str, tuple[float, float]]
    warnings: tuple[str, ...]
    frame: str = "ned"
    hydro_sources: tuple[tuple[str, str], ...] = ()
    """Which tag of a Gazebo file each hydrodynamic number came from (:attr:`uvms.model.model.Model.hydro_sources`)."""
    disturbance_wrench: tuple[float, ...] = ()
    """The model's constant disturbance wrench ``[K M N X Y Z]`` [N m, N] when it is not zero, else empty (it acts in
    every run, not in the statics or the trim above; ``docs/models.md``, "Disturbance wrench")."""

    def table(self) -> str:
        """The report as aligned text lines (what ``uvms validate`` prints after its summary)."""
        def vec(v, unit):
            return "(" + ", ".join(f"{x + 0.0:.6g}" for x in v) + f") {unit}"

        at = ", ".join(f"{n}={v:.6g}" for n, v in zip(self.joint_names, self.q)) or "no joints"
        lines = [f"statics at rest (vehicle level, {at}; vehicle frame {VEHICLE_AXES[self.frame]}):",
                 f"  total mass:           {self.mass_kg:.6g} kg",
                 f"  displaced fluid mass: {self.displaced_mass_kg:.6g} kg",
                 f"  net buoyancy:         {self.net_buoyancy_N:.6g} N (positive: rises)",
                 f"  centre of mass:       {vec(self.center_of_mass_m, 'm')}",
                 "  centre of buoyancy:   " + (vec(self.center_of_buoyancy_m, 'm')
                                               if np.all(np.isfinite(self.center_of_buoyancy_m)) else "none"),
                 f"  static moment:        {vec(self.static_moment_Nm, 'N m')} (K, M, N about the vehicle origin)",
                 f"  righting moment:      {self.righting_moment_Nm:.6g} N m x sin(tilt away from trim)"]
        if self.trim_roll_rad is None:
            lines.append(f"  settles to:           no stable attitude ({self.trim_note})")
        else:
            lines.append(f"  settles to:           roll {math.degrees(self.trim_roll_rad) + 0.0:.4g} deg, "
                         f"pitch {math.degrees(self.trim_pitch_rad) + 0.0:.4g} deg (ZYX Euler, yaw 0)")
        if self.n_thrusters == 0:
            lines.append("thrust available: no thrusters (ideal actuation: a commanded body wrench is applied as "
                         "it is)")
        else:
            lines.extend(self._thrust_lines())
        lines.append("effective mass/inertia 1/(M^-1)_jj (rigid body + added mass, joints free):")
        lines.append("  " + ", ".join(f"{a} {v:.4g} {u}" for a, v, u in
                                      zip(AXES, self.effective_inertia, INERTIA_UNITS)))
        if self.hydro_sources:
            lines.append("hydrodynamics read from the file's tags:")
            lines.extend(f"  {what}: {tag}" for what, tag in self.hydro_sources)
        if self.disturbance_wrench:
            lines.append(f"disturbance wrench:     {vec(self.disturbance_wrench[:3], 'N m')} (K, M, N), "
                         f"{vec(self.disturbance_wrench[3:], 'N')} (X, Y, Z), body axes: in every run, not in the "
                         "statics above")
        lines.extend(f"warning: {w}" for w in self.warnings)
        return "\n".join(lines)

    def _thrust_lines(self) -> list[str]:
        def amount(x):
            return "unlimited" if math.isinf(x) else f"{x:.4g}"

        lines = [f"thrust available ({self.n_thrusters} thrusters; {self.thrust_method}):"]
        for axis, fwd, rev, unit in zip(AXES, self.thrust_forward_N, self.thrust_reverse_N, AXIS_UNITS):
            lines.append(f"  {axis:<6} +{amount(fwd)} / -{amount(rev)} {unit}")
        missing = ", ".join(self.missing_axes)
        lines.append(f"  layout rank {self.allocation_rank} of 6" + (f"; cannot push in: {missing}" if missing
                                                                      else ": pushes in all six directions"))
        return lines

    def to_dict(self) -> dict[str, Any]:
        """The report as plain JSON-able values; units in the key names, ``null`` for "none" or "no limit"."""
        def finite_or_none(v):
            return [float(x) if math.isfinite(x) else None for x in v]

        trim = None if self.trim_roll_rad is None else {"roll_rad": self.trim_roll_rad,
                                                        "pitch_rad": self.trim_pitch_rad}
        sources = {"hydro_sources": dict(self.hydro_sources)} if self.hydro_sources else {}
        if self.disturbance_wrench:
            sources["disturbance_wrench_KMN_Nm_XYZ_N"] = list(self.disturbance_wrench)
        return {**sources, 
            "model": self.model_name,
            "frame": self.frame,
            "q": dict(zip(self.joint_names, (float(x) for x in self.q))),
            "gravity_m_s2": self.gravity_m_s2,
            "total_mass_kg": self.mass_kg,
            "displaced_mass_kg": self.displaced_mass_kg,
            "net_buoyancy_N": self.net_buoyancy_N,
            "center_of_mass_m": finite_or_none(self.center_of_mass_m),
            "center_of_buoyancy_m": finite_or_none(self.center_of_buoyancy_m),
            "static_moment_KMN_Nm": [float(x) for x in self.static_moment_Nm],
            "righting_moment_Nm": self.righting_moment_Nm,
            "trim": trim,
            "trim_note": self.trim_note,
            "thrust": {
                "method": self.thrust_method,
                "n_thrusters": self.n_thrusters,
                "forward_N_or_Nm": dict(zip(AXES, finite_or_none(self.thrust_forward_N))),
                "reverse_N_or_Nm": dict(zip(AXES, finite_or_none(self.thrust_reverse_N))),
                "allocation_rank": self.allocation_rank,
                "missing_axes": list(self.missing_axes),
            },
            "effective_inertia_kg_or_kgm2": dict(zip(AXES, (float(x) for x in self.effective_inertia))),
            "b_bounds_kg_or_kgm2": {a: list(b) for a, b in self.b_bounds.items()},
            "warnings": list(self.warnings),
        }


def thruster_limits(thruster) -> tuple[float, float]:
    """``(lower, upper)`` steady thrust [N] of one thruster: ``min_thrust`` if its model has one, else
    ``-max_thrust`` (odd models)."""
    upper = float(thruster.parameters.max_thrust)
    lower = float(getattr(thruster.parameters, "min_thrust", -upper))
    return lower, upper


def available_thrust(Lambda: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(6,) largest ``+w_j`` and (6,) largest ``-w_j`` (as positive numbers) per axis of :data:`AXES`, the
    other wrench components zero, thrusts within ``[lower, upper]`` (linear programming; ``inf`` if
    unbounded)."""
    from scipy.optimize import linprog

    m = Lambda.shape[1]
    forward, reverse = np.zeros(6), np.zeros(6)
    if m == 0:
        return forward, reverse
    bounds = [(None if math.isinf(lo) else lo, None if math.isinf(hi) else hi) for lo, hi in zip(lower, upper)]
    for a, row in enumerate(WRENCH_ROW):
        others = np.delete(Lambda, row, axis=0)
        for sign, out in ((1.0, forward), (-1.0, reverse)):
            res = linprog(-sign * Lambda[row], A_eq=others, b_eq=np.zeros(5), bounds=bounds, method="highs")
            if res.status == 3:
                out[a] = math.inf
            elif res.status == 0:
                value = float(-res.fun)
                out[a] = value if value > _TOL * max(1.0, float(np.abs(upper[np.isfinite(upper)]).sum(
                    initial=0.0))) else 0.0
            else:  # T = 0 is always feasible: anything else is a solver failure
                raise RuntimeError(f"linprog failed on axis {AXES[a]}: {res.message}")
    return forward, reverse


def missing_axes(Lambda: np.ndarray) -> tuple[int, tuple[str, ...]]:
    """``(rank, names)``: rank of ``Lambda`` and the axes of :data:`AXES` whose unit wrench is outside its column
    space."""
    if Lambda.shape[1] == 0:
        return 0, AXES
    U, s, _ = np.linalg.svd(Lambda, full_matrices=True)
    rank = int(np.sum(s > 1e-10 * max(1.0, float(s.max()))))
    N = U[:, rank:]
    return rank, tuple(a for a, row in zip(AXES, WRENCH_ROW) if float(np.linalg.norm(N[row])) > 1e-8)


def end_effector_name(model) -> str:
    """The name the model file gives the end effector: the named frame it was placed at (a URDF model's
    ``end_effector: tool``, or the deepest link by default), or ``"end_effector"`` for a frame of its own (the
    YAML arm's DH end effector). The model keeps a copy of that frame under ``"end_effector"``, so this is the
    first other frame fixed in the same body at the same pose (frames that coincide, such as two jaw links on
    one fixed joint, are one frame under two names: the first, as the URDF's deepest-link default takes it)."""
    from uvms.model.model import END_EFFECTOR

    ee = model.frame(END_EFFECTOR)
    same = [f.name for f in model.frames if f.name != END_EFFECTOR and f.body == ee.body
            and np.array_equal(f.position, ee.position) and np.array_equal(f.rotation, ee.rotation)]
    return same[0] if same else END_EFFECTOR


def model_report(model, q=None, *, controller=None) -> ModelReport:
    """The statics, actuation and controller-fit report of ``model`` at rest, arm at ``q`` (module docstring).

    Args:
        model: a :class:`uvms.Model`.
        q: joint values in ``model.joint_names`` order [rad or m]; default zeros.
        controller: :class:`uvms.control.smc.SlidingModeParameters` whose ``b`` bounds are checked (default:
            the paper's).

    Raises:
        UvmsInputError: ``q`` of the wrong length or not finite.
    """
    from uvms.thrusters.layouts import layout_matrix

    q = joint_values(model, q)
    s = statics(model, q)
    g, m, mf, r_G, r_B = s.gravity, s.mass, s.fluid_mass, s.center_of_mass, s.center_of_buoyancy
    static = np.cross(s.first_moment_mass - s.first_moment_fluid, np.asarray(model.gravity, dtype=float))
    roll, pitch, note = rest_attitude(model, s)
    righting = 0.0 if roll is None else mf * g * float(np.linalg.norm(r_G - r_B))

    thrusters = tuple(model.thrusters)
    Lambda = layout_matrix(thrusters)
    limits = np.array([thruster_limits(t) for t in thrusters], dtype=float).reshape(-1, 2)
    forward, reverse = available_thrust(Lambda, limits[:, 0], limits[:, 1])
    rank, missing = missing_axes(Lambda)

    inertia = effective_inertia(model, q)
    bounds, warnings = b_bounds_check(inertia, controller)
    for arr in (q, r_G, r_B, static, forward, reverse, inertia):
        arr.setflags(write=False)
    return ModelReport(
        model_name=model.name, joint_names=tuple(model.joint_names), q=q, gravity_m_s2=g, mass_kg=m,
        displaced_mass_kg=mf, net_buoyancy_N=(mf - m) * g, center_of_mass_m=r_G, center_of_buoyancy_m=r_B,
        static_moment_Nm=static, righting_moment_Nm=righting, trim_roll_rad=roll, trim_pitch_rad=pitch,
        trim_note=note, thrust_forward_N=forward, thrust_reverse_N=reverse, thrust_method=THRUST_METHOD,
        n_thrusters=len(thrusters), allocation_rank=rank, missing_axes=missing, effective_inertia=inertia,
        b_bounds=bounds, warnings=warnings, frame=model.convention,
        hydro_sources=tuple(getattr(model, "hydro_sources", ())),
        disturbance_wrench=tuple(float(x) for x in model.disturbance_wrench) if np.any(model.disturbance_wrench)
        else ())
