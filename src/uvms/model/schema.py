"""Schema of a model YAML file (pydantic v2); ``models/paper.yaml`` is the annotated example, ``docs/models.md``
the reference. A model file either describes the robot itself (:class:`ModelSpec`: modified-DH rows of a serial
arm) or names a URDF and adds what URDF cannot hold (:class:`UrdfModelSpec`, ``models/paper_urdf.yaml``).

SI units throughout; spatial 6-vectors and 6x6 matrices are ``[angular; linear]`` (``docs/conventions.md``).
Every model is frozen and forbids unknown keys. Besides shapes and signs, the physics is checked here:
rotational inertia about the centre of mass must be symmetric positive semi-definite and satisfy the
triangle inequality on its principal moments, and every added-mass matrix (paper Eq. 2) must be symmetric
positive semi-definite. :func:`uvms.model.load.format_validation_error` turns a failure into one line.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

import numpy as np
from pydantic import (
    AfterValidator,
    BeforeValidator,
    Discriminator,
    Strict,
    Tag,
    ValidationInfo,
    field_validator,
    model_validator,
)

from uvms.schema_base import (  # noqa: F401  (the kit's names, re-exported for model code)
    ZERO3,
    ZERO6,
    Mat3,
    Mat6,
    Name,
    NonNegative,
    NonNegativeVec3,
    Number,
    Positive,
    Spec,
    Vec3,
    Vec6,
    fail,
    is_number,
    numbers,
    show,
)
from uvms.spatial import inertia_about_com

RELATIVE_TOLERANCE = 1e-9
"""Relative tolerance of the symmetry, semi-definiteness and triangle checks (the paper's links sit exactly
on the triangle-inequality boundary: diag(0, 0.0016, 0.0016) about the CoM)."""



FrameName = Literal["ned", "enu"]
"""A model's ``frame:`` key, :data:`uvms.frames.FRAMES` (ned: world z down, body FRD; enu: z up, FLU)."""


class EnvironmentSpec(Spec):
    """Fluid and gravity (paper appendix, "Environmental Parameters"); world frame of the model's ``frame``."""

    density: Positive = 1000.0                    # rho [kg/m^3]
    gravity: Vec3 | None = None                   # a_g [m/s^2]; default 9.81 down (frames.default_gravity)
    current: Vec3 = ZERO3                         # constant default current velocity [m/s]
    fluid_acceleration: Vec3 = ZERO3              # a_f [m/s^2] (Eq. 7)


class BuoyancySpec(Spec):
    """Displaced fluid (Eqs. 7-8): its mass ``m_f`` [kg] and centre of buoyancy ``b`` [m, body frame]."""

    mass: NonNegative
    center: Vec3


class _MatrixSpec(Spec):
    """A symmetric matrix given either as its ``diagonal`` or as a full ``matrix``, about a stated point."""

    diagonal: Any = None
    matrix: Any = None
    about: str

    @model_validator(mode="after")
    def _one_form(self) -> _MatrixSpec:
        if (self.diagonal is None) == (self.matrix is None):
            found = "both" if self.diagonal is not None else "neither"
            raise fail(f"expected exactly one of 'diagonal' or 'matrix', found {found}")
        return self

    @property
    def form(self) -> str:
        """``"diagonal"`` or ``"matrix"``: the key the values were given under."""
        return "diagonal" if self.diagonal is not None else "matrix"

    def value(self) -> np.ndarray:
        """The matrix as given (about the point ``about``)."""
        return np.diag(self.diagonal) if self.diagonal is not None else np.array(self.matrix, dtype=float)


class VehicleInertiaSpec(_MatrixSpec):
    """Vehicle rotational inertia [kg m^2], body axes, about its CoM or the body-frame origin."""

    diagonal: Vec3 | None = None
    matrix: Mat3 | None = None
    about: Literal["com", "origin"]


class LinkInertiaSpec(_MatrixSpec):
    """Link rotational inertia [kg m^2], link axes, about its CoM or the joint (the link-frame origin)."""

    diagonal: Vec3 | None = None
    matrix: Mat3 | None = None
    about: Literal["com", "joint"]


