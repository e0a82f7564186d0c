"""Argument checks at the boundary of the Python API: shapes, finiteness and types.

Every public entry point (:func:`uvms.forward_dynamics`, :func:`uvms.simulate`, :class:`uvms.State` ...) calls
these helpers before anything reaches a compiled kernel, which would otherwise read past the end of a short
array or carry a NaN through silently. A failed check raises :class:`~uvms.errors.UvmsInputError` (a
``ValueError``) whose one-line message starts with the argument's name, e.g.
``joint_torques: expected 3 finite values (one per joint), got shape (4,)``.

The helpers are cheap on purpose (a few hundred nanoseconds for a short vector: one conversion, one shape
comparison and a sum of the values as a finiteness test), so the dynamics entry points stay fast.
"""

from __future__ import annotations

import math
import sys
from numbers import Real
from typing import Any, Callable

import numpy as np

from uvms.errors import UvmsInputError


class _NotLoaded:
    """Stands for a class whose module was never imported: no value is an instance of it."""


_FOUND: dict[tuple[str, str], type] = {}


def _loaded(module: str, name: str) -> type:
    """The class ``module.name`` if its module has been imported (kept once found), else :class:`_NotLoaded`.

    This module is on the ground floor (``docs/architecture.md``): it imports nothing of ``uvms.model`` or
    :mod:`uvms.state` (both import it), yet an instance of their classes can only exist once they are imported,
    so the isinstance checks stay exact."""
    found = _FOUND.get((module, name))
    if found is None:
        found = getattr(sys.modules.get(module), name, None)
        if not isinstance(found, type):
            return _NotLoaded
        _FOUND[(module, name)] = found
    return found


def _model_class() -> type:
    """:class:`uvms.model.model.Model`, or :class:`_NotLoaded`."""
    return _loaded("uvms.model.model", "Model")


def _state_class() -> type:
    """:class:`uvms.state.State`, or :class:`_NotLoaded`."""
    return _loaded("uvms.state", "State")


MAX_RECORDED_VALUES = 2 * 10**8
"""Largest number of values a run allocates before it starts: its recorded state values (rows times state
entries, 1.6 GB of float64), those of one :func:`uvms.rollout` batch in all, a noisy IMU's noise table
(:mod:`uvms.sensors.body_acceleration`), the sensors' errors of a run fed to a controller
(:mod:`uvms.sim.sensing`, :mod:`uvms.control.estimator`). A larger one is refused before anything is allocated."""

_FLOAT64 = np.dtype(np.float64)
_NUMERIC_KINDS = "iuf"
"""numpy dtype kinds accepted as numbers: signed and unsigned integers, floats (not bool, complex, str, object)."""


def show(value: Any, limit: int = 40) -> str:
    """A short one-line description of what was passed, for error messages."""
    if isinstance(value, np.ndarray):
        return f"an array of shape {value.shape}" if value.dtype.kind in _NUMERIC_KINDS \
            else f"an array of dtype {value.dtype} and shape {value.shape}"
    if isinstance(value, (str, bytes)):
        text = " ".join(repr(value).split())
        return ("a string " if isinstance(value, str) else "bytes ") + (text if len(text) <= limit
                                                                          else text[: limit - 3] + "...")
    if value is None or isinstance(value, (bool, np.bool_)):
        return repr(value)
    if isinstance(value, Real):
        return repr(float(value)) if isinstance(value, (float, np.floating)) else repr(value)
    return f"a {type(value).__name__}"


def fail(name: str, message: str) -> UvmsInputError:
    """The error for argument ``name``: ``"<name>: <message>"`` on one line."""
    return UvmsInputError(message, path=name)


