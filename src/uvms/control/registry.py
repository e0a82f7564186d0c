"""Controllers by name: a decorator-based registry and the validation of their parameters.

A controller class registers itself with ``@register("name")``; it has a ``Parameters`` frozen dataclass
whose fields are declared with :func:`parameter` (default, converter, one-line description) and a constructor
``cls(model, parameters, *, period)``. :func:`make_controller` checks a plain mapping of parameters (from
a scenario file or the command line) against that dataclass: an unknown key or an invalid value raises a
one-line :class:`~uvms.errors.UvmsInputError` naming ``controller.parameters.<key>``.

Bundled controllers (:data:`BUILTIN_MODULES`): ``smc-ab`` (the paper), ``smc-ne`` (Dunnigan and Russell),
``smc-vehicle``, ``pid`` and ``lqr`` (designed from :func:`uvms.linearize`).
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable
from dataclasses import field, fields
from typing import Any

import numpy as np

from uvms.control.base import Controller
from uvms.errors import UvmsInputError

BUILTIN_MODULES: tuple[str, ...] = (
    "uvms.control.smc_ab", "uvms.control.smc_ne", "uvms.control.smc_vehicle", "uvms.control.pid",
    "uvms.control.lqr",
)
"""Modules whose import registers the bundled controllers (imported on first use of the registry)."""

_REGISTRY: dict[str, Any] = {}


def register(name: str) -> Callable[[Any], Any]:
    """Class decorator: make a controller class available to :func:`make_controller` as ``name``."""

    def decorate(cls: Any) -> Any:
        if name in _REGISTRY and _REGISTRY[name] is not cls:
            raise ValueError(f"controller name {name!r} is already registered by {_REGISTRY[name].__name__}")
        _REGISTRY[name] = cls
        cls.name = name
        return cls

    return decorate


def _registry() -> dict[str, Any]:
    for module in BUILTIN_MODULES:
        importlib.import_module(module)
    return _REGISTRY


def controller_names() -> tuple[str, ...]:
    """The registered controller names, sorted."""
    return tuple(sorted(_registry()))


def controller_class(name: str) -> Any:
    """The class registered as ``name``.

    Raises:
        UvmsInputError: unknown name (one line, listing the known ones).
    """
    registry = _registry()
    if name not in registry:
        raise UvmsInputError(f"unknown controller {name!r}; expected one of: {', '.join(sorted(registry))}",
                             path="controller.name")
    return registry[name]


def make_controller(name: str, model, *, period: float = 0.01, parameters: dict[str, Any] | None = None
                    ) -> Controller:
    """A new controller ``name`` for the plant ``model``, updated every ``period`` seconds.

    Args:
        name: one of :func:`controller_names` (``smc-ab``, ``smc-ne``, ``smc-vehicle``, ``pid``).
        model: the plant :class:`~uvms.model.Model` (model-based controllers derive their own model from it).
        period: update period [s].
        parameters: overrides of the controller's ``Parameters`` defaults (see ``docs/controllers.md``).

    Raises:
        UvmsInputError: unknown name or parameter, invalid value or period (one line).
    """
    cls = controller_class(name)
    if isinstance(period, bool) or not isinstance(period, (int, float)) or not period > 0 or not math.isfinite(period):
        raise UvmsInputError(f"expected a period > 0 [s], found {period!r}", path="controller.period")
    if parameters is not None and not isinstance(parameters, dict):
        raise UvmsInputError(f"expected a mapping of parameter names to values, found {parameters!r}",
                             path="controller.parameters")
    return cls(model, parse_parameters(cls.Parameters, parameters), period=float(period))


# ----------------------------------------------------------------------------------- parameter checking


def parameter(default: Any, convert: Callable[[Any], Any], doc: str):
    """A dataclass field with a converter (used by :func:`parse_parameters`) and a one-line description."""
    return field(default=default, metadata={"convert": convert, "doc": doc})


def parse_parameters(cls, parameters: dict[str, Any] | None, prefix: str = "controller.parameters"):
    """Build the parameter dataclass ``cls`` from a mapping; each field's ``metadata["convert"]`` checks it.

    Raises:
        UvmsInputError: an unknown key or an invalid value, one line naming ``<prefix>.<key>``.
    """
    known = {f.name: f for f in fields(cls)}
    values: dict[str, Any] = {}
    for key, value in (parameters or {}).items():
        if key not in known:
            raise UvmsInputError(f"unknown parameter; expected one of: {', '.join(known)}", path=f"{prefix}.{key}")
        try:
            values[key] = known[key].metadata["convert"](value)
        except ValueError as exc:
            raise UvmsInputError(str(exc), path=f"{prefix}.{key}") from None
    return cls(**values)


def parameter_table(cls) -> list[tuple[str, Any, str]]:
    """``(name, default, description)`` of every field of a parameter dataclass (for docs and help)."""
    return [(f.name, f.default, f.metadata["doc"]) for f in fields(cls)]


def number(value: Any) -> float:
    """A finite real number (booleans refused)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"expected a finite number, found {value!r}")
    return float(value)


def positive(value: Any) -> float:
    x = number(value)
    if x <= 0:
        raise ValueError(f"expected a number > 0, found {value!r}")
    return x


def non_negative(value: Any) -> float:
    x = number(value)
    if x < 0:
        raise ValueError(f"expected a number >= 0, found {value!r}")
    return x


def at_least_one(value: Any) -> float:
    x = number(value)
    if x < 1:
        raise ValueError(f"expected a number >= 1, found {value!r}")
    return x


def non_negative_integer(value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
        raise ValueError(f"expected an integer >= 0, found {value!r}")
    return int(value)


def vector(n: int, check: Callable[[Any], float] = number, *, scalar: bool = False) -> Callable[[Any], tuple]:
    """A converter accepting a list of ``n`` values (each passed through ``check``), or one if ``scalar``."""

    def convert(value: Any) -> tuple[float, ...]:
        if scalar and not isinstance(value, (list, tuple, np.ndarray)):
            return (check(value),) * n
        if not isinstance(value, (list, tuple, np.ndarray)) or len(value) != n:
            raise ValueError(f"expected {'a number or ' if scalar else ''}a list of {n} numbers, found {value!r}")
        return tuple(check(x) for x in value)

    return convert


def bounds(value: Any) -> tuple[float, float]:
    """``[b_min, b_max]`` with ``0 < b_min <= b_max``."""
    lo, hi = vector(2, positive)(value)
    if lo > hi:
        raise ValueError(f"expected [b_min, b_max] with b_min <= b_max, found {value!r}")
    return lo, hi


def choice(*options: str) -> Callable[[Any], str]:
    """A converter accepting one of ``options``."""

    def convert(value: Any) -> str:
        if value not in options:
            raise ValueError(f"expected one of {', '.join(options)}, found {value!r}")
        return str(value)

    return convert


def optional(convert: Callable[[Any], Any]) -> Callable[[Any], Any]:
    """``convert``, or ``None`` passed through."""
    return lambda value: None if value is None else convert(value)