def _symmetric_psd(A: np.ndarray, subpath: str, what: str) -> np.ndarray:
    """Check ``A`` symmetric positive semi-definite (relative tolerance); return its eigenvalues, ascending."""
    tol = RELATIVE_TOLERANCE * max(float(np.abs(A).max()), float(abs(np.trace(A))), 1e-300)
    i, j = np.unravel_index(int(np.argmax(np.abs(A - A.T))), A.shape)
    if abs(A[i, j] - A[j, i]) > tol:
        raise fail(f"expected a symmetric {what}, found [{i}][{j}] = {A[i, j]:.6g} but [{j}][{i}] = {A[j, i]:.6g}",
                   subpath)
    eig = np.linalg.eigvalsh(0.5 * (A + A.T))
    if eig[0] < -tol:
        raise fail(f"expected a positive semi-definite {what}, found eigenvalues "
                   f"[{', '.join(f'{e:.6g}' for e in eig)}]", subpath)
    return eig


class _AddedMassSpec(_MatrixSpec):
    """Added mass ``I_A`` (Eq. 2), 6x6 ``[angular; linear]`` in body axes [kg, kg m, kg m^2]."""

    diagonal: Vec6 | None = None
    matrix: Mat6 | None = None

    @model_validator(mode="after")
    def _physical(self) -> _AddedMassSpec:
        _symmetric_psd(self.value(), self.form, "added-mass matrix")
        return self


class VehicleAddedMassSpec(_AddedMassSpec):
    """Vehicle added mass, about its CoM or the body-frame origin."""

    about: Literal["origin", "com"]


class LinkAddedMassSpec(_AddedMassSpec):
    """Link added mass, about the joint (link-frame origin) or the CoM."""

    about: Literal["joint", "com"]


def _added_mass_kind(value: Any) -> str:
    return "mapping" if isinstance(value, dict) else "string"


def _from_geometry(value: Any) -> Any:
    if value != "from_geometry":
        raise fail("expected 'from_geometry' or a mapping with 'diagonal' or 'matrix' and 'about', "
                   f"found {show(value)}")
    return value


SHAPE_TYPES = ("sphere", "box", "cylinder", "ellipsoid", "from_collision")
UNION_TAGS = ("string", "mapping", *(f"shape:{t}" for t in SHAPE_TYPES), "shape:unknown")
"""Tags of tagged unions; :func:`uvms.model.load.format_validation_error` leaves them out of field paths."""

LinkAddedMass = Annotated[
    Annotated[Literal["from_geometry"], BeforeValidator(_from_geometry), Tag("string")]
    | Annotated[LinkAddedMassSpec, Tag("mapping")],
    Discriminator(_added_mass_kind),
]


def inertia_com(mass: float, com: tuple[float, float, float], inertia: _MatrixSpec) -> np.ndarray:
    """Rotational inertia about the CoM [kg m^2] (parallel-axis shift when given about the origin/joint)."""
    I = inertia.value()
    return I if inertia.about == "com" else inertia_about_com(mass, np.array(com), I)


def check_rotational_inertia(I_com: np.ndarray, subpath: str = "") -> None:
    """Symmetric PSD and the triangle inequality ``I1 + I2 >= I3`` on the principal moments about the CoM."""
    moments = _symmetric_psd(I_com, subpath, "rotational inertia about the centre of mass")
    tol = RELATIVE_TOLERANCE * max(float(np.sum(np.abs(moments))), 1e-300)
    if moments[0] + moments[1] < moments[2] - tol:
        raise fail("expected principal moments about the centre of mass with I1 + I2 >= I3 (triangle "
                   f"inequality), found [{', '.join(f'{m:.6g}' for m in moments)}]", subpath)


class _BodySpec(Spec):
    """Mass properties shared by the vehicle and the links."""

    mass: Positive                                # [kg]
    com: Vec3                                     # centre of mass, body frame [m]

    @field_validator("inertia", check_fields=False)
    @classmethod
    def _physical_inertia(cls, inertia: _MatrixSpec, info: ValidationInfo) -> _MatrixSpec:
        if "mass" in info.data and "com" in info.data:  # otherwise their own error is reported
            check_rotational_inertia(inertia_com(info.data["mass"], info.data["com"], inertia), inertia.form)
        return inertia


class RotationalDragSpec(Spec):
    """Strip-integrated rotational drag of a cube of side ``a`` (Eq. 4): ``M_j = -(rho Cd a^5/32) w_j |w_j|``."""

    side: NonNegative                             # a [m]
    coefficient: NonNegative                      # Cd [-]


