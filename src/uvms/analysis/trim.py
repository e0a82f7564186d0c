"""Trim: the attitude a vehicle-manipulator system rests at, and the ballast that levels it.

All quantities are for the system at rest with the arm at joint values ``q``, vectors in the vehicle frame of
the model's convention (``model.convention``: x forward, y starboard, z down in ned; x forward, y port, z up in enu;
``docs/conventions.md``, "Frames"). The formulas below are written for ned; an enu model's gravity along world
-z flips ``d`` in :func:`trim_attitude`, and :func:`level_ballast` solves in ned and maps the result back. :mod:`uvms.analysis.report` (``uvms validate``) uses
the same functions; ``uvms trim`` prints :func:`trim`.

Statics (paper Eqs. 7-8)
    ``m = sum m_i``, ``m_f = sum m_f,i``, ``r_G = sum m_i p_Gi / m``, ``r_B = sum m_f,i p_Bi / m_f`` (body points
    placed by :func:`uvms.forward_kinematics`, vehicle level at the origin; ``m_i`` and its centre are the
    weight's, :attr:`uvms.Model.weight_mass`: the dry mass of a model whose inertia includes added mass);
    net vertical force ``(m_f - m) |a_g|``, positive up (positively buoyant: rises).

Rest attitude
    Weight through ``r_G`` and buoyancy through ``r_B`` on one vertical line, centre of buoyancy above: in body
    axes ``R^T a_g / |a_g| = d / |d|``, ``d = r_G - r_B``; with ZYX Euler angles and yaw 0
    (:func:`trim_attitude`)::

        phi = atan2(d_y, d_z)       theta = atan2(-d_x, sqrt(d_y^2 + d_z^2))

    exact (``d`` does not depend on the attitude), taken about the centre of mass so that it also holds for a
    system that is not neutrally buoyant (``docs/conventions.md``, "Trim").

Ballast that levels it (:func:`level_ballast`)
    An amount ``a >= 0`` of ballast at one point ``c`` of a box ``region`` (vehicle frame), with mass ``mu a`` and
    displaced-fluid mass ``beta a``: a point mass (``a`` in kg: ``mu = 1``, ``beta = 0``) or buoyancy foam (``a``
    in m^3: ``mu = rho_foam``, ``beta = rho``). After it ``d' = r_G' - r_B'`` satisfies, exactly (the ``a^2``
    terms cancel)::

        (m + mu a)(m_f + beta a) d' = m m_f d + a w(c),     w(c) = mu m_f (c - r_B) - beta m (c - r_G)

    Level means ``d'_x = d'_y = 0`` and stable ``d'_z > 0``. With ``y = a c`` every condition is linear in
    ``(a, y)``: ``w`` is affine in ``c``, and ``c`` in the box is ``a lo <= y <= a hi``. Two linear programs
    (:func:`scipy.optimize.linprog`, HiGHS): the least ballast ``a``, then at that amount the position with the
    largest ``d'_z`` (the righting arm). A ballast limit ``a <= max_amount`` or a region that cannot level it:
    no solution, one :class:`~uvms.errors.UvmsInputError` line.

Controller fit (paper Eqs. 27-29)
    :func:`effective_inertia` ``1 / (M^-1)_jj`` per body axis and :func:`b_bounds_check` (the sliding-mode ``b``
    bounds, the paper's by default: ``uvms.control.smc.PAPER_B_*``), with one warning line per axis outside.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from uvms.dynamics.axes import AXES, INERTIA_UNITS, WRENCH_ROW, effective_inertia  # noqa: F401
from uvms.errors import UvmsInputError, show
from uvms.frames import VEHICLE_AXES, convert_vectors

CONTROLLED_AXES: tuple[str, ...] = ("surge", "sway", "yaw")
"""Axes of the sliding-mode controller (``uvms.control.smc.AXES``), in the order of its ``b_limits()``."""
BALLAST_KINDS: tuple[str, ...] = ("mass", "foam")
"""Kinds of levelling ballast: a point mass [kg], or buoyancy foam [m^3]."""


# ----------------------------------------------------------------------------------------------- statics


def joint_values(model, q) -> np.ndarray:
    """``q`` as (n,) finite floats in the model's joint order (zeros when ``None``); a mapping
    ``{joint name: value}`` sets the named joints (others zero); ``UvmsInputError`` else."""
    n = model.n_joints
    if q is None:
        return np.zeros(n)
    if isinstance(q, dict):
        values = np.zeros(n)
        for name, value in q.items():
            if name not in model.joint_names:
                raise UvmsInputError(f"model {model.name!r} has no joint {show(name)}; joints: "
                                     f"{', '.join(model.joint_names) or '(none)'}", path="q")
            try:
                values[model.joint_names.index(name)] = float(value)
            except (TypeError, ValueError):
                raise UvmsInputError(f"joint {name!r}: expected a number, found {show(value)}", path="q") from None
        q = values
    try:
        values = np.array(q, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise UvmsInputError(f"expected {n} numbers, found {show(q)}", path="q") from None
    if values.size != n:
        order = ", ".join(model.joint_names) or "none"
        raise UvmsInputError(f"expected {n} joint values (joints: {order}), found {values.size}", path="q")
    if not np.all(np.isfinite(values)):
        raise UvmsInputError(f"expected finite joint values, found {show(values.tolist())}", path="q")
    return values


def centres(model, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """World points (vehicle level at the origin) of every body's centre of mass (where its weight acts,
    :attr:`uvms.Model.weight_center`) and of buoyancy, (nb, 3) each."""
    from uvms.dynamics.poses import forward_kinematics
    from uvms.state import State

    poses = forward_kinematics(model, State.from_euler(model, q=q))
    R, p = poses.rotation[:model.n_bodies], poses.position[:model.n_bodies]
    return (p + np.einsum("bij,bj->bi", R, model.weight_center), p + np.einsum("bij,bj->bi", R, model.cob))


@dataclass(frozen=True)
class Statics:
    """Totals of a system at rest, level, arm at ``q`` (vehicle frame): ``m``, ``m_f`` [kg], ``r_G``, ``r_B`` [m]
    (``r_B`` NaN without displaced fluid), the first moments ``m r_G``, ``m_f r_B`` [kg m] and ``|a_g|``."""

    mass: float
    fluid_mass: float
    center_of_mass: np.ndarray
    center_of_buoyancy: np.ndarray
    first_moment_mass: np.ndarray
    first_moment_fluid: np.ndarray
    gravity: float

    @property
    def net_buoyancy(self) -> float:
        """``(m_f - m) |a_g|`` [N], positive up."""
        return (self.fluid_mass - self.mass) * self.gravity


def statics(model, q: np.ndarray) -> Statics:
    """:class:`Statics` of ``model`` with the arm at ``q`` (module docstring)."""
    mass, fluid = np.asarray(model.weight_mass, dtype=float), np.asarray(model.buoyancy_mass, dtype=float)
    m, mf = float(mass.sum()), float(fluid.sum())
    p_com, p_cob = centres(model, q)
    first_mass, first_fluid = mass @ p_com, fluid @ p_cob
    r_B = first_fluid / mf if mf > 0 else np.full(3, np.nan)
    return Statics(m, mf, first_mass / m, r_B, first_mass, first_fluid, float(np.linalg.norm(model.gravity)))


def trim_attitude(d: np.ndarray, gravity: np.ndarray) -> tuple[float | None, float | None, str]:
    """ZYX ``(roll, pitch)`` with yaw 0 at which ``R^T a_g`` is along ``d = r_G - r_B`` (module docstring), or
    ``(None, None, why)``."""
    g = float(np.linalg.norm(gravity))
    if g == 0.0:
        return None, None, "no gravity"
    scale = max(1.0, float(np.max(np.abs(d))))
    if float(np.linalg.norm(d)) <= 1e-12 * scale:
        return None, None, "centre of mass and centre of buoyancy coincide"
    ghat = gravity / g
    if abs(abs(ghat[2]) - 1.0) > 1e-12:
        return None, None, "gravity is not along the world z axis"
    d = d * np.sign(ghat[2])       # R^T (-e_z) = d/|d|  <=>  R^T e_z = -d/|d|
    roll = math.atan2(d[1], d[2])
    pitch = math.atan2(-d[0], math.hypot(d[1], d[2]))
    return roll, pitch, ""


def rest_attitude(model, s: Statics) -> tuple[float | None, float | None, str]:
    """The rest ``(roll, pitch, note)`` of :func:`trim_attitude` for :class:`Statics` ``s``."""
    if s.fluid_mass <= 0:
        return None, None, "no displaced fluid (no buoyancy)"
    return trim_attitude(s.center_of_mass - s.center_of_buoyancy, np.asarray(model.gravity, dtype=float))


# -------------------------------------------------------------------------------------- controller fit


def b_bounds_check(inertia: np.ndarray, controller=None) -> tuple[dict[str, tuple[float, float]], tuple[str, ...]]:
    """The sliding-mode ``b`` bounds per controlled axis (``controller``: a
    :class:`uvms.control.smc.SlidingModeParameters`, default the paper's) and at most one warning line naming
    every axis whose effective inertia (:func:`effective_inertia`) lies outside them (only the sliding-mode
    controllers with fixed bounds use them: :func:`uvms.control.smc.b_bounds_misses`)."""
    from uvms.control.smc import SlidingModeParameters, b_bounds_misses

    params = controller if controller is not None else SlidingModeParameters()
    bounds = {axis: (float(lo), float(hi)) for axis, (lo, hi) in zip(CONTROLLED_AXES, params.b_limits())}
    misses = b_bounds_misses(params, inertia)
    who = "the paper's b bounds" if controller is None else "its b bounds"
    return bounds, ((f"sliding-mode controller: {who} (used by smc-ab, smc-ne, smc-vehicle with b_source: fixed; "
                     f"not by pid, lqr) miss {misses} (paper Eqs. 27-29 assume it inside)",) if misses else ())


# ------------------------------------------------------------------------------------------------ ballast


@dataclass(frozen=True, eq=False)
class Ballast:
    """A levelling ballast (:func:`level_ballast`).

    Attributes:
        kind: ``"mass"`` (a point mass) or ``"foam"`` (buoyancy foam).
        amount: kg of mass or m^3 of foam.
        mass_kg: its mass [kg].
        displaced_mass_kg: the fluid it displaces [kg].
        position_m: (3,) where its centre goes, vehicle frame [m].
        region_m: (2, 3) the box it was placed in (lower and upper corner), vehicle frame [m].
        net_buoyancy_after_N: the system's net vertical force with it [N], positive up.
        righting_arm_after_m: ``d'_z``, the height of the centre of buoyancy above the centre of mass with it [m].
    """

    kind: str
    amount: float
    mass_kg: float
    displaced_mass_kg: float
    position_m: np.ndarray
    region_m: np.ndarray
    net_buoyancy_after_N: float
    righting_arm_after_m: float

    @property
    def unit(self) -> str:
        return "kg" if self.kind == "mass" else "m^3"

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "amount": self.amount, "unit": self.unit, "mass_kg": self.mass_kg,
                "displaced_mass_kg": self.displaced_mass_kg, "position_m": [float(x) for x in self.position_m],
                "region_m": [[float(x) for x in row] for row in self.region_m],
                "net_buoyancy_after_N": self.net_buoyancy_after_N,
                "righting_arm_after_m": self.righting_arm_after_m}


MIN_ARM = 0.001
"""Default least height [m] of the centre of buoyancy above the centre of mass after levelling (a stable, not
marginal, level attitude)."""


def default_region(model) -> np.ndarray:
    """(2, 3) the vehicle's outline box (``vehicle.box``) centred on the vehicle origin."""
    half = 0.5 * np.asarray(model.vehicle_box, dtype=float)
    return np.array([-half, half])


def _region(model, region) -> np.ndarray:
    """(2, 3) the box ``region`` (default :func:`default_region`): two finite corners, the lower first."""
    if region is None:
        return default_region(model)
    try:
        raw = np.asarray(region)
        if raw.dtype.kind not in "iuf":         # strings, booleans, None
            raise TypeError
        box = np.array(raw, dtype=float).reshape(2, 3)
    except (TypeError, ValueError):
        raise UvmsInputError(f"expected two corners [[x0, y0, z0], [x1, y1, z1]] [m], found {show(region)}",
                             path="region") from None
    if not np.all(np.isfinite(box)):
        raise UvmsInputError(f"expected finite corners [m], found {show(box.tolist())}", path="region")
    if np.any(box[0] > box[1]):
        axis = "xyz"[int(np.flatnonzero(box[0] > box[1])[0])]
        raise UvmsInputError(f"expected the lower corner first ({axis}0 <= {axis}1) [m], found "
                             f"{show(box.tolist())}", path="region")
    return box


def _amount(value, name: str) -> float:
    """A finite number >= 0 (a number, not a string or a boolean), else one line naming ``name``."""
    from numbers import Real

    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (Real, np.integer, np.floating)) or \
            not (math.isfinite(float(value)) and float(value) >= 0):
        raise UvmsInputError(f"expected a finite number >= 0, found {show(value)}", path=name)
    return float(value)


