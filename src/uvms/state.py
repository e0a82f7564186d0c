"""The simulation state: exactly what is integrated, nothing derived (MuJoCo's ``qpos, qvel, act``).

``position`` (3, world, m), ``quaternion`` (4, ``[w, x, y, z]``, body to world), ``nu`` (6, body velocity
``[omega; v]``, rad/s and m/s), ``q`` and ``qd`` (n, joint angles and rates, rad and rad/s) and
``actuator`` (thruster states when the thrusters have dynamics, e.g. Healey's ``[Omega_h..., U_h...]``).
Euler angles and the rotation matrix are derived on request.

The state vector ``x`` (what the integrators and the compiled kernels hold) packs the fields in that order::

    x = [position (3) | quaternion (4) | nu (6) | q (n) | qd (n) | actuator states]

:data:`POSITION`, :data:`QUATERNION`, :data:`NU` and :data:`JOINTS` are the offsets the compiled code slices
with (``x[NU:JOINTS]`` is ``nu``, ``x[JOINTS:JOINTS + n]`` is ``q``, ``x[JOINTS + n:JOINTS + 2 * n]`` is
``qd``, the actuator states start at ``JOINTS + 2 * n``); :class:`StateLayout` is the same layout for Python
code (slices, size, names of the entries). This module is on the ground floor (``docs/architecture.md``). The
kernels compiled with :mod:`uvms.jit` read the offsets as compile-time constants, so the kernel cache's
fingerprint (:mod:`uvms._cache`, which keys on that module's name) covers this file.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from uvms import checks
from uvms.errors import UvmsInputError, show
from uvms.rotations import euler_from_quaternion, quaternion_from_euler, rotation_from_quaternion

POSITION, QUATERNION, NU, JOINTS = 0, 3, 7, 13
"""Offsets in the state vector of the position (3), the quaternion (4), ``nu`` (6) and the joint angles (``n``;
the joint rates follow at ``JOINTS + n``, the actuator states at ``JOINTS + 2 * n``). ``JOINTS`` is also the
size of the vehicle's part of the state."""


class StateLayout:
    """The one owner of the state vector's layout for Python code: slices, size and quantity names for
    ``n_joints`` joints and ``n_actuator`` actuator states (compiled code uses the offsets of this module)."""

    _NAMES = ("x", "y", "z", "qw", "qx", "qy", "qz", "p (roll rate)", "q (pitch rate)", "r (yaw rate)",
              "u (surge velocity)", "v (sway velocity)", "w (heave velocity)")

    def __init__(self, n_joints: int, n_actuator: int = 0) -> None:
        self.n_joints, self.n_actuator = int(n_joints), int(n_actuator)
        n = self.n_joints
        self.position, self.quaternion, self.nu = (slice(POSITION, QUATERNION), slice(QUATERNION, NU),
                                                   slice(NU, JOINTS))
        self.q = slice(JOINTS, JOINTS + n)
        self.qd = slice(JOINTS + n, JOINTS + 2 * n)
        self.actuator = slice(JOINTS + 2 * n, JOINTS + 2 * n + self.n_actuator)
        self.size = JOINTS + 2 * n + self.n_actuator

    def slices(self) -> dict[str, slice]:
        """Every field's slice, by :class:`State` field name."""
        return {"position": self.position, "quaternion": self.quaternion, "nu": self.nu, "q": self.q,
                "qd": self.qd, "actuator": self.actuator}

    def quantity_name(self, index: int) -> str:
        """What entry ``index`` of the state vector is (for messages)."""
        n = self.n_joints
        if index < JOINTS:
            return self._NAMES[index]
        if index < JOINTS + n:
            return f"q{index - JOINTS + 1}"
        if index < JOINTS + 2 * n:
            return f"qd{index - JOINTS + 1 - n}"
        return f"actuator state {index - JOINTS - 2 * n}"


def layout(n_joints: int, n_actuator: int) -> dict[str, slice]:
    """Slices of the state vector (:meth:`StateLayout.slices`)."""
    return StateLayout(n_joints, n_actuator).slices()


def actuator_count(n_joints: int, size: int) -> int:
    """The number of actuator states of a state vector of ``size`` entries for ``n_joints`` joints."""
    return size - JOINTS - 2 * n_joints


def _vector(value, size: int | None, name: str, what: str = "") -> np.ndarray:
    """A read-only float64 copy of ``value`` (``size`` finite values; zeros for ``None``), else a one-line
    :class:`~uvms.errors.UvmsInputError` naming ``name``."""
    a = checks.optional_vector(value, size, name, what) if size is not None or value is not None else np.zeros(0)
    a.setflags(write=False)
    return a


_FIELDS = ("position", "quaternion", "nu", "q", "qd", "actuator")


def _by_joint_name(model, value, name: str):
    """A ``{joint name: value}`` mapping as a list in ``model.joint_names`` order (other values unchanged)."""
    if not isinstance(value, Mapping):
        return value
    out = np.zeros(model.n_joints)
    for joint, x in value.items():
        if joint not in model.joint_names:
            raise UvmsInputError(f"model {model.name!r} has no joint {show(joint)}; joints: "
                                 f"{', '.join(model.joint_names) or '(none)'}", path=name)
        try:
            out[model.joint_names.index(joint)] = checks.number(x, name)
        except UvmsInputError as exc:
            raise UvmsInputError(f"joint {joint!r}: {exc.message}", path=name) from None
    return out


