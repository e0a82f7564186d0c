"""Look-ups in increasing tables, compiled: the one bisection of the package (time tables of the uniform
current and of the prescribed joint motion and thruster commands, a depth profile's depths, a current field's
axes)."""

from __future__ import annotations

from uvms.jit import block


@block
def last_at_or_before(table, value, hi):
    """The last ``k < hi`` with ``table[k] <= value`` (0 when none), by bisection on increasing ``table``
    (``hi <= len(table)``; for ``table[0] <= value < table[hi]`` it is the ``k`` with
    ``table[k] <= value < table[k + 1]``)."""
    lo = 0
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if table[mid] <= value:
            lo = mid
        else:
            hi = mid
    return lo