def check_ballast_options(model, kind: str = "mass", region=None, max_amount: float | None = None,
                          foam_density: float = 0.0, min_arm: float = MIN_ARM) -> np.ndarray:
    """Every option of :func:`level_ballast` checked (whether or not a ballast turns out to be needed): the kind,
    the region (two finite corners, the lower first), ``max_amount`` (``None`` or finite >= 0), the foam density
    (finite, in ``[0, rho)``: lighter than the water) and ``min_arm`` (finite >= 0); one
    :class:`~uvms.errors.UvmsInputError` line naming the option. Returns the (2, 3) region."""
    if kind not in BALLAST_KINDS:
        raise UvmsInputError(f"expected one of {', '.join(BALLAST_KINDS)}, found {show(kind)}", path="ballast")
    box = _region(model, region)
    rho = float(model.density)
    density = foam_density
    if isinstance(density, (bool, np.bool_)) or not isinstance(density, (int, float, np.integer, np.floating)) or \
            not 0.0 <= float(density) < rho:
        raise UvmsInputError(f"expected a foam density in [0, {rho:.6g}) kg/m^3 (lighter than the water), found "
                             f"{show(foam_density)}", path="foam_density")
    _amount(min_arm, "min_arm")
    if max_amount is not None:
        _amount(max_amount, "max_amount")
    return box


