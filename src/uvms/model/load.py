"""Reading model files: bundled names or paths -> validated :class:`~uvms.model.model.Model`.

Every user-input problem (missing file, YAML syntax, schema violation) becomes a one-line
:class:`~uvms.errors.UvmsInputError`. :func:`read_yaml` and :func:`format_validation_error` are meant to be
reused for other input files (scenarios).
"""

from __future__ import annotations

import os
from importlib.resources import files
from pathlib import Path

from pydantic import BaseModel, ValidationError

from uvms import schema_base
from uvms.bundled import bundled_names, resolve_path
from uvms.errors import UvmsInputError
from uvms.model.model import Model
from uvms.model.schema import UNION_TAGS, ModelSpec, UrdfModelSpec
from uvms.safe_yaml import read_yaml, read_yaml_mapping  # noqa: F401  (read_yaml re-exported)

_MODELS = files("uvms.model") / "models"


def validation_input_error(exc: ValidationError, source: str | None, *,
                           schema: type[BaseModel] | None = None) -> UvmsInputError:
    """The first error of a pydantic ``ValidationError`` of a model file as a one-line :class:`UvmsInputError`
    (:func:`uvms.schema_base.validation_input_error` with the model schema's union tags).

    ``schema`` (the validated model class) lets unknown-key errors list the allowed keys.
    """
    return schema_base.validation_input_error(exc, source, schema=schema, union_tags=UNION_TAGS)


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


def load_model(name_or_path: str | os.PathLike[str], *, balance_inertia: bool | None = None,
               package_paths: dict[str, str | os.PathLike[str]] | None = None,
               allow_environment: bool | None = None, xacro_args: dict[str, str] | None = None,
               frame: str | None = None) -> Model:
    """Load a model: a bundled name (``"paper"``, see :func:`bundled_models`), a model YAML file, or a robot
    description (``.urdf``, ``.xacro``, ``.sdf``) whose root link is the vehicle (``docs/models.md``; a Gazebo
    file's plugin tags give its hydrodynamics and thrusters: "UUV Simulator and Gazebo files").

    The keywords (for robot descriptions; each replaces the model YAML's field of that name when given):
    ``balance_inertia`` accepts link inertias breaking the triangle inequality with their principal moments set
    to their mean (MuJoCo's ``balanceinertia``; one warning line names the links); ``package_paths``
    (``{package: folder}``), ``allow_environment`` and ``xacro_args`` say what a xacro may read beyond its own
    folder (``docs/models.md``, "What a xacro may do"). ``frame`` (``"ned"`` or ``"enu"``, for any model file)
    says which convention the file's numbers are written in (``docs/conventions.md``, "Frames"): a bare ROS URDF
    is ``frame="enu"`` (world z up, base_link forward-left-up); default: the file's ``frame:`` key, else ned
    (enu for a robot description with Gazebo plugin tags and for every SDF file).

    Raises:
        UvmsInputError: missing file, YAML or XML syntax error or invalid content (one-line message).
    """
    from uvms.frames import check_frame
    from uvms.model.sdf import is_sdf
    from uvms.model.urdf import VehicleExtras, is_robot_description, model_from_urdf
    from uvms.model.xacro import XacroOptions

    if frame is not None:
        check_frame(frame, "load_model(frame=...)")
    options = {key: value for key, value in (("balance_inertia", balance_inertia), ("package_paths", package_paths),
               ("allow_environment", allow_environment), ("xacro_args", xacro_args), ("frame", frame))
               if value is not None}
    if is_robot_description(name_or_path) and Path(name_or_path).exists():
        xacro = XacroOptions(package_paths=dict(options.get("package_paths", {})),
                             allow_environment=bool(options.get("allow_environment", False)),
                             args=dict(options.get("xacro_args", {})))
        extras = VehicleExtras(frame=frame, gravity=None, density=None, current=None)
        if is_sdf(name_or_path):
            from uvms.model.sdf import model_from_sdf

            return model_from_sdf(name_or_path, extras, balance_inertia=bool(balance_inertia))
        return model_from_urdf(name_or_path, extras, xacro=xacro, balance_inertia=bool(balance_inertia))
    key = (_file_key(resolve_model_path(name_or_path)), repr(sorted(options.items())))
    hit = _LOADED.get(key)
    if hit is not None and all(_file_key(path) == stat for path, stat in hit[1]):
        return hit[0]
    model, robot = _load_model_file(name_or_path, options)
    if len(_LOADED) >= _MAX_LOADED:
        _LOADED.pop(next(iter(_LOADED)))
    _LOADED[key] = (model, tuple((path, _file_key(path)) for path in robot))
    return model


_LOADED: dict[tuple, tuple] = {}
"""Models already built from a file: ``((path, mtime, size), keywords) -> (model, ((robot description, its key),
...))``.
A model is immutable, so a sweep's thousand runs of one model file build it once; an edited file (or an edited
URDF it names) is read again."""
_MAX_LOADED = 32


def _absolute_packages(options: dict) -> dict:
    """:func:`load_model`'s keywords as spec fields (package folders made absolute: a YAML's own are relative
    to the YAML file, the caller's to the working directory)."""
    out = dict(options)
    if "package_paths" in out:
        out["package_paths"] = {str(k): str(Path(v).resolve()) for k, v in out["package_paths"].items()}
    if "xacro_args" in out:
        out["xacro_args"] = {str(k): str(v) for k, v in out["xacro_args"].items()}
    return out


def _file_key(path) -> tuple:
    try:
        st = os.stat(path)
    except OSError:
        return (str(path), None, None)
    return (str(Path(path).resolve()), st.st_mtime_ns, st.st_size)


def _load_model_file(name_or_path, options: dict | None = None) -> tuple[Model, tuple]:
    """The model of a YAML file (bundled name or path) and the robot description files it was built from;
    ``options`` (keywords of :func:`load_model`) replace the fields of a URDF model YAML; the file's
    ``identified.parameters`` are set on the built model (:func:`uvms.model.parameters.with_parameters`)."""
    spec, source = load_model_spec(name_or_path)
    model, robot = _built(spec, source, options)
    if spec.identified.parameters:
        from uvms.model.parameters import with_parameters

        try:
            model = with_parameters(model, spec.identified.parameters, "identified.parameters")
        except UvmsInputError as exc:
            raise UvmsInputError(exc.message, source, exc.path) from None
    return model, robot


def _built(spec, source, options: dict | None) -> tuple[Model, tuple]:
    from uvms.model.build import build_model, build_urdf_model  # brings the kernels: only once a file has parsed
    from uvms.model.urdf import is_robot_description

    try:
        if isinstance(spec, UrdfModelSpec):
            if options:
                spec = spec.model_copy(update=_absolute_packages(options))
            urdf = Path(spec.urdf)
            if not urdf.is_absolute():
                urdf = Path(source).parent / urdf
            if not is_robot_description(urdf):
                raise UvmsInputError(f"expected a .urdf, .xacro or .sdf file, found {spec.urdf!r}", source, "urdf")
            if not urdf.exists():
                raise UvmsInputError(f"no such file: {urdf}", source, "urdf")
            return build_urdf_model(spec, urdf, source, frozenset(options or ())), (urdf,)
        if options and "frame" in options:
            spec = spec.model_copy(update={"frame": options["frame"]})
        return build_model(spec, source), ()
    except UvmsInputError as exc:   # checks made while building (thruster parameters...) name the file too
        if exc.source is not None:
            raise
        raise UvmsInputError(exc.message, source, exc.path) from None
