"""The one validation kit of uvms's input files: model, scenario and sweep files (pydantic v2).

Every schema derives from :class:`Spec` (frozen, unknown keys rejected, no NaN or infinity), writes its numbers
with the field types below, raises :func:`fail` from its own validators, and turns a pydantic failure into one
line with :func:`validation_input_error`. One strictness for every file (``docs/conventions.md``, "Input
files"): a number is a YAML number, never a string. The shared YAML loader (:mod:`uvms.safe_yaml`) reads
``1e-3`` as a float, so the quoted ``"1e-3"`` is a string and is refused like ``"fast"``; booleans are refused
too (YAML reads ``yes``/``on``/``true`` as booleans).

    class CaseSpec(Spec):
        duration: Positive
        offset: Vec3 = ZERO3

    try:
        CaseSpec.model_validate(data)
    except ValidationError as exc:
        raise validation_input_error(exc.errors(), "case.yaml", schema=CaseSpec) from None
"""

from __future__ import annotations

import math
import re
import types
import typing
from collections.abc import Iterable, Sequence
from typing import Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, Strict, ValidationError
from pydantic_core import ErrorDetails, PydanticCustomError

from uvms.errors import UvmsInputError, show

__all__ = [
    "Spec", "fail", "show", "finite_number", "is_number", "numbers", "matrix", "Number", "Positive", "NonNegative",
    "Vec3", "NonNegativeVec3", "Vec6", "Vector", "Mat3", "Mat6", "Name", "RunName", "ZERO3", "ZERO6",
    "run_name", "sanitised_name", "validation_input_error", "field_path",
]


class Spec(BaseModel):
    """Base of every schema model of every input file: frozen, unknown keys rejected, no NaN or infinity."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


def fail(message: str, subpath: str | int = "") -> PydanticCustomError:
    """A validation error with a complete message; ``subpath`` (e.g. ``"diagonal"`` or a list index) extends
    the field path of the value being validated."""
    return PydanticCustomError("uvms", "{message}", {"message": message, "subpath": subpath})


# ---------------------------------------------------------------------------------------------- numbers


def is_number(value: Any) -> bool:
    """A finite int or float (not a boolean, not a string)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def finite_number(value: Any) -> float:
    """``value`` as a float if it is a finite YAML number, else a :func:`fail` saying what was expected."""
    if is_number(value):
        return float(value)
    if isinstance(value, bool):
        raise fail(f"expected a number, found {show(value)} (YAML reads true/false, yes/no, on/off as booleans)")
    raise fail(f"expected a finite number, found {show(value)}")


def numbers(size: int | None = None, *, minimum: float | None = None, what: str = "") -> BeforeValidator:
    """A list of finite numbers (exactly ``size`` of them if given, else at least one; each ``>= minimum`` if
    given) accepted as a tuple of floats; ``what`` replaces the default description in the message."""
    expected = what or ("a list of " + (f"{size} " if size else "") + "finite numbers"
                        + ("" if minimum is None else f" >= {minimum:g}"))

    def check(value: Any) -> tuple[float, ...]:
        if (isinstance(value, (list, tuple)) and (len(value) == size if size else len(value) > 0)
                and all(is_number(x) for x in value) and (minimum is None or all(x >= minimum for x in value))):
            return tuple(float(x) for x in value)
        raise fail(f"expected {expected}, found {show(value)}")

    return BeforeValidator(check)


def matrix(n: int) -> BeforeValidator:
    """An ``n`` x ``n`` nested list of finite numbers accepted as a tuple of row tuples."""

    def check(value: Any) -> tuple[tuple[float, ...], ...]:
        if isinstance(value, (list, tuple)) and len(value) == n and all(
                isinstance(row, (list, tuple)) and len(row) == n and all(is_number(x) for x in row) for row in value):
            return tuple(tuple(float(x) for x in row) for row in value)
        raise fail(f"expected a {n}x{n} matrix (a list of {n} rows of {n} finite numbers), found {show(value)}")

    return BeforeValidator(check)


Number = Annotated[float, BeforeValidator(finite_number)]
Positive = Annotated[float, BeforeValidator(finite_number), Field(gt=0)]
NonNegative = Annotated[float, BeforeValidator(finite_number), Field(ge=0)]
Vec3 = Annotated[tuple[float, float, float], numbers(3)]
NonNegativeVec3 = Annotated[tuple[float, float, float], numbers(3, minimum=0.0)]
Vec6 = Annotated[tuple[float, float, float, float, float, float], numbers(6)]
Vector = Annotated[tuple[float, ...], numbers()]
Mat3 = Annotated[tuple[tuple[float, ...], ...], matrix(3)]
Mat6 = Annotated[tuple[tuple[float, ...], ...], matrix(6)]
Name = Annotated[str, Strict(), Field(min_length=1)]

ZERO3 = (0.0, 0.0, 0.0)
ZERO6 = ZERO3 + ZERO3

# ---------------------------------------------------------------------------------------------- names

_RUN_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._+-]{0,99}")