def level_ballast(model, s: Statics, *, kind: str = "mass", region=None, max_amount: float | None = None,
                  foam_density: float = 0.0, min_arm: float = MIN_ARM) -> Ballast:
    """The least ballast within ``region`` that levels the system, placed where its righting arm is largest
    (module docstring).

    Args:
        model: the model (density, outline box).
        s: its :class:`Statics` at the arm pose.
        kind: ``"mass"`` (``amount`` in kg) or ``"foam"`` (``amount`` in m^3).
        region: (2, 3) box of allowed positions, vehicle frame [m] (default :func:`default_region`).
        max_amount: the most ballast allowed (kg or m^3); ``None``: no limit.
        foam_density: the foam's own density [kg/m^3] (``kind="foam"``; 0: ideal massless buoyancy).
        min_arm: the least height of the centre of buoyancy above the centre of mass after it [m].

    Raises:
        UvmsInputError: no ballast in the region and within the limit levels it (one line).
    """
    from scipy.optimize import linprog

    box = check_ballast_options(model, kind, region, max_amount, foam_density, min_arm)
    frame = model.convention
    if frame != "ned":      # the conditions below are written z down: solve in ned, map the answer back
        try:
            found = level_ballast(model.in_frame("ned"), _statics_in(s, frame, "ned"), kind=kind,
                                  region=_box_in(box, frame, "ned"), max_amount=max_amount,
                                  foam_density=foam_density, min_arm=min_arm)
        except UvmsInputError as exc:
            if exc.path != "ballast" or s.gravity == 0.0:
                raise
            raise _no_solution(kind, box, max_amount, min_arm) from None
        position = convert_vectors(found.position_m, "ned", frame)
        position.setflags(write=False)
        box.setflags(write=False)
        return replace(found, position_m=position, region_m=box)
    rho = float(model.density)
    if s.gravity == 0.0:
        raise UvmsInputError("no gravity: there is no attitude to level", path="ballast")
    mu, beta = (1.0, 0.0) if kind == "mass" else (float(foam_density), rho)
    m, mf = s.mass, s.fluid_mass
    # w(c) = k c - h   with  k = mu m_f - beta m,  h = mu m_f r_B - beta m r_G = mu S_B - beta S_G (first moments
    # scaled): with y = a c,  a w = k y - a h.  Unknowns z = (a, y_x, y_y, y_z).
    k = mu * mf - beta * m
    h = mu * s.first_moment_fluid - beta * s.first_moment_mass        # mu m_f r_B - beta m r_G
    base = mf * s.first_moment_mass - m * s.first_moment_fluid          # m m_f (r_G - r_B), also for m_f = 0
    A_eq = np.zeros((2, 4))
    A_eq[:, 0] = -h[:2]
    A_eq[0, 1] = A_eq[1, 2] = k
    b_eq = -base[:2]
    A_ub, b_ub = [], []
    for axis in range(3):                       # a lo <= y <= a hi
        row = np.zeros(4)
        row[0], row[1 + axis] = box[0, axis], -1.0
        A_ub.append(row.copy())
        b_ub.append(0.0)
        row[0], row[1 + axis] = -box[1, axis], 1.0
        A_ub.append(row)
        b_ub.append(0.0)
    # d'_z >= min_arm:  base_z + k y_z - a h_z >= min_arm (m m_f + a (mu m_f + beta m))  (+ min_arm mu beta a^2,
    # dropped: exact for a point mass and massless foam, within that term for foam with a mass)
    A_ub.append(np.array([h[2] + min_arm * (mu * mf + beta * m), 0.0, 0.0, -k]))
    b_ub.append(base[2] - min_arm * m * mf)
    bounds = [(0.0, max_amount)] + [(None, None)] * 3
    first = linprog(np.array([1.0, 0.0, 0.0, 0.0]), A_ub=np.array(A_ub), b_ub=np.array(b_ub), A_eq=A_eq, b_eq=b_eq,
                    bounds=bounds, method="highs")
    if first.status != 0:
        raise _no_solution(kind, box, max_amount, min_arm)
    amount = float(first.x[0])
    second = linprog(np.array([h[2], 0.0, 0.0, -k]), A_ub=np.array(A_ub), b_ub=np.array(b_ub), A_eq=A_eq,
                     b_eq=b_eq, bounds=[(amount, amount)] + [(None, None)] * 3, method="highs")
    x = second.x if second.status == 0 else first.x
    amount = float(x[0])
    position = x[1:] / amount if amount > 0 else np.clip(np.zeros(3), box[0], box[1])
    position = np.clip(position, box[0], box[1])
    m_after, mf_after = m + mu * amount, mf + beta * amount
    if mf_after <= 0:
        raise _no_solution(kind, box, max_amount, min_arm)
    d_after = ((s.first_moment_mass + mu * amount * position) / m_after
               - (s.first_moment_fluid + beta * amount * position) / mf_after)
    scale = max(1e-9, float(np.max(np.abs(d_after))))
    if d_after[2] <= 1e-9 * scale or np.any(np.abs(d_after[:2]) > 1e-6 * scale):
        raise _no_solution(kind, box, max_amount, min_arm)
    position.setflags(write=False)
    box.setflags(write=False)
    return Ballast(kind=kind, amount=amount, mass_kg=mu * amount, displaced_mass_kg=beta * amount,
                   position_m=position, region_m=box, net_buoyancy_after_N=(mf_after - m_after) * s.gravity,
                   righting_arm_after_m=float(d_after[2]))