class VehicleDragSpec(Spec):
    """Vehicle quadratic drag (Eqs. 3-5)."""

    area: NonNegativeVec3                         # A_j per body axis [m^2]
    coefficient: NonNegativeVec3                  # Cd_j per body axis [-]
    rotational: RotationalDragSpec


def _six_or_matrix(value: Any) -> Any:
    """6 values (a diagonal) or a 6x6 matrix, as a 6x6 tuple of rows."""
    if isinstance(value, (list, tuple)) and len(value) == 6 and all(is_number(x) for x in value):
        return tuple(tuple(float(value[i]) if i == j else 0.0 for j in range(6)) for i in range(6))
    if isinstance(value, (list, tuple)) and len(value) == 6 and all(
            isinstance(row, (list, tuple)) and len(row) == 6 and all(is_number(x) for x in row) for row in value):
        return tuple(tuple(float(x) for x in row) for row in value)
    raise fail(f"expected 6 finite numbers (a diagonal) or a 6x6 matrix, found {show(value)}")


SixOrMatrix = Annotated[tuple[tuple[float, ...], ...], BeforeValidator(_six_or_matrix)]


class FossenDampingSpec(Spec):
    """Fossen's linear and quadratic damping of a body (Fossen 2021, hydrodynamic damping):
    ``f = -(D_l + D_q diag|nu_p|) nu_p`` with ``nu_p`` the velocity relative to the fluid of the point ``about``.

    Either ``coefficients`` (SNAME names such as ``X_u``, ``X_u|u|``, ``N_r``; :mod:`uvms.hydro.fossen`), read
    with ``convention`` (``derivative``: the printed value is the derivative, dissipative values negative;
    ``magnitude``: the value is the matrix entry), or ``linear`` / ``quadratic`` given as matrix entries in
    uvms's ``[angular; linear]`` order (6 diagonal values or a 6x6 matrix). Units: linear ``[N s/m]``,
    ``[N m s/rad]`` (and mixed ``[N s]``, ``[N m s/m]``); quadratic ``[N s^2/m^2]``, ``[N m s^2/rad^2]``.
    The symmetric part of each matrix must be positive semi-definite (dissipative).
    """

    about: Vec3 = ZERO3                           # point the coefficients hold about, body frame [m]
    convention: Literal["derivative", "magnitude"] = "derivative"
    coefficients: dict[Name, Number] | None = None
    linear: SixOrMatrix | None = None
    quadratic: SixOrMatrix | None = None

    @model_validator(mode="after")
    def _physical(self) -> FossenDampingSpec:
        if self.coefficients is not None and (self.linear is not None or self.quadratic is not None):
            raise fail("expected either 'coefficients' (SNAME names) or 'linear'/'quadratic' (matrices), "
                       "found both")
        if self.coefficients is None and self.linear is None and self.quadratic is None:
            raise fail("expected 'coefficients' or 'linear'/'quadratic', found none")
        D_l, D_q = self.matrices()
        for name, D in (("linear", D_l), ("quadratic", D_q)):
            sub = "coefficients" if self.coefficients is not None else name
            eig = np.linalg.eigvalsh(0.5 * (D + D.T))
            tol = RELATIVE_TOLERANCE * max(float(np.abs(D).max()), 1e-300)
            if eig[0] < -tol:
                raise fail(f"expected a dissipative {name} damping matrix (symmetric part positive "
                           f"semi-definite), found eigenvalues [{', '.join(f'{e:.6g}' for e in eig)}]"
                           + (" (SNAME derivatives of a dissipative body are negative; or give "
                              "convention: magnitude)" if self.coefficients is not None else ""), sub)
        return self

    def matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """``(D_l, D_q)``, 6x6 ``[angular; linear]`` matrix entries."""
        from uvms.hydro.fossen import damping_matrices, sname_index

        if self.coefficients is not None:
            for name in self.coefficients:
                try:
                    sname_index(name)
                except ValueError as exc:
                    raise fail(str(exc), f"coefficients.{name}") from None
            try:
                return damping_matrices(self.coefficients, convention=self.convention)
            except Exception as exc:  # a duplicate name (X_u|u| and X_|u|u)
                raise fail(getattr(exc, "message", str(exc)), "coefficients") from None
        zero = np.zeros((6, 6))
        return (np.array(self.linear) if self.linear is not None else zero,
                np.array(self.quadratic) if self.quadratic is not None else zero)


