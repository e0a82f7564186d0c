"""Exceptions meant for users: each prints as one line, and the CLI shows it without a traceback.

Light on purpose (no third-party imports): :mod:`uvms.cli` imports it before any heavy module.
"""

from __future__ import annotations

import reprlib
from typing import Any

_bounded_repr = reprlib.Repr()   # a few items of a user value: a message never renders an unbounded one
_bounded_repr.maxlevel, _bounded_repr.maxstring, _bounded_repr.maxother, _bounded_repr.maxlong = 3, 80, 80, 40
_bounded_repr.maxlist = _bounded_repr.maxtuple = _bounded_repr.maxdict = _bounded_repr.maxset = 8


def show(value: Any, limit: int = 60) -> str:
    """A short one-line rendering of a user value for error messages (at most ``limit`` characters)."""
    text = " ".join(_bounded_repr.repr(value).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


class UvmsInputError(ValueError):
    """Invalid user input (model or scenario file, command-line value).

    ``str()`` is one line: ``"<file>: <field.path>: <what was expected, what was found>"``; the file and
    the path are left out when there is none.

    Attributes:
        message: what was expected and what was found.
        source: the file the input came from, or ``None``.
        path: dotted field path such as ``arm.links[1].mass`` (or ``line 3, column 5``), or ``None``.
    """

    def __init__(self, message: str, source: str | None = None, path: str | None = None) -> None:
        super().__init__(message, source, path)  # all arguments in args: picklable (dask workers)
        self.message, self.source, self.path = message, source, path

    def __str__(self) -> str:
        text = ": ".join(str(part) for part in (self.source, self.path, self.message) if part)
        return " ".join(text.split())  # one line, whatever the parts contain


class SimulationDiverged(RuntimeError):
    """The integration produced a non-finite or runaway state.

    Attributes:
        time: simulation time at which the divergence was detected [s].
        quantity: what diverged, e.g. ``"joint velocity qd[2] = 3.1e+12 rad/s"``.
        hint: what the user might change (time step, tolerances, gains), or ``""``.
    """

    def __init__(self, time: float, quantity: str, hint: str = "") -> None:
        super().__init__(time, quantity, hint)
        self.time, self.quantity, self.hint = float(time), quantity, hint

    def __str__(self) -> str:
        text = f"simulation diverged at t = {self.time:.6g} s: {self.quantity}"
        return " ".join((text + (f"; {self.hint}" if self.hint else "")).split())