def _no_solution(kind: str, box: np.ndarray, max_amount: float | None, min_arm: float) -> UvmsInputError:
    what = "point mass" if kind == "mass" else "foam"
    limit = "" if max_amount is None else f" of at most {max_amount:.6g} {'kg' if kind == 'mass' else 'm^3'}"
    corners = " to ".join(f"({', '.join(f'{v:.4g}' for v in row)})" for row in box)
    return UvmsInputError(f"cannot float level: no {what}{limit} placed in the box {corners} m levels the vehicle "
                          f"with its centre of buoyancy at least {min_arm:.4g} m above its centre of mass; allow more "
                          f"ballast or a larger region", path="ballast")


def _statics_in(s: Statics, source: str, target: str) -> Statics:
    """:class:`Statics` with its vectors in convention ``target``'s vehicle axes."""
    return replace(s, **{name: convert_vectors(getattr(s, name), source, target) for name in
                         ("center_of_mass", "center_of_buoyancy", "first_moment_mass", "first_moment_fluid")})


def _box_in(box: np.ndarray, source: str, target: str) -> np.ndarray:
    """A (2, 3) box (lower, upper corner) in convention ``target``'s vehicle axes (its corners re-sorted)."""
    corners = convert_vectors(box, source, target)
    return np.array([corners.min(axis=0), corners.max(axis=0)])