def vector(value: Any, size: int | None, name: str, what: str = "") -> np.ndarray:
    """``value`` as a fresh, writeable, C-ordered float64 array of shape ``(size,)`` with finite entries.

    ``size=None`` accepts any length (a 1-D array). ``what`` is appended to the expectation, e.g.
    ``" (one per joint)"``. Raises :class:`UvmsInputError` naming ``name`` for a wrong shape, a non-numeric
    value (strings, booleans, objects) or a NaN or infinite entry.
    """
    if type(value) is np.ndarray and value.dtype is _FLOAT64 and value.shape == (size,):   # the usual case, fast
        a = value.copy()
        total = sum(a.tolist())
        if total - total == 0.0:
            return a
    expected = (f"{size} finite values" if size is not None else "a 1-D array of finite values") + what
    if isinstance(value, (str, bytes)) or value is None:
        raise fail(name, f"expected {expected}, got {show(value)}")
    try:
        a = np.asarray(value)
    except (ValueError, TypeError):          # ragged nested lists and other non-arrays
        raise fail(name, f"expected {expected}, got {show(value)}") from None
    if a.dtype.kind not in _NUMERIC_KINDS:
        found = f"values of type {a.dtype}" if a.dtype.kind in "bcUSO" and a.ndim else show(value)
        raise fail(name, f"expected {expected}, got {found}")
    if a.ndim != 1 or (size is not None and a.shape[0] != size):
        raise fail(name, f"expected {expected}, got shape {a.shape}")
    if a.dtype is not _FLOAT64 or not isinstance(value, (list, tuple)):
        a = np.array(a, dtype=np.float64)    # a copy: the caller's array is never aliased (a list's is new)
    total = sum(a.tolist())                  # NaN or inf in, NaN or inf out (or a finite sum overflowing)
    if total - total != 0.0:
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise fail(name, f"expected {expected}, got {a[bad[0]]} at index {bad[0]}")
    return a


def matrix(value: Any, rows: int | None, cols: int | None, name: str, what: str = "") -> np.ndarray:
    """``value`` as a fresh float64 array of shape ``(rows, cols)`` (``None``: any number) with finite
    entries, else :class:`UvmsInputError` naming ``name``, like :func:`vector`."""
    expected = ("rows" if rows is None else f"{rows} row{'s' if rows != 1 else ''}") + " of " + \
        ("finite values, all of one length" if cols is None else f"{cols} finite values") + what
    found = ""
    try:
        a = np.asarray(value) if not isinstance(value, (str, bytes)) and value is not None else None
    except (ValueError, TypeError):          # ragged rows
        a, found = None, "rows of different lengths"
    if a is None or a.dtype.kind not in _NUMERIC_KINDS or a.ndim != 2 or (rows is not None and a.shape[0] != rows) \
            or (cols is not None and a.shape[1] != cols):
        found = found or (f"shape {a.shape}" if a is not None and a.dtype.kind in _NUMERIC_KINDS else show(value))
        raise fail(name, f"expected {expected}, got {found}")
    a = np.array(a, dtype=np.float64)
    if not np.all(np.isfinite(a)):
        r, c = np.argwhere(~np.isfinite(a))[0]
        raise fail(name, f"expected {expected}, got {a[r, c]} at row {r}, column {c}")
    return a


def optional_vector(value: Any, size: int, name: str, what: str = "", default: Any = None) -> np.ndarray:
    """:func:`vector`, or when ``value`` is ``None`` a fresh float64 copy of ``default`` (trusted: a model's
    own array) or zeros."""
    if value is None:
        return np.zeros(size) if default is None else np.array(default, dtype=np.float64)
    if type(value) is np.ndarray and value.dtype is _FLOAT64 and value.shape == (size,):   # vector's fast path
        a = value.copy()
        total = sum(a.tolist())
        if total - total == 0.0:
            return a
    return vector(value, size, name, what)


