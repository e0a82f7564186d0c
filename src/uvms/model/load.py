"""Reading model files: bundled names or paths -> validated :class:`~uvms.model.model.Model`.

Every user-input problem (missing file, YAML syntax, schema violation) becomes a one-line
:class:`~uvms.errors.UvmsInputError`. :func:`read_yaml` and :func:`format_validation_error` are meant to be
reused for other input files (scenarios).
"""

from __future__ import annotations

import os
import types
import typing
from importlib.resources import files
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ValidationError
from pydantic_core import ErrorDetails

from uvms.bundled import bundled_names, resolve_path
from uvms.errors import UvmsInputError
from uvms.model.build import build_model, build_urdf_model
from uvms.model.model import Model
from uvms.model.schema import UNION_TAGS, ModelSpec, UrdfModelSpec, show
from uvms.safe_yaml import read_yaml, read_yaml_mapping  # noqa: F401  (read_yaml re-exported)

_MODELS = files("uvms.model") / "models"


def _leaves(annotation: Any) -> list[Any]:
    """The model classes an annotation can hold (through Annotated, unions, tuples and lists)."""
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if origin is typing.Annotated:
        return _leaves(args[0])
    if origin in (typing.Union, types.UnionType, tuple, list):
        return [leaf for arg in args if arg is not Ellipsis for leaf in _leaves(arg)]
    return [annotation] if isinstance(annotation, type) and issubclass(annotation, BaseModel) else []


def _allowed_keys(schema: type[BaseModel], loc: tuple[Any, ...]) -> list[str]:
    """The keys the schema allows in the mapping that holds ``loc[-1]``."""
    models: list[Any] = [schema]
    for part in loc[:-1]:
        if isinstance(part, str):
            fields = [m.model_fields[part] for m in models if part in m.model_fields]
            models = [leaf for f in fields for leaf in _leaves(f.annotation)]
    return sorted(models[0].model_fields) if models else []


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
    if kind in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        op, bound = {"greater_than": (">", "gt"), "greater_than_equal": (">=", "ge"), "less_than": ("<", "lt"),
                     "less_than_equal": ("<=", "le")}[kind]
        return f"expected a number {op} {ctx[bound]:g}, found {found}"
    if kind in ("float_type", "float_parsing"):
        return f"expected a number, found {found}"
    if kind in ("int_type", "int_parsing", "int_from_float"):
        return f"expected a whole number, found {found}"
    if kind == "finite_number":
        return f"expected a finite number, found {found}"
    if kind == "literal_error":
        return f"expected {ctx['expected']}, found {found}"
    if kind in ("model_type", "model_attributes_type", "dict_type"):
        return f"expected a mapping, found {found}"
    if kind in ("tuple_type", "list_type"):
        return f"expected a list, found {found}"
    if kind == "string_type":
        return f"expected a string, found {found}"
    if kind == "string_too_short":
        return f"expected a non-empty string, found {found}"
    message = error["msg"]
    return f"{message[:1].lower()}{message[1:]}, found {found}"


def _field_path(error: ErrorDetails) -> str:
    """Dotted path such as ``arm.links[1].inertia.diagonal`` (union tags left out)."""
    loc = [part for part in error["loc"] if part not in UNION_TAGS]
    subpath = error.get("ctx", {}).get("subpath") if error["type"] == "uvms" else None
    if subpath:
        loc.append(subpath)
    path = ""
    for part in loc:
        path += f"[{part}]" if isinstance(part, int) else (f".{part}" if path else str(part))
    return path or "(top level)"


def validation_input_error(exc: ValidationError, source: str | None, *,
                           schema: type[BaseModel] | None = None) -> UvmsInputError:
    """The first error of a pydantic ``ValidationError`` as a one-line :class:`UvmsInputError`.

    ``schema`` (the validated model class) lets unknown-key errors list the allowed keys.
    """
    errors = exc.errors()
    message = _describe(errors[0], schema)
    if len(errors) > 1:
        message += f" (and {len(errors) - 1} more error{'s' if len(errors) > 2 else ''})"
    return UvmsInputError(message, source, _field_path(errors[0]))


def format_validation_error(exc: ValidationError, source: str | None, *,
                            schema: type[BaseModel] | None = None) -> str:
    """One line ``"<source>: <field.path>: <expected, found>"`` for a pydantic ``ValidationError``."""
    return str(validation_input_error(exc, source, schema=schema))


def bundled_models() -> list[str]:
    """Names of the models shipped with uvms."""
    return bundled_names(_MODELS)


def resolve_model_path(name_or_path: str | os.PathLike[str]) -> Path:
    """An existing file path as given, else the bundled model of that name."""
    return resolve_path(name_or_path, _MODELS, "model")


def load_model_spec(name_or_path: str | os.PathLike[str]) -> tuple[ModelSpec | UrdfModelSpec, str]:
    """The validated spec of a bundled name or a YAML path, and the file it came from: a
    :class:`ModelSpec`, or a :class:`UrdfModelSpec` when the file has a ``urdf`` key."""
    path = resolve_model_path(name_or_path)
    source = str(path)
    data = read_yaml_mapping(path, "model fields")
    schema = UrdfModelSpec if "urdf" in data else ModelSpec
    try:
        return schema.model_validate(data), source
    except ValidationError as exc:
        raise validation_input_error(exc, source, schema=schema) from None


def load_model(name_or_path: str | os.PathLike[str]) -> Model:
    """Load a model: a bundled name (``"paper"``, see :func:`bundled_models`), a model YAML file, or a robot
    description (``.urdf``, ``.xacro``) whose root link is the vehicle (``docs/models.md``).

    Raises:
        UvmsInputError: missing file, YAML or XML syntax error or invalid content (one-line message).
    """
    from uvms.model.urdf import is_robot_description, model_from_urdf

    if is_robot_description(name_or_path) and Path(name_or_path).exists():
        return model_from_urdf(name_or_path)
    spec, source = load_model_spec(name_or_path)
    try:
        if isinstance(spec, UrdfModelSpec):
            urdf = Path(spec.urdf)
            if not urdf.is_absolute():
                urdf = Path(source).parent / urdf
            if not is_robot_description(urdf):
                raise UvmsInputError(f"expected a .urdf or .xacro file, found {spec.urdf!r}", source, "urdf")
            if not urdf.exists():
                raise UvmsInputError(f"no such file: {urdf}", source, "urdf")
            return build_urdf_model(spec, urdf, source)
        return build_model(spec, source)
    except UvmsInputError as exc:   # checks made while building (thruster parameters...) name the file too
        if exc.source is not None:
            raise
        raise UvmsInputError(exc.message, source, exc.path) from None
