"""The compile options of every compiled kernel (one place, so they cannot drift apart).

The ground floor (``docs/architecture.md``): physics, dynamics, control and the simulation core all compile
with these decorators, so this module imports nothing of uvms.

- ``cache=True``: compiled once, loaded from disk by later processes.
- ``_nrt=False``: no reference counting. The kernels never allocate; they only read and write arrays their
  caller owns. With numba's reference counting on, every array taken out of a named tuple or sliced out of a
  workspace (``ws.IA[i]``) costs an atomic increment and decrement, and the ~40 arrays of the model and
  workspace are counted again on every call: measured on the paper model, the articulated-body algorithm took
  2.5 us with it and 1.5 us without (``benchmarks/bench_dynamics.py --only compiled``). A function called only
  from Python that allocates (``crba_alloc``, ``end_effector_path``) uses plain ``njit``; one that allocates
  and is called from a kernel uses ``allocating``, which turns reference counting on explicitly (numba gives a
  function its caller's setting unless it sets one).
- ``error_model="numpy"``: a division by zero gives ``inf``/``nan`` (caught by the callers' finiteness checks)
  instead of a branch to a ``ZeroDivisionError`` after every division; results of finite arithmetic are the
  same.
- no ``fastmath``: NaN and infinity must propagate to the finiteness checks unchanged. Two narrow exceptions,
  for the wave kernels' loops over components (:mod:`uvms.hydro.elementary`, :mod:`uvms.hydro.flow`), neither
  of which changes what a NaN or an infinity does: ``fused_*`` allow floating-point **contraction** only
  (``a * b + c`` may become one fused multiply-add, rounded once: never less accurate); ``sum_kernel`` also
  allows **reassociation**, for loops of plain sums of products, so that they can be split into lane-wise
  partial sums and vectorised (the sum is then rounded in another order). ``nnan``, ``ninf``, ``afn`` (libm
  approximations) are never used.
- ``nogil=True``: a kernel holds no Python object, so it releases the GIL; threads run in parallel
  (:func:`uvms.rollout`).

``kernel`` compiles a function of its own; ``block`` a small helper inlined into its callers (numba-level
inlining, for the spatial-algebra and per-effect helpers called once per body).
"""

from __future__ import annotations

from numba import njit

OPTIONS = {"cache": True, "_nrt": False, "error_model": "numpy", "nogil": True}

kernel = njit(**OPTIONS)
"""Decorator of a compiled kernel (see the module docstring)."""

block = njit(inline="always", **OPTIONS)
"""Decorator of a small compiled helper inlined into every kernel that calls it."""

FUSED = {"fastmath": {"contract"}, **OPTIONS}
"""Compile options with floating-point contraction (the module docstring's first exception)."""

fused_kernel = njit(**FUSED)
"""Decorator of a compiled kernel whose ``a * b + c`` may be fused (elementary functions, wave terms)."""

fused_block = njit(inline="always", **FUSED)
"""Decorator of a small inlined helper with contraction (it takes its caller's options once inlined: call it
from ``fused_kernel`` or ``sum_kernel`` code only, or from tests)."""

SUMS = {"fastmath": {"contract", "reassoc"}, **OPTIONS}
"""Compile options of a loop of sums of products that may be reassociated (the second exception)."""

sum_kernel = njit(**SUMS)
"""Decorator of a compiled kernel of dot products over wave components (vectorised partial sums)."""

ALLOCATING = {"cache": True, "nogil": True, "_nrt": True, "error_model": "python"}
"""Compile options of a function that allocates and is reached from kernels: the bounded least squares of the
thrust allocation (``np.linalg.lstsq``, :mod:`uvms.thrusters.command`)."""

allocating = njit(**ALLOCATING)
"""Decorator of a compiled function that allocates, called from kernels (see the module docstring)."""