@dataclass(frozen=True, eq=False)
class State:
    """Vehicle pose and velocity, joint angles and rates, actuator states (frozen)."""

    position: np.ndarray
    quaternion: np.ndarray
    nu: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    actuator: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self) -> None:
        q = checks.vector(self.q, None, "q", " (one per joint)")
        n = q.shape[0]
        object.__setattr__(self, "position", _vector(self.position, 3, "position", " [m]"))
        quat = checks.vector(self.quaternion, 4, "quaternion", " [w, x, y, z]")
        norm = float(np.linalg.norm(quat))
        if not 0.5 < norm < 2.0:
            raise checks.fail("quaternion", f"expected a unit quaternion [w, x, y, z], got norm {norm:.6g}")
        quat = quat / norm
        quat.setflags(write=False)
        object.__setattr__(self, "quaternion", quat)
        object.__setattr__(self, "nu", _vector(self.nu, 6, "nu", " [omega; v]"))
        q.setflags(write=False)
        object.__setattr__(self, "q", q)
        object.__setattr__(self, "qd", _vector(self.qd, n, "qd", " (one per joint, as q)"))
        object.__setattr__(self, "actuator", _vector(self.actuator, None, "actuator"))
        vector = np.concatenate([getattr(self, name) for name in _FIELDS])
        vector.setflags(write=False)
        start = 0
        for name in _FIELDS:                 # every field a read-only view of the one vector
            size = getattr(self, name).shape[0]
            object.__setattr__(self, name, vector[start:start + size])
            start += size
        object.__setattr__(self, "_packed", vector)

    _packed = None
    """The fields packed in the state vector's layout ``[position | quaternion | nu | q | qd | actuator]``
    (:class:`StateLayout`), read-only, of which the fields are views (``None`` for a :meth:`trusted` state
    built from separate arrays): the compiled dynamics take it as one argument."""

    @classmethod
    def from_euler(cls, model, *, position=None, euler=None, nu=None, q=None, qd=None, actuator=None) -> "State":
        """A state from ZYX Euler angles ``(phi, theta, psi)`` [rad]; omitted values are zero.

        ``q`` and ``qd`` are lists in the order of ``model.joint_names`` (the tree order), or mappings
        ``{joint name: value}`` in which omitted joints are zero.
        """
        n = checks.model(model).n_joints
        q = _by_joint_name(model, q, "q")
        qd = _by_joint_name(model, qd, "qd")
        return cls(
            position=_vector(position, 3, "position", " [m]"),
            quaternion=quaternion_from_euler(_vector(euler, 3, "euler", " (phi, theta, psi) [rad]")),
            nu=_vector(nu, 6, "nu", " [omega; v]"),
            q=_vector(q, n, "q", " (one per joint)"),
            qd=_vector(qd, n, "qd", " (one per joint)"),
            actuator=_vector(actuator, None, "actuator"),
        )

    @classmethod
    def trusted(cls, position, quaternion, nu, q, qd, actuator, vector=None) -> "State":
        """A state from read-only arrays the integrator produced (checked and normalised): no validation and
        no copies; ``vector``: the packed array the fields are views of, if any (:attr:`_packed`). For the
        simulation loop only; user code should use the constructor or :meth:`from_euler`.
        """
        obj = object.__new__(cls)
        obj.__dict__.update(position=position, quaternion=quaternion, nu=nu, q=q, qd=qd, actuator=actuator)
        if vector is not None:
            obj.__dict__["_packed"] = vector
        return obj

    @classmethod
    def zero(cls, model) -> "State":
        """The vehicle at the world origin, level, at rest, joints at zero."""
        return cls.from_euler(model)

    @property
    def rotation(self) -> np.ndarray:
        """3x3 body-to-world rotation ``R``."""
        return rotation_from_quaternion(self.quaternion)

    @property
    def euler(self) -> np.ndarray:
        """ZYX Euler angles ``(phi, theta, psi)`` [rad] (reported, never integrated)."""
        return euler_from_quaternion(self.quaternion)

    @property
    def n_joints(self) -> int:
        return int(self.q.size)

    @property
    def generalized_velocity(self) -> np.ndarray:
        """``[nu; qd]`` (6 + n)."""
        return np.concatenate([self.nu, self.qd])

    def in_frame(self, source: str, target: str) -> "State":
        """This state (of a model written in convention ``source``) in convention ``target``
        (:func:`uvms.frames.convert_state`: ``H p``, ``[w, x, -y, -z]``, ``H6 nu``; joints and actuators same)."""
        from uvms.frames import convert_state

        return convert_state(self, source, target)

    def replace(self, **changes) -> "State":
        """A new state with some fields changed."""
        unknown = sorted(set(changes) - set(_FIELDS))
        if unknown:
            raise checks.fail(unknown[0], f"not a state field; expected one of: {', '.join(_FIELDS)}")
        values = {name: getattr(self, name) for name in _FIELDS}
        values.update(changes)
        return State(**values)