def run_name(value: Any) -> str:
    """A name that can name a run directory: up to 100 letters, digits and ``. _ + -``, not starting with a
    punctuation mark."""
    if isinstance(value, str) and _RUN_NAME.fullmatch(value):
        return value
    raise fail("expected a name of up to 100 letters, digits and . _ + - (it names the run directory), "
               f"found {show(value)}")


RunName = Annotated[str, BeforeValidator(run_name)]


def sanitised_name(text: str, fallback: str) -> str:
    """``text`` (a file name without extension) made a valid :data:`RunName`: other characters become ``_``,
    leading punctuation is dropped, at most 100 characters; ``fallback`` if nothing is left."""
    name = re.sub(r"[^A-Za-z0-9._+-]", "_", text).lstrip("._+-")[:100]
    return name or fallback


# ---------------------------------------------------------------------------------------------- errors


def _leaves(annotation: Any) -> list[Any]:
    """The model classes an annotation can hold (through Annotated, unions, tuples, lists and dicts)."""
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if origin is typing.Annotated:
        return _leaves(args[0])
    if origin in (typing.Union, types.UnionType, tuple, list):
        return [leaf for arg in args if arg is not Ellipsis for leaf in _leaves(arg)]
    return [annotation] if isinstance(annotation, type) and issubclass(annotation, BaseModel) else []


def _allowed_keys(schema: type[BaseModel], loc: Sequence[Any]) -> list[str]:
    """The keys the schema allows in the mapping that holds ``loc[-1]``."""
    models: list[Any] = [schema]
    for part in loc[:-1]:
        if isinstance(part, str):
            fields = [m.model_fields[part] for m in models if part in m.model_fields]
            models = [leaf for f in fields for leaf in _leaves(f.annotation)]
    return sorted(models[0].model_fields) if models else []


_BOUNDS = {"greater_than": (">", "gt"), "greater_than_equal": (">=", "ge"), "less_than": ("<", "lt"),
           "less_than_equal": ("<=", "le")}
_KINDS = {"float_type": "a number", "float_parsing": "a number", "int_type": "a whole number",
          "int_parsing": "a whole number", "int_from_float": "a whole number", "finite_number": "a finite number",
          "model_type": "a mapping", "model_attributes_type": "a mapping", "dict_type": "a mapping",
          "tuple_type": "a list", "list_type": "a list", "string_type": "a string",
          "string_too_short": "a non-empty string"}


def _describe(error: ErrorDetails, schema: type[BaseModel] | None) -> str:
    """What was expected and what was found, for one pydantic error."""
    kind, ctx, found = error["type"], error.get("ctx", {}), show(error.get("input"))
    if kind == "uvms":
        return ctx["message"]
    if kind == "missing":
        return "expected a value (required field), found none"
    if kind == "extra_forbidden":
        allowed = _allowed_keys(schema, error["loc"]) if schema is not None else []
        return "unknown key" + (f"; expected one of: {', '.join(allowed)}" if allowed else "")
    if kind in _BOUNDS:
        op, bound = _BOUNDS[kind]
        return f"expected a number {op} {ctx[bound]:g}, found {found}"
    if kind == "literal_error":
        return f"expected {ctx['expected']}, found {found}"
    if kind in _KINDS:
        return f"expected {_KINDS[kind]}, found {found}"
    message = error["msg"]
    return f"{message[:1].lower()}{message[1:]}, found {found}"


def field_path(error: ErrorDetails, union_tags: Iterable[str] = ()) -> str:
    """Dotted path such as ``arm.links[1].inertia.diagonal`` of one pydantic error (the tags of tagged unions,
    ``union_tags``, left out; a :func:`fail` ``subpath`` appended)."""
    tags = set(union_tags)
    loc = [part for part in error["loc"] if not (isinstance(part, str) and part in tags)]
    subpath = error.get("ctx", {}).get("subpath") if error["type"] == "uvms" else None
    if subpath not in (None, ""):
        loc.append(subpath)
    path = ""
    for part in loc:
        path += f"[{part}]" if isinstance(part, int) else (f".{part}" if path else str(part))
    return path or "(top level)"


def validation_input_error(errors: ValidationError | Sequence[ErrorDetails], source: str | None, *,
                           schema: type[BaseModel] | None = None,
                           union_tags: Iterable[str] = ()) -> UvmsInputError:
    """The first of pydantic's ``errors`` (a list, or a ``ValidationError``) as a one-line
    :class:`~uvms.errors.UvmsInputError` naming ``source`` and the field path.

    Unknown keys come first (a typo'd key also makes its intended field "missing": the typo is the one to
    report); ``schema`` (the validated model class) lets an unknown-key error list the allowed keys;
    ``union_tags`` are left out of field paths.
    """
    listed = list(errors.errors() if isinstance(errors, ValidationError) else errors)
    listed.sort(key=lambda e: e["type"] != "extra_forbidden")
    first = listed[0]
    message = _describe(first, schema)
    if len(listed) > 1:
        message += f" (and {len(listed) - 1} more error{'s' if len(listed) > 2 else ''})"
    return UvmsInputError(message, source, field_path(first, union_tags))