def with_ballast(model, ballast: Ballast):
    """A copy of ``model`` with ``ballast`` added to the vehicle (body 0): its mass at ``position_m`` (a point, no
    rotational inertia of its own) and its displaced fluid centred there (:func:`uvms.model.loads.with_point_load`)."""
    from uvms.model.loads import with_point_load

    return with_point_load(model, 0, ballast.position_m, mass=ballast.mass_kg, fluid_mass=ballast.displaced_mass_kg)


# --------------------------------------------------------------------------------------------------- trim


@dataclass(frozen=True, eq=False)
class Trim:
    """Where the system rests with the arm at ``q``, and the ballast that levels it (:func:`trim`).

    Attributes:
        model_name, joint_names, q: the model, its joint order and the arm pose [rad or m].
        mass_kg, displaced_mass_kg: ``m`` and ``m_f`` [kg].
        net_buoyancy_N: ``(m_f - m) |a_g|`` [N], positive: positively buoyant (rises); negative: sinks.
        center_of_mass_m, center_of_buoyancy_m: (3,) ``r_G``, ``r_B`` [m] (vehicle frame, level).
        roll_rad, pitch_rad: the rest attitude (ZYX Euler, yaw 0), or ``None`` (see ``note``).
        note: why there is no rest attitude, or ``""``.
        level: whether it rests level already (roll and pitch within :data:`LEVEL_TOLERANCE`).
        ballast: the levelling :class:`Ballast` (``None`` when it is level already).
        effective_inertia: (6,) ``1 / (M^-1)_jj`` per axis of :data:`AXES` [kg or kg m^2].
        b_bounds: ``{axis: (b_min, b_max)}`` of the sliding-mode controller checked.
        warnings: one line per controlled axis whose effective inertia is outside its ``b`` bounds.
    """

    model_name: str
    joint_names: tuple[str, ...]
    q: np.ndarray
    mass_kg: float
    displaced_mass_kg: float
    net_buoyancy_N: float
    center_of_mass_m: np.ndarray
    center_of_buoyancy_m: np.ndarray
    roll_rad: float | None
    pitch_rad: float | None
    note: str
    level: bool
    ballast: Ballast | None
    effective_inertia: np.ndarray
    b_bounds: dict[str, tuple[float, float]]
    warnings: tuple[str, ...]
    frame: str = "ned"

    def table(self) -> str:
        """The trim as text lines (what ``uvms trim`` prints)."""
        def vec(v):
            return "(" + ", ".join(f"{x + 0.0:.6g}" for x in v) + ")"

        at = ", ".join(f"{n}={v:.6g}" for n, v in zip(self.joint_names, self.q)) or "no joints"
        sense = "rises" if self.net_buoyancy_N > 0 else "sinks" if self.net_buoyancy_N < 0 else "neutral"
        lines = [f"{self.model_name}: trim with the arm at {at} (vehicle frame {VEHICLE_AXES[self.frame]})",
                 f"  net vertical force: {self.net_buoyancy_N:+.6g} N ({sense}; mass {self.mass_kg:.6g} kg, "
                 f"displaced {self.displaced_mass_kg:.6g} kg)",
                 f"  centre of mass:     {vec(self.center_of_mass_m)} m",
                 "  centre of buoyancy: " + (vec(self.center_of_buoyancy_m) + " m"
                                             if np.all(np.isfinite(self.center_of_buoyancy_m)) else "none")]
        if self.roll_rad is None:
            lines.append(f"  rests at:           no stable attitude ({self.note})")
        else:
            lines.append(f"  rests at:           roll {math.degrees(self.roll_rad) + 0.0:.4g} deg, pitch "
                         f"{math.degrees(self.pitch_rad) + 0.0:.4g} deg (ZYX Euler, yaw 0)")
        b = self.ballast
        if b is None:
            lines.append("  level already: no ballast needed")
        else:
            what = f"{b.amount:.4g} kg point mass" if b.kind == "mass" else \
                f"{b.amount:.4g} m^3 of foam ({b.mass_kg:.4g} kg, lifting {(b.displaced_mass_kg - b.mass_kg):.4g} kg)"
            lines.append(f"  to level it:        {what} at {vec(b.position_m)} m")
            lines.append(f"  then:               net vertical force {b.net_buoyancy_after_N:+.6g} N, centre of "
                         f"buoyancy {b.righting_arm_after_m:.4g} m above the centre of mass")
        lines.append("  effective mass/inertia: " + ", ".join(
            f"{a} {v:.4g} {u}" for a, v, u in zip(AXES, self.effective_inertia, INERTIA_UNITS)))
        lines.extend(f"warning: {w}" for w in self.warnings)
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-able values; units in the key names, ``null`` for none."""
        def finite_or_none(v):
            return [float(x) if math.isfinite(x) else None for x in v]

        return {"model": self.model_name, "frame": self.frame,
                "q": dict(zip(self.joint_names, (float(x) for x in self.q))),
                "total_mass_kg": self.mass_kg, "displaced_mass_kg": self.displaced_mass_kg,
                "net_buoyancy_N": self.net_buoyancy_N,
                "center_of_mass_m": finite_or_none(self.center_of_mass_m),
                "center_of_buoyancy_m": finite_or_none(self.center_of_buoyancy_m),
                "rest": None if self.roll_rad is None else {"roll_rad": self.roll_rad, "pitch_rad": self.pitch_rad},
                "note": self.note, "level": self.level,
                "ballast": None if self.ballast is None else self.ballast.to_dict(),
                "effective_inertia_kg_or_kgm2": dict(zip(AXES, (float(x) for x in self.effective_inertia))),
                "b_bounds_kg_or_kgm2": {a: list(b) for a, b in self.b_bounds.items()},
                "warnings": list(self.warnings)}


LEVEL_TOLERANCE = math.radians(0.01)
"""Roll and pitch within this [rad] (0.01 deg) count as level: no ballast is computed."""


def trim(model, q=None, *, ballast: str = "mass", region=None, max_amount: float | None = None,
         foam_density: float = 0.0, min_arm: float = MIN_ARM, controller=None) -> Trim:
    """The rest attitude of ``model`` with the arm at ``q`` and the ballast that levels it (module docstring).

    Args:
        model: a :class:`uvms.Model`.
        q: joint values (a list in ``model.joint_names`` order or a ``{name: value}`` mapping); default zeros.
        ballast: ``"mass"`` (a point mass, kg) or ``"foam"`` (buoyancy foam, m^3).
        region: (2, 3) box of allowed ballast positions (vehicle frame) [m]; default the vehicle's outline box.
        max_amount: the most ballast allowed (kg or m^3), ``None``: no limit.
        foam_density: the foam's density [kg/m^3] (``ballast="foam"``).
        min_arm: the least height of the centre of buoyancy above the centre of mass after levelling [m].
        controller: :class:`uvms.control.smc.SlidingModeParameters` whose ``b`` bounds are checked (default: the
            paper's).

    Raises:
        UvmsInputError: bad ``q``, ``region``, ``ballast`` or limits (every option is checked before anything is
            computed, also when the system rests level and needs no ballast: :func:`check_ballast_options`), or
            no ballast levels it (one line).
    """
    from uvms import checks

    checks.model(model)
    q = joint_values(model, q)
    check_ballast_options(model, ballast, region, max_amount, foam_density, min_arm)   # all of them, up front
    s = statics(model, q)
    roll, pitch, note = rest_attitude(model, s)
    level = roll is not None and abs(roll) <= LEVEL_TOLERANCE and abs(pitch) <= LEVEL_TOLERANCE
    found = None if level else level_ballast(model, s, kind=ballast, region=region, max_amount=max_amount,
                                             foam_density=foam_density, min_arm=min_arm)
    inertia = effective_inertia(model, q)
    bounds, warnings = b_bounds_check(inertia, controller)
    for arr in (q, s.center_of_mass, s.center_of_buoyancy, inertia):
        arr.setflags(write=False)
    return Trim(model_name=model.name, joint_names=tuple(model.joint_names), q=q, mass_kg=s.mass,
                displaced_mass_kg=s.fluid_mass, net_buoyancy_N=s.net_buoyancy, center_of_mass_m=s.center_of_mass,
                center_of_buoyancy_m=s.center_of_buoyancy, roll_rad=roll, pitch_rad=pitch, note=note, level=level,
                ballast=found, effective_inertia=inertia, b_bounds=bounds, warnings=warnings, frame=model.convention)


def trimmed_state(model, q=None, *, position=None, yaw: float = 0.0):
    """The :class:`~uvms.state.State` at rest at the attitude the system rests at with the arm at ``q``
    (:func:`rest_attitude`; yaw ``yaw`` [rad], ``position`` [m] default the origin): a scenario's trimmed start.

    Raises:
        UvmsInputError: there is no stable rest attitude (centres coincide, no buoyancy or gravity).
    """
    from uvms import checks
    from uvms.state import State

    checks.model(model)
    q = joint_values(model, q)
    roll, pitch, note = rest_attitude(model, statics(model, q))
    if roll is None:
        raise UvmsInputError(f"no stable rest attitude: {note}", path="trim")
    return State.from_euler(model, position=position, euler=[roll, pitch, checks.number(yaw, "yaw")], q=q)
