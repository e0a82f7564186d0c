"""The hydrodynamic forces on every body, by cause: :mod:`uvms.dynamics.inspect` (re-exported here, where the
per-effect kernels live, for the name users know)."""

from uvms.dynamics.inspect import *  # noqa: F401,F403
from uvms.dynamics.inspect import __all__  # noqa: F401