PositiveVec3 = Annotated[tuple[float, float, float], numbers(3, minimum=0.0)]


class _ShapeSpec(Spec):
    """A hydrodynamic shape posed in its body's frame (:mod:`uvms.hydro.shapes`): gives buoyancy (volume and
    centre), added mass (summed over the body's shapes) and quadratic drag. ``position`` is the shape's centre
    [m] and ``rotation_rpy`` its orientation ``Rz(yaw) Ry(pitch) Rx(roll)`` [rad], body frame."""

    position: Vec3 = ZERO3
    rotation_rpy: Vec3 = ZERO3

    def _positive(self, names: tuple[str, ...]) -> None:
        for name in names:
            value = getattr(self, name)
            values = value if isinstance(value, tuple) else (value,)
            if not all(v > 0 for v in values):
                found = show(list(values) if len(values) > 1 else values[0])
                raise fail(f"expected positive dimensions [m], found {found}", name)

    def rotation(self) -> np.ndarray:
        from uvms.rotations import rotation_from_euler

        return rotation_from_euler(np.array(self.rotation_rpy))


class SphereShapeSpec(_ShapeSpec):
    """A sphere of ``radius`` [m]; ``drag_coefficient`` [-] on its frontal area ``pi a^2``."""

    type: Literal["sphere"]
    radius: Number
    drag_coefficient: NonNegative = 0.0

    @model_validator(mode="after")
    def _dims(self) -> SphereShapeSpec:
        self._positive(("radius",))
        return self


class BoxShapeSpec(_ShapeSpec):
    """A box of edges ``size`` [m] (shape x, y, z); ``drag_coefficients`` [-] per face family."""

    type: Literal["box"]
    size: Vec3
    drag_coefficients: NonNegativeVec3 = ZERO3

    @model_validator(mode="after")
    def _dims(self) -> BoxShapeSpec:
        self._positive(("size",))
        return self


class CylinderShapeSpec(_ShapeSpec):
    """A solid cylinder of ``radius`` and ``length`` [m] along the shape x axis, centred on ``position``;
    cross-flow ``drag_coefficient`` (Eq. 6) and end-on ``axial_drag_coefficient`` [-]."""

    type: Literal["cylinder"]
    radius: Number
    length: Number
    drag_coefficient: NonNegative = 0.0
    axial_drag_coefficient: NonNegative = 0.0

    @model_validator(mode="after")
    def _dims(self) -> CylinderShapeSpec:
        self._positive(("radius", "length"))
        return self


class EllipsoidShapeSpec(_ShapeSpec):
    """An ellipsoid of ``semi_axes`` [m]; cross-flow and axial drag coefficients [-] (along shape x)."""

    type: Literal["ellipsoid"]
    semi_axes: Vec3
    drag_coefficient: NonNegative = 0.0
    axial_drag_coefficient: NonNegative = 0.0

    @model_validator(mode="after")
    def _dims(self) -> EllipsoidShapeSpec:
        self._positive(("semi_axes",))
        return self


class FromCollisionSpec(Spec):
    """The URDF link's ``<collision>`` primitives (box, cylinder, sphere) as shapes, each with this drag
    coefficient [-] (a box on every face, a cylinder across its axis); meshes are skipped with a warning."""

    type: Literal["from_collision"]
    drag_coefficient: NonNegative = 0.0


def _shape_type(value: Any) -> str:
    kind = value.get("type") if isinstance(value, dict) else None
    return f"shape:{kind}" if kind in SHAPE_TYPES else "shape:unknown"


def _unknown_shape(value: Any) -> Any:
    kind = value.get("type") if isinstance(value, dict) else value
    raise fail(f"expected a shape with type sphere, box, cylinder, ellipsoid or from_collision, found "
               f"{show(kind)}")


ShapeSpec = Annotated[
    Annotated[SphereShapeSpec, Tag("shape:sphere")] | Annotated[BoxShapeSpec, Tag("shape:box")]
    | Annotated[CylinderShapeSpec, Tag("shape:cylinder")] | Annotated[EllipsoidShapeSpec, Tag("shape:ellipsoid")]
    | Annotated[FromCollisionSpec, Tag("shape:from_collision")]
    | Annotated[Any, BeforeValidator(_unknown_shape), Tag("shape:unknown")],
    Discriminator(_shape_type),
]


