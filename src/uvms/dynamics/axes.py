"""The six body axes by name, and the plant's effective mass or inertia along each: ``1 / (M^-1)_jj`` of the
joint-space mass matrix, the quantity the sliding-mode law's ``b`` bounds must contain (paper Eqs. 27-29) and
that ``uvms trim`` / ``uvms validate`` report."""

from __future__ import annotations

import numpy as np

from uvms.dynamics.api import mass_matrix
from uvms.errors import UvmsInputError
from uvms.state import State

AXES: tuple[str, ...] = ("surge", "sway", "heave", "roll", "pitch", "yaw")
"""Body axes, in this order everywhere: forces X, Y, Z [N], then moments K, M, N [N m]."""
WRENCH_ROW: tuple[int, ...] = (3, 4, 5, 0, 1, 2)
"""Row of each axis of :data:`AXES` in a ``[K, M, N, X, Y, Z]`` wrench (and in ``nu``)."""
INERTIA_UNITS: tuple[str, ...] = ("kg", "kg", "kg", "kg m^2", "kg m^2", "kg m^2")
"""Units of the effective mass or inertia of each axis of :data:`AXES`."""


def effective_inertia(model, q: np.ndarray) -> np.ndarray:
    """(6,) ``1 / (M^-1)_jj`` of the joint-space mass matrix at ``q`` per axis of :data:`AXES`."""
    M = mass_matrix(model, State.from_euler(model, q=q))
    try:
        inverse = np.linalg.inv(M)
    except np.linalg.LinAlgError:
        raise UvmsInputError("the mass matrix is singular at this pose") from None
    return np.array([1.0 / inverse[row, row] for row in WRENCH_ROW])
