"""Hydrodynamic shapes posed on a body: buoyancy, added mass and quadratic drag of spheres, boxes, cylinders
and ellipsoids (prolate spheroids for torpedo hulls).

Conventions (``docs/conventions.md``): spatial vectors ``[angular; linear]`` in body axes about the body-frame
origin; drag uses the velocity relative to the fluid ``nu_r``. Each shape has its own frame, posed in the body
frame by ``rotation`` (shape-to-body: columns are the shape axes in body coordinates) and ``position`` (the
shape's centre in body coordinates). Every shape here is centred on its frame origin, so the centre of buoyancy
of a shape is its ``position``.

What each shape provides, and where the formula comes from:

* **Sphere** (radius ``a``): volume ``4/3 pi a^3``; added mass ``rho V / 2`` in translation and none in
  rotation (Lamb 1932; Newman 1977); drag ``-0.5 rho Cd pi a^2 |v| v`` at the centre.
* **Ellipsoid** (semi-axes ``a, b, c``; a prolate spheroid for torpedo hulls): volume ``4/3 pi a b c``; added
  mass from Lamb's inertia integrals ``alpha0, beta0, gamma0`` (Lamb 1918, 1932; Imlay 1961; Fossen 2021
  §8.4.2); drag by cross-flow strips along x (the paper's Eq. 6 generalised to an elliptic section) plus an
  axial term ``-0.5 rho Cd_ax pi b c u|u|``.
* **Cylinder** (radius ``r``, length ``L``, any axis): volume ``pi r^2 L``; added mass by strip theory,
  ``rho pi r^2`` per unit length normal to the axis (Patel 1989, as
  :func:`uvms.hydro.added_mass.cylinder_added_mass`), along the axis a documented approximation; drag by
  Eq. 6 along the axis (:func:`uvms.hydro.drag.link_drag_force`) plus an axial term
  ``-0.5 rho Cd_ax pi r^2 u|u|``.
* **Box** (edges ``lx, ly, lz``): volume ``lx ly lz``; added mass approximated by Lamb's ellipsoid
  coefficients for the box's aspect ratios applied to the box's own displaced mass and fluid inertia; drag
  face by face (Eqs. 3-4 generalised), the exact integral of ``|v_n| v_n`` over the three projected faces.

Several shapes on one body add up. For buoyancy (volumes and volume-weighted centre) and drag (forces of
independent strips) the sum is exact within the models; for added mass it is an approximation that ignores
the interaction between the shapes' flows (each shape is treated as if alone in the fluid).

Drag at run time: :func:`drag_table` turns a list of shapes into one flat ``(n, DRAG_ROW)`` array (pose,
dimensions and the pre-multiplied coefficients ``0.5 rho Cd (area)``), and the compiled
:func:`shapes_drag_force` sums the drag of every row into one spatial force about the body origin, with scalar
loops and no allocation (its scratch is the ``work`` array of :func:`drag_workspace`).

References: H. Lamb, *Hydrodynamics*, 6th ed., 1932 (the sphere and the ellipsoid moving through a liquid);
H. Lamb, "The inertia-coefficients of an ellipsoid moving in fluid", ARC R&M 623, 1918 (``k1, k2, k'``
formulas and table); F. H. Imlay, "The complete expressions for added mass of a rigid body moving in an
ideal fluid", DTMB report 1528, 1961; J. N. Newman, *Marine Hydrodynamics*, 1977; T. I. Fossen,
*Handbook of Marine Craft Hydrodynamics and Motion Control*, 2nd ed., 2021; B. C. Carlson, "Numerical
computation of real or complex elliptic integrals", Numer. Algorithms 10, 1995 (``R_D``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence, Union

import numpy as np

from uvms.hydro.added_mass import cylinder_added_mass
from uvms.hydro.drag import link_drag_force
from uvms.jit import block, kernel
from uvms.spatial import plucker_from_pose

# ----------------------------------------------------------------------------------------------------------
# Shapes
# ----------------------------------------------------------------------------------------------------------


def _pose(rotation, position) -> tuple[np.ndarray, np.ndarray]:
    R = np.array(rotation, dtype=float).reshape(3, 3)
    p = np.array(position, dtype=float).reshape(3)
    if not (np.all(np.isfinite(R)) and np.all(np.isfinite(p))):
        raise ValueError("shape pose must be finite")
    if not np.allclose(R.T @ R, np.eye(3), atol=1e-9) or np.linalg.det(R) < 0:
        raise ValueError("shape rotation must be a proper rotation matrix (R^T R = I, det R = +1)")
    return R, p


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be positive and finite, got {value}")
    return value


def _non_negative(name: str, value: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and value >= 0):
        raise ValueError(f"{name} must be non-negative and finite, got {value}")
    return value


@dataclass(frozen=True, eq=False)
class Sphere:
    """A sphere of ``radius`` [m] centred at ``position`` (body frame).

    Attributes:
        radius: ``a`` [m].
        drag_coefficient: ``Cd`` on the frontal area ``pi a^2`` (0: no drag).
        rotation, position: pose of the shape frame in the body frame (a sphere needs only the position).
    """

    radius: float
    drag_coefficient: float = 0.0
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    position: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", _positive("Sphere.radius", self.radius))
        object.__setattr__(self, "drag_coefficient", _non_negative("Sphere.drag_coefficient",
                                                                   self.drag_coefficient))
        R, p = _pose(self.rotation, self.position)
        object.__setattr__(self, "rotation", R)
        object.__setattr__(self, "position", p)


@dataclass(frozen=True, eq=False)
class Box:
    """A rectangular box with edges ``size = (lx, ly, lz)`` [m] along its frame axes, centred at ``position``.

    Attributes:
        size: edge lengths along the shape x, y, z axes [m].
        drag_coefficients: ``Cd`` per face family (x, y, z), each on its projected face area
            (``ly lz``, ``lx lz``, ``lx ly``), as the paper's Eq. 3 (0: no drag).
        rotation, position: pose of the shape frame in the body frame.
    """

    size: Sequence[float]
    drag_coefficients: Sequence[float] = (0.0, 0.0, 0.0)
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    position: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        size = tuple(_positive(f"Box.size[{i}]", s) for i, s in enumerate(np.reshape(self.size, 3)))
        cd = tuple(_non_negative(f"Box.drag_coefficients[{i}]", c)
                   for i, c in enumerate(np.reshape(self.drag_coefficients, 3)))
        object.__setattr__(self, "size", size)
        object.__setattr__(self, "drag_coefficients", cd)
        R, p = _pose(self.rotation, self.position)
        object.__setattr__(self, "rotation", R)
        object.__setattr__(self, "position", p)


@dataclass(frozen=True, eq=False)
class Cylinder:
    """A solid circular cylinder of ``radius`` and ``length`` along its frame x axis, centred at ``position``.

    Use :func:`rotation_from_axis` to put the axis along any body direction.

    Attributes:
        radius, length: ``r``, ``L`` [m].
        drag_coefficient: cross-flow ``Cd`` on the projected area ``2 r`` per unit length (paper Eq. 6).
        axial_drag_coefficient: ``Cd`` of end-on flow on the end area ``pi r^2`` (0 by default, as Eq. 6).
        axial_added_mass: ``"spheroid"`` (default) approximates the added mass along the axis by that of the
            spheroid of the same length and diameter; ``"none"`` keeps pure strip theory (as the paper's links).
        rotation, position: pose of the shape frame in the body frame.
    """

    radius: float
    length: float
    drag_coefficient: float = 0.0
    axial_drag_coefficient: float = 0.0
    axial_added_mass: str = "spheroid"
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    position: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", _positive("Cylinder.radius", self.radius))
        object.__setattr__(self, "length", _positive("Cylinder.length", self.length))
        object.__setattr__(self, "drag_coefficient", _non_negative("Cylinder.drag_coefficient",
                                                                   self.drag_coefficient))
        object.__setattr__(self, "axial_drag_coefficient",
                           _non_negative("Cylinder.axial_drag_coefficient", self.axial_drag_coefficient))
        if self.axial_added_mass not in ("spheroid", "none"):
            raise ValueError(f"Cylinder.axial_added_mass must be 'spheroid' or 'none', got {self.axial_added_mass!r}")
        R, p = _pose(self.rotation, self.position)
        object.__setattr__(self, "rotation", R)
        object.__setattr__(self, "position", p)


@dataclass(frozen=True, eq=False)
class Ellipsoid:
    """An ellipsoid with semi-axes ``(a, b, c)`` [m] along its frame x, y, z axes, centred at ``position``.

    A prolate spheroid (torpedo hull) is ``a > b = c`` (see :func:`spheroid`).

    Attributes:
        semi_axes: ``(a, b, c)`` [m].
        drag_coefficient: cross-flow ``Cd`` of the strips along x, on the local projected width.
        axial_drag_coefficient: ``Cd`` of flow along x on the frontal area ``pi b c``.
        rotation, position: pose of the shape frame in the body frame.
    """

    semi_axes: Sequence[float]
    drag_coefficient: float = 0.0
    axial_drag_coefficient: float = 0.0
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))
    position: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        axes = tuple(_positive(f"Ellipsoid.semi_axes[{i}]", s)
                     for i, s in enumerate(np.reshape(self.semi_axes, 3)))
        object.__setattr__(self, "semi_axes", axes)
        object.__setattr__(self, "drag_coefficient", _non_negative("Ellipsoid.drag_coefficient",
                                                                   self.drag_coefficient))
        object.__setattr__(self, "axial_drag_coefficient",
                           _non_negative("Ellipsoid.axial_drag_coefficient", self.axial_drag_coefficient))
        R, p = _pose(self.rotation, self.position)
        object.__setattr__(self, "rotation", R)
        object.__setattr__(self, "position", p)


Shape = Union[Sphere, Box, Cylinder, Ellipsoid]


def spheroid(length: float, diameter: float, **kwargs) -> Ellipsoid:
    """A spheroid of ``length`` along its frame x axis and ``diameter`` across (``a = L/2``, ``b = c = D/2``)."""
    return Ellipsoid((0.5 * length, 0.5 * diameter, 0.5 * diameter), **kwargs)


def rotation_from_axis(axis) -> np.ndarray:
    """A rotation (shape-to-body) whose first column is the unit vector along ``axis`` (body coordinates).

    For axisymmetric shapes (cylinder, spheroid) only this column matters; the other two complete a
    right-handed frame with its y axis horizontal (in the body x-y plane): ``+x`` gives the identity,
    ``+y`` gives ``Rz(+90 deg)``, ``+z`` gives ``Ry(-90 deg)``.
    """
    e = np.asarray(axis, dtype=float).reshape(3)
    n = np.linalg.norm(e)
    if not (math.isfinite(n) and n > 0):
        raise ValueError(f"axis must be a non-zero finite vector, got {e}")
    e = e / n
    y = np.cross([0.0, 0.0, 1.0], e)              # horizontal, as the body y axis is for e = x
    if np.linalg.norm(y) < 1e-9:                   # e along +/- z: keep the body y axis
        y = np.array([0.0, 1.0, 0.0])
    y /= np.linalg.norm(y)
    z = np.cross(e, y)
    return np.column_stack([e, y, z])


# ----------------------------------------------------------------------------------------------------------
# Buoyancy: volume and centre
# ----------------------------------------------------------------------------------------------------------


def volume(shape: Shape) -> float:
    """Displaced volume [m^3] of a fully submerged shape."""
    if isinstance(shape, Sphere):
        return 4.0 / 3.0 * math.pi * shape.radius**3
    if isinstance(shape, Box):
        lx, ly, lz = shape.size
        return lx * ly * lz
    if isinstance(shape, Cylinder):
        return math.pi * shape.radius**2 * shape.length
    if isinstance(shape, Ellipsoid):
        a, b, c = shape.semi_axes
        return 4.0 / 3.0 * math.pi * a * b * c
    raise TypeError(f"not a shape: {type(shape).__name__}")


def centre(shape: Shape) -> np.ndarray:
    """Centre of buoyancy [m] (the centroid: every shape here is centred on its frame), body coordinates."""
    volume(shape)  # type check
    return shape.position.copy()


def buoyancy(shapes: Sequence[Shape]) -> tuple[float, np.ndarray]:
    """Total displaced volume [m^3] and its centre (volume-weighted centroid) [m] of several shapes.

    The buoyancy force is then ``rho g V`` at that centre (:func:`uvms.hydro.buoyancy.buoyancy_force` with
    ``fluid_mass = rho V``). Overlapping shapes are counted twice: give disjoint shapes.
    """
    if len(shapes) == 0:
        return 0.0, np.zeros(3)
    vols = np.array([volume(s) for s in shapes])
    cents = np.array([s.position for s in shapes])
    total = float(vols.sum())
    return total, (vols[:, None] * cents).sum(axis=0) / total


# ----------------------------------------------------------------------------------------------------------
# Added mass
# ----------------------------------------------------------------------------------------------------------


def transform_added_mass(M6: np.ndarray, R: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Move a 6x6 ``[angular; linear]`` added-mass matrix from a shape frame to the body frame.

    ``M6`` is about the shape-frame origin in shape axes; the shape frame has orientation ``R`` (shape-to-body)
    and origin ``p`` in the body frame. The shape frame's velocity is ``nu_s = X nu_b`` with
    ``X = plucker(R^T, p)`` (:func:`uvms.spatial.plucker_from_pose`), so equal kinetic energy
    ``0.5 nu_s^T M6 nu_s = 0.5 nu_b^T (X^T M6 X) nu_b`` gives the congruence ``M_body = X^T M6 X``
    (Featherstone 2008, ch. 2: the same congruence as for a rigid-body inertia).
    """
    M6 = np.asarray(M6, dtype=float)
    if M6.shape != (6, 6):
        raise ValueError(f"added-mass matrix must be 6x6, got shape {M6.shape}")
    X = plucker_from_pose(np.asarray(R, dtype=float), np.asarray(p, dtype=float))
    return X.T @ M6 @ X


def ellipsoid_inertia_integrals(a: float, b: float, c: float) -> tuple[float, float, float]:
    """Lamb's ``(alpha0, beta0, gamma0)`` of an ellipsoid with semi-axes ``a, b, c`` (Lamb 1932; Lamb 1918).

    ``alpha0 = a b c int_0^inf dl / ((a^2 + l) Delta)``, ``Delta = sqrt((a^2+l)(b^2+l)(c^2+l))``, evaluated as
    ``(2/3) a b c R_D(b^2, c^2, a^2)`` with Carlson's symmetric integral ``R_D`` (``scipy.special.elliprd``);
    ``beta0``, ``gamma0`` cyclically. They sum to 2; a sphere has 2/3 each.
    """
    from scipy.special import elliprd

    a2, b2, c2 = a * a, b * b, c * c
    k = 2.0 / 3.0 * a * b * c
    return (float(k * elliprd(b2, c2, a2)), float(k * elliprd(c2, a2, b2)), float(k * elliprd(a2, b2, c2)))


def ellipsoid_added_mass_coefficients(a: float, b: float, c: float) -> tuple[np.ndarray, np.ndarray]:
    """Lamb's inertia coefficients of an ellipsoid: ``(k_lin, k_rot)``, each (3,) for the x, y, z axes.

    Translation along axis i (Lamb 1932): added mass ``k_i rho V`` with ``k_i = A_i / (2 - A_i)``
    (``A = alpha0, beta0, gamma0``). Rotation about axis i, with (j, k) the other two axes (Lamb 1932)::

        I'_i = (rho V / 5) (s_j^2 - s_k^2)^2 (A_k - A_j) / (2 (s_j^2 - s_k^2) + (s_j^2 + s_k^2)(A_j - A_k))

    returned as the ratio ``k'_i = I'_i / I_i`` to the displaced fluid's moment of inertia
    ``I_i = rho V (s_j^2 + s_k^2) / 5``. For a prolate spheroid these are Lamb's ``k1, k2, k'``
    (:func:`lamb_k_factors`); equal axes give 0 (a sphere or a spheroid about its axis has none).
    """
    s = np.array([a, b, c], dtype=float)
    A = np.array(ellipsoid_inertia_integrals(a, b, c))
    k_lin = A / (2.0 - A)
    k_rot = np.zeros(3)
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        d = s[j] ** 2 - s[k] ** 2
        denom = 2.0 * d + (s[j] ** 2 + s[k] ** 2) * (A[j] - A[k])
        if d == 0.0 or denom == 0.0:
            continue
        I_added = d * d * (A[k] - A[j]) / denom          # over rho V / 5
        k_rot[i] = I_added / (s[j] ** 2 + s[k] ** 2)
    return k_lin, k_rot


def lamb_k_factors(a: float, b: float) -> tuple[float, float, float]:
    """Lamb's ``(k1, k2, k')`` of a prolate spheroid, semi-axes ``a > b`` (closed form, Lamb 1918).

    With ``e = sqrt(1 - (b/a)^2)``::

        alpha0 = 2 (1 - e^2) / e^3 (0.5 ln((1 + e)/(1 - e)) - e)
        beta0  = 1 / e^2 - (1 - e^2) / (2 e^3) ln((1 + e)/(1 - e))
        k1 = alpha0 / (2 - alpha0)      (along the axis)
        k2 = beta0 / (2 - beta0)        (across)
        k' = e^4 (beta0 - alpha0) / ((2 - e^2) (2 e^2 - (2 - e^2)(beta0 - alpha0)))   (rotation across)

    the form used by Fossen (2021 §8.4.2) and Imlay (1961). Independent of
    :func:`ellipsoid_added_mass_coefficients` (elliptic integrals), which it checks in the tests.
    """
    if not (a > b > 0):
        raise ValueError(f"a prolate spheroid needs a > b > 0, got a = {a}, b = {b}")
    e = math.sqrt(1.0 - (b / a) ** 2)
    log = math.log((1.0 + e) / (1.0 - e))
    alpha0 = 2.0 * (1.0 - e * e) / e**3 * (0.5 * log - e)
    beta0 = 1.0 / e**2 - (1.0 - e * e) / (2.0 * e**3) * log
    k1 = alpha0 / (2.0 - alpha0)
    k2 = beta0 / (2.0 - beta0)
    kp = e**4 * (beta0 - alpha0) / ((2.0 - e * e) * (2.0 * e * e - (2.0 - e * e) * (beta0 - alpha0)))
    return k1, k2, kp


def _diagonal_added_mass(m_lin, I_rot) -> np.ndarray:
    M = np.zeros((6, 6))
    M[0, 0], M[1, 1], M[2, 2] = I_rot
    M[3, 3], M[4, 4], M[5, 5] = m_lin
    return M


def local_added_mass(shape: Shape, density: float) -> np.ndarray:
    """6x6 ``[angular; linear]`` added mass about the shape's centre, in shape axes (potential flow).

    * Sphere: ``rho V / 2`` in translation, no rotational part (Lamb 1932).
    * Ellipsoid: ``k_i rho V`` in translation and ``k'_i I_i`` in rotation
      (:func:`ellipsoid_added_mass_coefficients`); diagonal about the centre (Lamb 1932).
    * Cylinder: strip theory, ``rho pi r^2`` per unit length normal to the axis
      (:func:`uvms.hydro.added_mass.cylinder_added_mass`, moved from the end to the centre, which gives
      ``rho pi r^2 L`` across and ``rho pi r^2 L^3 / 12`` in pitch/yaw and no coupling); no roll added inertia
      (a circular section moves no fluid in rotation about its axis); end effects neglected. Along the axis
      strip theory gives nothing; with ``axial_added_mass = "spheroid"`` (default) the axial added mass is
      approximated by that of the spheroid of the same length and diameter, ``k1(L/D) rho (pi/6) L D^2``.
    * Box: no closed form exists. Approximation used: the ellipsoid coefficients ``k_i, k'_i`` for the box's
      aspect ratios (semi-axes ``lx/2, ly/2, lz/2``), applied to the box's own displaced mass ``rho lx ly lz``
      and fluid moment of inertia ``rho V (l_j^2 + l_k^2) / 12``. A cube gets ``rho V / 2`` in translation
      (the sphere's coefficient) and none in rotation: an underestimate for sharp-edged bodies; give the
      vehicle's identified added mass instead when one is published.
    """
    rho = _non_negative("density", density)
    V = volume(shape)
    if isinstance(shape, Sphere):
        return _diagonal_added_mass([0.5 * rho * V] * 3, [0.0] * 3)
    if isinstance(shape, Ellipsoid):
        a, b, c = shape.semi_axes
        k_lin, k_rot = ellipsoid_added_mass_coefficients(a, b, c)
        I_fluid = rho * V / 5.0 * np.array([b * b + c * c, c * c + a * a, a * a + b * b])
        return _diagonal_added_mass(k_lin * rho * V, k_rot * I_fluid)
    if isinstance(shape, Box):
        lx, ly, lz = shape.size
        k_lin, k_rot = ellipsoid_added_mass_coefficients(0.5 * lx, 0.5 * ly, 0.5 * lz)
        I_fluid = rho * V / 12.0 * np.array([ly * ly + lz * lz, lz * lz + lx * lx, lx * lx + ly * ly])
        return _diagonal_added_mass(k_lin * rho * V, k_rot * I_fluid)
    if isinstance(shape, Cylinder):
        r, L = shape.radius, shape.length
        M_end = cylinder_added_mass(rho, r, L)                 # about the end at x = 0, axis along +x
        M = transform_added_mass(M_end, np.eye(3), np.array([-0.5 * L, 0.0, 0.0]))
        if shape.axial_added_mass == "spheroid":
            k_lin, _ = ellipsoid_added_mass_coefficients(0.5 * L, r, r)
            M[3, 3] += k_lin[0] * rho * (4.0 / 3.0 * math.pi * 0.5 * L * r * r)
        return M
    raise TypeError(f"not a shape: {type(shape).__name__}")


def added_mass(shape: Shape, density: float) -> np.ndarray:
    """6x6 ``[angular; linear]`` added mass of a posed shape about the body origin, in body axes."""
    return transform_added_mass(local_added_mass(shape, density), shape.rotation, shape.position)


def total_added_mass(shapes: Sequence[Shape], density: float) -> np.ndarray:
    """Sum of the shapes' added masses (body axes, body origin): an approximation that ignores interaction."""
    M = np.zeros((6, 6))
    for s in shapes:
        M += added_mass(s, density)
    return M


# ----------------------------------------------------------------------------------------------------------
# Drag: one table row per shape, one compiled kernel for all of them
# ----------------------------------------------------------------------------------------------------------

KIND_SPHERE, KIND_BOX, KIND_CYLINDER, KIND_ELLIPSOID = 0, 1, 2, 3
#: Row layout of :func:`drag_table`: kind, rotation (row-major 3x3), position, dimensions, coefficients.
COL_KIND, COL_ROTATION, COL_POSITION, COL_DIMENSIONS, COL_COEFFICIENTS = 0, 1, 10, 13, 16
DRAG_ROW = 19
WORK_SIZE = 12

_GL4_X, _GL4_W = np.polynomial.legendre.leggauss(4)
_GL8_X, _GL8_W = np.polynomial.legendre.leggauss(8)


def drag_table(shapes: Sequence[Shape], density: float) -> np.ndarray:
    """The ``(n, DRAG_ROW)`` drag table of ``shapes`` for :func:`shapes_drag_force`.

    Per row: ``kind``; ``R`` row-major (shape-to-body); ``p``; dimensions; coefficients ``k``:

    =========== ====================== ======================================================================
    kind        dimensions             coefficients
    =========== ====================== ======================================================================
    sphere      ``a, 0, 0``            ``0.5 rho Cd pi a^2``, 0, 0
    box         ``lx/2, ly/2, lz/2``   ``0.5 rho Cd_x``, ``0.5 rho Cd_y``, ``0.5 rho Cd_z`` (per unit area)
    cylinder    ``r, L, 0``            ``0.5 rho Cd 2 r`` (per unit length), ``0.5 rho Cd_ax pi r^2``, 0
    ellipsoid   ``a, b, c``            ``0.5 rho Cd`` (per unit projected area), ``0.5 rho Cd_ax pi b c``, 0
    =========== ====================== ======================================================================
    """
    rho = _non_negative("density", density)
    table = np.zeros((len(shapes), DRAG_ROW))
    for i, s in enumerate(shapes):
        row = table[i]
        row[COL_ROTATION:COL_ROTATION + 9] = s.rotation.reshape(9)
        row[COL_POSITION:COL_POSITION + 3] = s.position
        if isinstance(s, Sphere):
            row[COL_KIND] = KIND_SPHERE
            row[COL_DIMENSIONS] = s.radius
            row[COL_COEFFICIENTS] = 0.5 * rho * s.drag_coefficient * math.pi * s.radius**2
        elif isinstance(s, Box):
            row[COL_KIND] = KIND_BOX
            row[COL_DIMENSIONS:COL_DIMENSIONS + 3] = 0.5 * np.array(s.size)
            row[COL_COEFFICIENTS:COL_COEFFICIENTS + 3] = 0.5 * rho * np.array(s.drag_coefficients)
        elif isinstance(s, Cylinder):
            row[COL_KIND] = KIND_CYLINDER
            row[COL_DIMENSIONS:COL_DIMENSIONS + 2] = (s.radius, s.length)
            row[COL_COEFFICIENTS] = 0.5 * rho * s.drag_coefficient * 2.0 * s.radius
            row[COL_COEFFICIENTS + 1] = 0.5 * rho * s.axial_drag_coefficient * math.pi * s.radius**2
        elif isinstance(s, Ellipsoid):
            a, b, c = s.semi_axes
            row[COL_KIND] = KIND_ELLIPSOID
            row[COL_DIMENSIONS:COL_DIMENSIONS + 3] = (a, b, c)
            row[COL_COEFFICIENTS] = 0.5 * rho * s.drag_coefficient
            row[COL_COEFFICIENTS + 1] = 0.5 * rho * s.axial_drag_coefficient * math.pi * b * c
        else:
            raise TypeError(f"not a shape: {type(s).__name__}")
    return table


def shape_drag_tables(shapes_per_body: Sequence[Sequence[Shape]]) -> np.ndarray:
    """``(nb, k, DRAG_ROW)`` drag tables (:func:`drag_table`) of the bodies' shapes **per unit fluid density**
    (the kernel model multiplies the coefficient columns by ``Model.density``, so a density override applies to
    them), padded with zero rows (the count of real rows is ``Model.shape_count``)."""
    k = max([len(s) for s in shapes_per_body] + [0])
    out = np.zeros((len(shapes_per_body), k, DRAG_ROW))
    for i, shapes in enumerate(shapes_per_body):
        if shapes:
            out[i, :len(shapes)] = drag_table(shapes, 1.0)
    return out


def drag_workspace() -> np.ndarray:
    """Scratch for :func:`shapes_drag_force` (allocate once per run)."""
    return np.zeros(WORK_SIZE)


@block
def _g(v):
    return v * abs(v)


@kernel
def rectangle_drag_integrals(c, alpha, beta, u0, u1, w0, w1):
    """``(I, I_u, I_w)`` = integrals over ``[u0,u1] x [w0,w1]`` of ``g``, ``u g``, ``w g``, ``g = v |v|``,
    ``v = c + alpha u + beta w`` (the normal velocity over a flat face, linear in the face coordinates).

    ``g`` is a polynomial of degree 2 on each side of the line ``v = 0``. The outer interval is split where
    that line meets the edges ``w = w0`` and ``w = w1``, the inner one where it crosses; on every piece the
    integrand is then a polynomial of degree <= 5, which 4-point Gauss-Legendre integrates exactly.
    """
    b0 = 1e300
    b1 = 1e300
    if alpha != 0.0:
        b0 = -(c + beta * w0) / alpha
        b1 = -(c + beta * w1) / alpha
        if b0 > b1:
            b0, b1 = b1, b0
    I = 0.0
    Iu = 0.0
    Iw = 0.0
    lo = u0
    for piece in range(3):
        if piece == 0:
            hi = b0 if u0 < b0 < u1 else (b1 if u0 < b1 < u1 else u1)
        elif piece == 1:
            hi = b1 if (lo < b1 < u1) else u1
        else:
            hi = u1
        if hi > lo:
            hu = 0.5 * (hi - lo)
            mu = 0.5 * (hi + lo)
            for gi in range(4):
                u = mu + hu * _GL4_X[gi]
                wu = hu * _GL4_W[gi]
                t = c + alpha * u
                split = 1e300
                if beta != 0.0:
                    split = -t / beta
                n_in = 2 if w0 < split < w1 else 1
                s_in = 0.0
                sw_in = 0.0
                for p in range(n_in):
                    a_ = w0
                    b_ = w1
                    if n_in == 2:
                        if p == 0:
                            b_ = split
                        else:
                            a_ = split
                    hw = 0.5 * (b_ - a_)
                    mw = 0.5 * (b_ + a_)
                    for gj in range(4):
                        w = mw + hw * _GL4_X[gj]
                        gv = _g(t + beta * w) * hw * _GL4_W[gj]
                        s_in += gv
                        sw_in += w * gv
                I += wu * s_in
                Iu += wu * u * s_in
                Iw += wu * sw_in
        lo = hi
        if lo >= u1:
            break
    return I, Iu, Iw


@kernel
def _ellipsoid_crossflow(a, b, c, k, vy0, dy, vz0, dz):
    """Cross-flow drag of strips along x of an ellipsoid, ``(F_y, F_z, M_y, M_z)`` about its centre.

    The section at ``s`` is an ellipse of semi-axes ``b sqrt(1 - s^2/a^2)``, ``c sqrt(1 - s^2/a^2)``; for a
    normal velocity ``v_n = (v_y, v_z)`` its width across the flow is ``2 sqrt(b^2 n_z^2 + c^2 n_y^2)``
    (``n = v_n / |v_n|``), so ``dF = -k sqrt(1 - s^2/a^2) 2 sqrt(c^2 v_y^2 + b^2 v_z^2) v_n ds`` with
    ``v_y = vy0 + dy s``, ``v_z = vz0 + dz s``, ``k = 0.5 rho Cd``; ``dM = [s, 0, 0] x dF``. Integrated with
    ``s = a sin(theta)`` (which removes the square-root end points) by 8-point Gauss-Legendre on each side
    of the smallest weighted speed, as :func:`uvms.hydro.drag.link_drag_force` does for Eq. 6.
    """
    qa = c * c * dy * dy + b * b * dz * dz
    th_split = 10.0
    if qa > 0.0:
        s_min = -(c * c * vy0 * dy + b * b * vz0 * dz) / qa
        if -a < s_min < a:
            th_split = math.asin(s_min / a)
    half_pi = 0.5 * math.pi
    n_pieces = 2 if -half_pi < th_split < half_pi else 1
    sy = sz = sys_ = szs = 0.0
    for piece in range(n_pieces):
        lo = -half_pi
        hi = half_pi
        if n_pieces == 2:
            if piece == 0:
                hi = th_split
            else:
                lo = th_split
        h = 0.5 * (hi - lo)
        m = 0.5 * (hi + lo)
        for gi in range(8):
            th = m + h * _GL8_X[gi]
            ct = math.cos(th)
            s = a * math.sin(th)
            wgt = h * _GL8_W[gi] * a * ct * ct          # ds = a cos(th) dth, sqrt(1 - s^2/a^2) = cos(th)
            vy = vy0 + dy * s
            vz = vz0 + dz * s
            q = 2.0 * math.sqrt(c * c * vy * vy + b * b * vz * vz)
            sy += wgt * q * vy
            sz += wgt * q * vz
            sys_ += wgt * s * q * vy
            szs += wgt * s * q * vz
    # dF = -k (...) v_n ds; dM = [s, 0, 0] x [0, dF_y, dF_z] = [0, -s dF_z, s dF_y]
    return -k * sy, -k * sz, k * szs, -k * sys_


@kernel
def shapes_drag_force(table, nu_r, out, work):
    """``out`` = the summed quadratic drag ``[moment; force]`` of every shape in ``table`` (body axes, about
    the body origin) at the body velocity ``nu_r`` relative to the fluid; ``work``: :func:`drag_workspace`.

    Each shape sees the velocity of its own frame, ``omega_s = R^T omega``, ``v_s = R^T (v + omega x p)``;
    its force ``[m_s; f_s]`` about its centre in shape axes goes back as ``f = R f_s``,
    ``m = R m_s + p x f``.

    * sphere: ``f_s = -k |v_s| v_s``.
    * box: for each axis ``j`` the projected face through the centre (edges along the other two axes ``k, l``,
      cyclic) has normal velocity ``v_n = v_j - omega_l u + omega_k w`` at face point ``u e_k + w e_l``;
      ``dF = -k_j v_n |v_n| e_j dA`` (Eq. 3 per face, each projected face once, as Eq. 4 counts each slice
      once), integrated exactly (:func:`rectangle_drag_integrals`). A cube spinning about an axis gets Eq. 4's
      ``rho Cd a^5 / 32 omega |omega|``.
    * cylinder: Eq. 6 (:func:`uvms.hydro.drag.link_drag_force`) from its end at ``x = -L/2``, plus
      ``-k_ax u |u|`` along the axis.
    * ellipsoid: cross-flow strips (``_ellipsoid_crossflow``) plus ``-k_ax u |u|`` along x.
    """
    for i in range(6):
        out[i] = 0.0
    for row in range(table.shape[0]):
        t = table[row]
        kind = int(t[COL_KIND])
        R00, R01, R02 = t[1], t[2], t[3]
        R10, R11, R12 = t[4], t[5], t[6]
        R20, R21, R22 = t[7], t[8], t[9]
        px, py, pz = t[10], t[11], t[12]
        w0, w1, w2 = nu_r[0], nu_r[1], nu_r[2]
        # velocity of the point p (body axes), then both vectors in shape axes (R^T)
        vpx = nu_r[3] + w1 * pz - w2 * py
        vpy = nu_r[4] + w2 * px - w0 * pz
        vpz = nu_r[5] + w0 * py - w1 * px
        ox = R00 * w0 + R10 * w1 + R20 * w2
        oy = R01 * w0 + R11 * w1 + R21 * w2
        oz = R02 * w0 + R12 * w1 + R22 * w2
        vx = R00 * vpx + R10 * vpy + R20 * vpz
        vy = R01 * vpx + R11 * vpy + R21 * vpz
        vz = R02 * vpx + R12 * vpy + R22 * vpz
        mx = my = mz = fx = fy = fz = 0.0
        if kind == KIND_SPHERE:
            k = t[COL_COEFFICIENTS]
            sp = math.sqrt(vx * vx + vy * vy + vz * vz)
            fx = -k * sp * vx
            fy = -k * sp * vy
            fz = -k * sp * vz
        elif kind == KIND_BOX:
            hx, hy, hz = t[13], t[14], t[15]
            # face normal x: coordinates (u, w) = (y, z), v_n = v_x - omega_z y + omega_y z
            kx = t[COL_COEFFICIENTS]
            if kx != 0.0:
                # face normal x: coordinates (u, w) = (y, z), v_n = v_x - omega_z y + omega_y z
                I, Iu, Iw = rectangle_drag_integrals(vx, -oz, oy, -hy, hy, -hz, hz)
                fx = -kx * I
                # r = (0, y, z), dF = (dFx, 0, 0): dM = (0, z dFx, -y dFx)
                my += -kx * Iw
                mz -= -kx * Iu
            ky = t[COL_COEFFICIENTS + 1]
            if ky != 0.0:
                # face normal y: coordinates (u, w) = (z, x), v_n = v_y - omega_x z + omega_z x
                I, Iu, Iw = rectangle_drag_integrals(vy, -ox, oz, -hz, hz, -hx, hx)
                fy = -ky * I
                # r = (x, 0, z), dF = (0, dFy, 0): dM = (-z dFy, 0, x dFy)
                mx -= -ky * Iu
                mz += -ky * Iw
            kz = t[COL_COEFFICIENTS + 2]
            if kz != 0.0:
                # face normal z: coordinates (u, w) = (x, y), v_n = v_z - omega_y x + omega_x y
                I, Iu, Iw = rectangle_drag_integrals(vz, -oy, ox, -hx, hx, -hy, hy)
                fz = -kz * I
                # r = (x, y, 0), dF = (0, 0, dFz): dM = (y dFz, -x dFz, 0)
                mx += -kz * Iw
                my -= -kz * Iu
        elif kind == KIND_CYLINDER:
            k = t[COL_COEFFICIENTS]
            L = t[14]
            if k != 0.0:
                nu_end = work[0:6]
                f_end = work[6:12]
                h = 0.5 * L
                # the end frame sits at (-L/2, 0, 0): v_end = v + omega x (-h e_x) = (vx, vy - oz h, vz + oy h)
                nu_end[0] = ox
                nu_end[1] = oy
                nu_end[2] = oz
                nu_end[3] = vx
                nu_end[4] = vy - oz * h
                nu_end[5] = vz + oy * h
                link_drag_force(k, L, nu_end, f_end)
                fy = f_end[4]
                fz = f_end[5]
                # moment about the centre: m_c = m_end + (end - centre) x f = m_end + (-h, 0, 0) x f
                mx = f_end[0]
                my = f_end[1] + h * fz
                mz = f_end[2] - h * fy
            ka = t[COL_COEFFICIENTS + 1]
            fx = -ka * vx * abs(vx)
        elif kind == KIND_ELLIPSOID:
            a, b, c = t[13], t[14], t[15]
            k = t[COL_COEFFICIENTS]
            if k != 0.0:
                fy, fz, my, mz = _ellipsoid_crossflow(a, b, c, k, vy, oz, vz, -oy)
            ka = t[COL_COEFFICIENTS + 1]
            fx = -ka * vx * abs(vx)
        # back to body axes: f = R f_s, m = R m_s + p x f
        Fx = R00 * fx + R01 * fy + R02 * fz
        Fy = R10 * fx + R11 * fy + R12 * fz
        Fz = R20 * fx + R21 * fy + R22 * fz
        out[0] += R00 * mx + R01 * my + R02 * mz + py * Fz - pz * Fy
        out[1] += R10 * mx + R11 * my + R12 * mz + pz * Fx - px * Fz
        out[2] += R20 * mx + R21 * my + R22 * mz + px * Fy - py * Fx
        out[3] += Fx
        out[4] += Fy
        out[5] += Fz