def _no_collision(shapes: tuple) -> tuple:
    for k, shape in enumerate(shapes):
        if isinstance(shape, FromCollisionSpec):
            raise fail(f"entry {k} is from_collision, which reads a URDF link's collision primitives: use it in "
                       "a URDF model's additions")
    return shapes


def _buoyancy_and_added_mass_given(body):
    """A DH model's body states its buoyancy and added mass, or carries shapes that give them."""
    for key in ("buoyancy", "added_mass"):
        if getattr(body, key) is None and not body.shapes:
            raise fail("expected a value (required field, unless the body has 'shapes' that give it), found none",
                       key)
    return body


class VehicleSpec(_BodySpec):
    """The vehicle (body 0; paper appendix, "URV Parameters")."""

    inertia: VehicleInertiaSpec
    buoyancy: BuoyancySpec | None = None          # default: from ``shapes``
    added_mass: VehicleAddedMassSpec | None = None    # default: from ``shapes``
    drag: VehicleDragSpec
    box: NonNegativeVec3                          # box dimensions [m]
    damping: FossenDampingSpec | None = None      # Fossen's linear + quadratic damping (added to ``drag``)
    shapes: tuple[ShapeSpec, ...] = ()            # buoyancy, added mass and drag of shapes (added to ``drag``)

    _shapes_here = field_validator("shapes")(classmethod(lambda cls, v: _no_collision(v)))
    _hydrostatics = model_validator(mode="after")(lambda self: _buoyancy_and_added_mass_given(self))


class DHSpec(Spec):
    """A modified Denavit-Hartenberg row (Craig): ``RotX(alpha_prev) TransX(a_prev) RotZ(theta) TransZ(d)``."""

    alpha_prev: Number                            # [rad]
    a_prev: Number                                # [m]
    d: Number                                     # [m]
    theta_offset: Number                          # [rad], added to the joint angle q


class CylinderSpec(Spec):
    """A link's cylinder along its x axis from the joint (Eq. 6)."""

    radius: NonNegative                           # r [m]
    length: NonNegative                           # L [m]


class LinkSpec(_BodySpec):
    """One arm link: body i, moved by revolute joint i (paper appendix, "Manipulator Parameters")."""

    name: Name
    dh: DHSpec
    inertia: LinkInertiaSpec
    cylinder: CylinderSpec
    drag_coefficient: NonNegative                 # normal-flow Cd [-] (Eq. 6)
    buoyancy: BuoyancySpec | None = None          # default: from ``shapes``
    added_mass: LinkAddedMass | None = None       # or "from_geometry" (cylinder strip theory); default: ``shapes``
    damping: FossenDampingSpec | None = None      # Fossen's linear + quadratic damping (added to Eq. 6)
    shapes: tuple[ShapeSpec, ...] = ()            # buoyancy, added mass and drag of shapes (added to Eq. 6)

    _shapes_here = field_validator("shapes")(classmethod(lambda cls, v: _no_collision(v)))
    _hydrostatics = model_validator(mode="after")(lambda self: _buoyancy_and_added_mass_given(self))


class MountSpec(Spec):
    """Pose of DH frame 0 in the vehicle frame; rotation ``Rz(yaw) Ry(pitch) Rx(roll)``."""

    position: Vec3 = ZERO3                        # [m]
    rotation_rpy: Vec3 = ZERO3                    # (roll, pitch, yaw) [rad]


class EndEffectorSpec(Spec):
    """End-effector frame in the last link frame, as a modified-DH row (``theta_offset`` is its angle)."""

    dh: DHSpec


class ArmSpec(Spec):
    """A serial arm of revolute joints."""

    mount: MountSpec = MountSpec()
    links: tuple[LinkSpec, ...]
    end_effector: EndEffectorSpec = EndEffectorSpec(dh=DHSpec(alpha_prev=0.0, a_prev=0.0, d=0.0, theta_offset=0.0))

    @field_validator("links")
    @classmethod
    def _links(cls, links: tuple[LinkSpec, ...]) -> tuple[LinkSpec, ...]:
        if not links:
            raise fail("expected at least one link, found none (leave 'arm' out for a vehicle without an arm)")
        _unique([link.name for link in links], "link")
        return links