def flag(value: Any, name: str) -> bool:
    """``value`` if it is ``True`` or ``False`` (numpy booleans too); anything else is refused."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise fail(name, f"expected True or False, got {show(value)}")


def number(value: Any, name: str, *, positive: bool = False, nonnegative: bool = False, unit: str = "") -> float:
    """A finite real number (``> 0`` if ``positive``, ``>= 0`` if ``nonnegative``) as a float; booleans and
    strings are refused."""
    expected = ("a positive, finite number" if positive else "a finite number >= 0" if nonnegative
                else "a finite number") + (f" [{unit}]" if unit else "")
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (Real, np.integer, np.floating)):
        raise fail(name, f"expected {expected}, got {show(value)}")
    x = float(value)
    if not math.isfinite(x) or (positive and x <= 0.0) or (nonnegative and x < 0.0):
        raise fail(name, f"expected {expected}, got {x!r}")
    return x


def count(value: Any, name: str, *, minimum: int = 0) -> int:
    """A whole number ``>= minimum`` (an ``int`` or a numpy integer; booleans, floats and strings are refused)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise fail(name, f"expected a whole number >= {minimum}, got {show(value)}")
    return int(value)


def optional_number(value: Any, name: str, *, positive: bool = False, unit: str = "") -> float | None:
    """:func:`number`, or ``None`` for ``None``."""
    return None if value is None else number(value, name, positive=positive, unit=unit)


def callable_or_none(value: Any, name: str, signature: str) -> Callable | None:
    """``value`` if it is ``None`` or callable (``signature`` describes the expected call, for the message)."""
    if value is None or callable(value):
        return value
    raise fail(name, f"expected None or a callable {signature}, got {show(value)}")


def model(value: Any, name: str = "model"):
    """``value`` if it is a :class:`uvms.Model`."""
    if isinstance(value, _model_class()):
        return value
    raise fail(name, f"expected a uvms Model (from uvms.load_model), got {show(value)}")


def state(model_: Any, value: Any, name: str = "state"):
    """``value`` if it is a :class:`uvms.State` with the joints of ``model_`` (checked first)."""
    if not isinstance(model_, _model_class()):
        model(model_)
    if not isinstance(value, _state_class()):
        raise fail(name, f"expected a uvms State (e.g. uvms.State.from_euler(model, ...)), got {show(value)}")
    n = model_.n_joints
    if value.q.shape[0] != n:
        raise fail(name, f"expected a state of the model's {n} joints, got one of {value.q.shape[0]} "
                         f"(q of shape {value.q.shape})")
    return value


def finite(*arrays: np.ndarray) -> bool:
    """Whether every entry of the (1-D) ``arrays`` is finite; a sum of the values first (fast), exact if that
    sum is not finite (a NaN or infinity, or finite values whose sum overflows)."""
    total = 0.0
    for a in arrays:
        total += sum(a.tolist())
    return total - total == 0.0 or all(bool(np.all(np.isfinite(a))) for a in arrays)


def overflow(what: str, inputs: dict[str, np.ndarray]) -> UvmsInputError:
    """The error for finite inputs so large that ``what`` overflowed to inf or NaN inside a kernel: it names the
    input of largest magnitude (the likely culprit) instead of a NaN result being returned silently."""
    name, size = max(((k, float(np.max(np.abs(a)))) for k, a in inputs.items() if a.size), key=lambda kv: kv[1])
    return fail(name, f"expected values the dynamics can evaluate in floating point: {what} overflowed to inf or "
                      f"NaN, with |{name}| up to {size:.3g}")


def returned_vector(value: Any, size: int, name: str, what: str, t: float) -> np.ndarray:
    """What a user callable ``name`` returned at time ``t``, checked like :func:`vector`."""
    try:
        return vector(value, size, name, what)
    except UvmsInputError as exc:
        raise fail(f"{name} (returned at t = {t:.6g} s)", exc.message) from None


JOINT_INERTIA_RELATIVE = 1e-9
"""A link's inertia about its joint axis counts as zero below this fraction of its whole rotational inertia about
the joint origin (rigid plus added: the trace of both): round-off of the parallel-axis shift, not a body."""