class ThrustTableSpec(Spec):
    """A thrust table typed into the model file: commands (strictly increasing, any unit) and the steady
    thrust at each, in newtons (``thrust_N``) or kilogram-force (``thrust_kgf``)."""

    command: tuple[Number, ...]
    thrust_N: tuple[Number, ...] | None = None    # [N]
    thrust_kgf: tuple[Number, ...] | None = None  # [kgf] (x 9.80665 N)

    @model_validator(mode="after")
    def _one_form(self) -> ThrustTableSpec:
        if (self.thrust_N is None) == (self.thrust_kgf is None):
            found = "both" if self.thrust_N is not None else "neither"
            raise fail(f"expected exactly one of 'thrust_N' or 'thrust_kgf', found {found}")
        return self


class ThrusterSpec(Spec):
    """A thruster (Eqs. 9-12); ``model: table`` takes its steady thrust from a datasheet table
    (:mod:`uvms.thrusters.table`): ``table`` is ``t200`` (bundled Blue Robotics T200 at 16 V), a CSV file
    beside the model file, or an inline :class:`ThrustTableSpec`."""

    name: Name
    position: Vec3                                # r_h, body frame [m]
    direction: Vec3                               # e_h, body frame (non-zero; normalised when used)
    model: Literal["healey", "first_order", "ideal", "table"]
    parameters: dict[str, Number] | None = None
    max_thrust: Positive | None = None            # [N]
    table: Name | ThrustTableSpec | None = None   # model: table only

    @model_validator(mode="after")
    def _table(self) -> ThrusterSpec:
        if self.model == "table" and self.table is None:
            raise fail("expected a 'table' (t200, a CSV file name, or {command, thrust_N}) for model: table, "
                       "found none")
        if self.model != "table" and self.table is not None:
            raise fail(f"a 'table' is only read for model: table, found model: {self.model}", "table")
        return self

    @field_validator("direction")
    @classmethod
    def _nonzero(cls, direction: tuple[float, float, float]) -> tuple[float, float, float]:
        if not any(direction):
            raise fail(f"expected a non-zero direction vector, found {show(list(direction))}")
        return direction


def _unique(names: list[str], what: str) -> None:
    seen = [n for i, n in enumerate(names) if n in names[:i]]
    if seen:
        raise fail(f"expected unique {what} names, found {seen[0]!r} twice")


def _unique_thrusters(thrusters: tuple[ThrusterSpec, ...]) -> tuple[ThrusterSpec, ...]:
    _unique([t.name for t in thrusters], "thruster")
    return thrusters


Thrusters = Annotated[tuple[ThrusterSpec, ...], AfterValidator(_unique_thrusters)]
"""A model's thruster list (DH or URDF route): names unique."""


class IdentifiedSpec(Spec):
    """``identified:``: parameters set on the built model (:mod:`uvms.model.parameters`, names such as
    ``buoyancy``, ``cob.z``, ``damping.linear.pitch``) and the record of how they were found (free-form,
    written by ``uvms identify``: method, logs, held-out logs, uncertainties, scores)."""

    parameters: dict[Name, float] = {}
    record: dict[str, Any] = {}


class PointLoadSpec(Spec):
    """A point load on a body (``docs/models.md``, "Point loads and dry weight"; :mod:`uvms.model.loads`): a
    weight, a foam block or a sensor as a point ``mass`` [kg] and/or displaced fluid (``buoyancy`` [kg] or
    ``volume`` [m^3]) at ``position`` [m] in the frame of the link ``body``. ``inertial: false``: the mass only
    weighs (the body's inertia already holds it)."""

    name: Name
    body: Name                                    # a link (frame) name; "vehicle" for a DH model's vehicle
    position: Vec3                                # [m], in that link's frame
    mass: NonNegative | None = None               # point mass [kg]
    buoyancy: NonNegative | None = None           # displaced-fluid mass [kg]
    volume: NonNegative | None = None             # displaced volume [m^3] (x density)
    inertial: Annotated[bool, Strict()] = True    # false: adds to the weight only

    @model_validator(mode="after")
    def _something(self) -> PointLoadSpec:
        if self.buoyancy is not None and self.volume is not None:
            raise fail("expected at most one of 'buoyancy' (kg) or 'volume' (m^3), found both")
        if self.mass is None and self.buoyancy is None and self.volume is None:
            raise fail("expected a 'mass', a 'buoyancy' or a 'volume', found none")
        if not self.inertial and not self.mass:
            raise fail("expected a 'mass' for inertial: false (a load that only weighs), found none", "inertial")
        return self

    def fluid_mass(self, density: float) -> float:
        """Displaced-fluid mass [kg] (0 without buoyancy)."""
        if self.volume is not None:
            return float(density * self.volume)
        return float(self.buoyancy or 0.0)


def _unique_loads(loads: tuple[PointLoadSpec, ...]) -> tuple[PointLoadSpec, ...]:
    _unique([p.name for p in loads], "point load")
    return loads


PointLoads = Annotated[tuple[PointLoadSpec, ...], AfterValidator(_unique_loads)]
"""A model's point loads (DH or URDF route): names unique."""


class WeightSpec(Spec):
    """The dry weight of a URDF link whose inertial mass includes added mass: ``mass`` [kg] acting at ``center``
    [m, link frame] (``inertia_includes_added_mass: true``)."""

    mass: NonNegative
    center: Vec3 = ZERO3


class ModelSpec(Spec):
    """A whole model file: environment, vehicle, optional arm and thrusters."""

    name: Name
    description: str | None = None
    frame: FrameName = "ned"                      # world/body convention (docs/conventions.md, "Frames")
    environment: EnvironmentSpec = EnvironmentSpec()
    vehicle: VehicleSpec
    arm: ArmSpec | None = None
    thrusters: Thrusters = ()
    identified: IdentifiedSpec = IdentifiedSpec()   # parameters set after building (uvms identify)
    point_loads: PointLoads = ()                  # point masses and buoyancies on any body (uvms.model.loads)
    disturbance_wrench: Vec6 = ZERO6              # constant wrench on the vehicle, body axes [K M N X Y Z] [N m, N]


# --- a URDF and its additions (docs/models.md, "URDF") ----------------------------------------------------


class OriginAddedMassSpec(_AddedMassSpec):
    """Added mass of a URDF link or of the vehicle (root link), about the link-frame origin, link axes."""

    about: Literal["origin"]


def _urdf_added_mass_kind(value: Any) -> str:
    return "mapping" if isinstance(value, dict) else "string"


UrdfLinkAddedMass = Annotated[
    Annotated[Literal["from_geometry"], BeforeValidator(_from_geometry), Tag("string")]
    | Annotated[OriginAddedMassSpec, Tag("mapping")],
    Discriminator(_urdf_added_mass_kind),
]


class FluidVolumeSpec(Spec):
    """Displaced fluid of a link: its ``mass`` [kg] or its ``volume`` [m^3] (mass = density x volume), and the
    centre of buoyancy ``center`` [m, link frame] (Eqs. 7-8)."""

    mass: NonNegative | None = None
    volume: NonNegative | None = None
    center: Vec3 = ZERO3

    @model_validator(mode="after")
    def _one_form(self) -> FluidVolumeSpec:
        if (self.mass is None) == (self.volume is None):
            found = "both" if self.mass is not None else "neither"
            raise fail(f"expected exactly one of 'mass' or 'volume', found {found}")
        return self

    def fluid_mass(self, density: float) -> float:
        """Displaced-fluid mass [kg]."""
        return float(self.mass) if self.mass is not None else float(density * self.volume)


class LinkCylinderSpec(Spec):
    """A drag cylinder on a URDF link (Eq. 6): from ``origin`` along ``axis`` (link frame) for ``length``."""

    radius: NonNegative                           # r [m]
    length: NonNegative                           # L [m]
    drag_coefficient: NonNegative                 # normal-flow Cd [-]
    axis: Vec3 = (1.0, 0.0, 0.0)                  # direction, link frame (normalised)
    origin: Vec3 = ZERO3                          # start of the cylinder, link frame [m]

    @field_validator("axis")
    @classmethod
    def _nonzero(cls, axis: tuple[float, float, float]) -> tuple[float, float, float]:
        if not any(axis):
            raise fail(f"expected a non-zero axis, found {show(list(axis))}")
        return axis