def joint_axis_inertia(mass, com, inertia_com, added_mass, joint_axis=None,
                       joint_type=None) -> tuple[np.ndarray, np.ndarray]:
    """Per link (bodies 1..n): its own (rigid plus added) inertia along its joint's motion subspace ``S``,
    ``S^T (I + I_A) S``, and the scale it is compared with.

    ``I`` is the link's rigid spatial inertia about its frame origin (the joint) and ``I_A`` its added mass there
    (``[angular; linear]``, paper Eq. 2). A revolute joint about the unit axis ``a`` (default: the link frame's z
    axis, the DH joints) gives ``a^T (I_c + m (|c|^2 1 - c c^T)) a + a^T I_A,ang a`` [kg m^2] (parallel-axis
    theorem), compared with the trace of the rotational inertia about the joint; a prismatic joint along ``a``
    gives ``m + a^T I_A,lin a`` [kg], compared with ``m`` plus the trace of the linear added mass."""
    m = np.asarray(mass, dtype=float)[1:]
    c = np.asarray(com, dtype=float).reshape(-1, 3)[1:]
    I = np.asarray(inertia_com, dtype=float).reshape(-1, 3, 3)[1:]
    A = np.asarray(added_mass, dtype=float).reshape(-1, 6, 6)[1:]
    n = m.shape[0]
    a = np.tile([0.0, 0.0, 1.0], (n, 1)) if joint_axis is None else np.asarray(joint_axis, dtype=float).reshape(n, 3)
    prismatic = np.zeros(n, bool) if joint_type is None else np.array([t == "prismatic" for t in joint_type], bool)
    cc = np.sum(c * c, axis=1)
    I_joint = I + m[:, None, None] * (cc[:, None, None] * np.eye(3) - c[:, :, None] * c[:, None, :])
    rotational = np.einsum("ni,nij,nj->n", a, I_joint + A[:, :3, :3], a)
    translational = m + np.einsum("ni,nij,nj->n", a, A[:, 3:, 3:], a)
    axis = np.where(prismatic, translational, rotational)
    scale = np.where(prismatic, m + np.trace(A[:, 3:, 3:], axis1=1, axis2=2),
                     np.trace(I_joint + A[:, :3, :3], axis1=1, axis2=2))
    return axis, scale


def check_joint_axis_inertia(mass, com, inertia_com, added_mass, *, joint_axis=None, joint_type=None,
                             source: str | None = None,
                             where: Callable[[int], str] = lambda j: f"links[{j}]") -> None:
    """Refuse a link that its joint cannot accelerate: zero (rigid + added) inertia along the joint's motion.

    The articulated-body algorithm divides by ``D_i = S_i^T I^A_i S_i`` (Featherstone 2008, Sec. 7.3), the
    articulated inertia of link ``i`` and everything outboard along joint ``i``'s motion; it is at least the
    link's own inertia along it (outboard bodies add positive semi-definite terms), so a positive own
    inertia (:func:`joint_axis_inertia`) is a sufficient, configuration-independent condition. ``where(j)``
    names the field of link ``j`` (0-based) in the message, which is one line: ``"<source>: <where>: ..."``.
    """
    axis, scale = joint_axis_inertia(mass, com, inertia_com, added_mass, joint_axis, joint_type)
    for j in np.flatnonzero(~(axis > JOINT_INERTIA_RELATIVE * scale)):
        if joint_type is not None and joint_type[j] == "prismatic":
            raise UvmsInputError(f"expected a positive mass along the prismatic joint, found {axis[j]:.6g} kg",
                                 source, where(int(j)))
        raise UvmsInputError(
            "expected a positive rotational inertia about the joint axis (through the joint origin, rigid "
            f"I + m d^2 plus added mass), found {axis[j]:.6g} kg m^2 (the dynamics divide by each joint's "
            "inertia about its axis)", source, where(int(j)))


ADAPTIVE_METHODS = ("RK23", "RK45", "DOP853", "Radau", "BDF", "LSODA")
"""The ``scipy.integrate.solve_ivp`` methods ``simulate(integrator=...)`` accepts besides ``"rk4"``."""