class UrdfLinkSpec(Spec):
    """Hydrodynamics of one URDF link, in its own frame (all optional)."""

    added_mass: UrdfLinkAddedMass | None = None   # or "from_geometry" (strip theory for the cylinder)
    buoyancy: FluidVolumeSpec | None = None
    cylinder: LinkCylinderSpec | None = None
    damping: FossenDampingSpec | None = None      # Fossen's linear + quadratic damping, link frame
    shapes: tuple[ShapeSpec, ...] = ()            # shapes in the link frame, or from_collision
    weight: WeightSpec | None = None              # dry weight (with inertia_includes_added_mass: true)

    @model_validator(mode="after")
    def _geometry(self) -> UrdfLinkSpec:
        if self.added_mass == "from_geometry" and self.cylinder is None:
            raise fail("expected a 'cylinder' for added_mass: from_geometry, found none", "added_mass")
        return self


class UrdfVehicleSpec(Spec):
    """Hydrodynamics of the vehicle (the URDF's root link; its frame is the vehicle frame)."""

    added_mass: OriginAddedMassSpec | None = None
    buoyancy: FluidVolumeSpec | None = None
    drag: VehicleDragSpec | None = None
    damping: FossenDampingSpec | None = None      # Fossen's linear + quadratic damping, vehicle frame
    shapes: tuple[ShapeSpec, ...] = ()            # shapes in the vehicle (root link) frame, or from_collision
    box: NonNegativeVec3 = ZERO3                  # box dimensions [m] (plots)
    weight: WeightSpec | None = None              # dry weight (with inertia_includes_added_mass: true)


class UrdfJointSpec(Spec):
    """Joint damping and friction replacing the URDF's ``<dynamics>`` values (docs/models.md)."""

    damping: NonNegative | None = None            # b [N m s/rad or N s/m]
    friction: NonNegative | None = None           # Coulomb F_c [N m or N]
    friction_speed: Positive | None = None        # regularisation speed v_s [rad/s or m/s]


class UrdfModelSpec(Spec):
    """A model file naming a URDF (or xacro) and adding what URDF cannot hold; the URDF stays untouched."""

    urdf: Name                                    # path, relative to this file
    name: Name | None = None                      # default: the URDF's robot name
    description: str | None = None
    frame: FrameName = "ned"                      # world/body convention of the URDF and of this file
    environment: EnvironmentSpec = EnvironmentSpec()
    vehicle: UrdfVehicleSpec = UrdfVehicleSpec()
    links: dict[Name, UrdfLinkSpec] = {}
    joints: dict[Name, UrdfJointSpec] = {}
    fixed_joints: tuple[Name, ...] = ()           # frozen at zero (e.g. mimic joints)
    end_effector: Name | None = None              # a link (frame) name; default: the deepest link
    thrusters: Thrusters = ()
    balance_inertia: Annotated[bool, Strict()] = False   # MuJoCo's balanceinertia for impossible inertias
    package_paths: dict[Name, Name] = {}          # xacro $(find pkg) folders, relative to this file
    allow_environment: Annotated[bool, Strict()] = False  # xacro $(env VAR) / $(optenv VAR) may read
    xacro_args: dict[Name, Annotated[str, Strict()]] = {}  # xacro <xacro:arg> values ($(arg name))
    identified: IdentifiedSpec = IdentifiedSpec()   # parameters set after building (uvms identify)
    point_loads: PointLoads = ()                  # point masses and buoyancies on any link (uvms.model.loads)
    disturbance_wrench: Vec6 = ZERO6              # constant wrench on the vehicle, body axes [K M N X Y Z] [N m, N]
    inertia_includes_added_mass: Annotated[bool, Strict()] = False  # the URDF's inertial masses hold added mass

    @model_validator(mode="after")
    def _dry_weight(self) -> UrdfModelSpec:
        bodies = [("vehicle", self.vehicle)] + [(f"links.{name}", link) for name, link in self.links.items()]
        for where, body in bodies:
            if self.inertia_includes_added_mass and body.added_mass is not None:
                raise fail("expected no added_mass: inertia_includes_added_mass is true (the URDF's inertias "
                           "already include it)", f"{where}.added_mass")
            if not self.inertia_includes_added_mass and body.weight is not None:
                raise fail("a dry weight is read only with inertia_includes_added_mass: true (else the weight is "
                           "the URDF's inertial mass)", f"{where}.weight")
        return self
