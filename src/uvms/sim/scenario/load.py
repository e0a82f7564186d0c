"""Loading a scenario: the file (a bundled name or a path), its schema, its model, and the checks against it.

:func:`load_scenario` reads a YAML file, :func:`scenario_from_data` validates parsed data: the schema
(:mod:`uvms.sim.scenario.schema`), the model file it names (a path relative to the scenario, or a bundled
model) with its overrides, the vector lengths that depend on the model's joint count, then the pieces that can
refuse it only once built (:meth:`uvms.sim.scenario.build.Scenario.prebuild`: a trimmed start without a rest
attitude, an unknown controller or bad parameters). Every refusal is one :class:`~uvms.errors.UvmsInputError`
line naming the file and the field.
"""

from __future__ import annotations

import hashlib
import os
from importlib.resources import files
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from uvms.bundled import bundled_names, resolve_path
from uvms.errors import UvmsInputError
from uvms.model.load import bundled_models, load_model
from uvms.model.model import Model
from uvms.safe_yaml import read_yaml_mapping
from uvms.schema_base import sanitised_name, show, validation_input_error
from uvms.sim.scenario.build import Scenario, apply_overrides
from uvms.sim.scenario.schema import UNION_TAGS, ScenarioSpec

_SCENARIOS = files("uvms") / "scenarios"


def bundled_scenarios() -> list[str]:
    """Names of the scenarios shipped with uvms."""
    return bundled_names(_SCENARIOS)


def resolve_scenario_path(name_or_path: str | os.PathLike[str]) -> Path:
    """An existing file path as given, else the bundled scenario of that name."""
    return resolve_path(name_or_path, _SCENARIOS, "scenario")


def load_scenario(name_or_path: str | os.PathLike[str]) -> Scenario:
    """Load and validate a scenario: a bundled name (see :func:`bundled_scenarios`) or a YAML file path.

    Raises:
        UvmsInputError: missing file, YAML syntax error, invalid content, missing or invalid model file,
            torque or joint vectors of the wrong length, unknown controller (one-line message).
    """
    path = resolve_scenario_path(name_or_path)
    data = read_yaml_mapping(path, "scenario fields")
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:  # pragma: no cover - read_yaml read it a moment ago
        raise UvmsInputError(f"cannot read: {exc}", str(path)) from None
    return scenario_from_data(data, source=str(path), base_dir=path.parent, text=text, default_name=path.stem)


def scenario_from_data(data: Any, *, source: str | None = None, base_dir: str | os.PathLike[str] | None = None,
                       text: str | None = None, default_name: str = "scenario") -> Scenario:
    """Validate scenario ``data`` (the parsed YAML mapping); relative model paths and data files (a current
    field, a joint-motion table) resolve against ``base_dir`` (default: the working directory for the model,
    the folder of ``source`` for data files). ``text`` (default: a YAML dump of ``data``) is hashed and kept."""
    import yaml

    try:
        spec = ScenarioSpec.model_validate(data)
    except ValidationError as exc:
        raise validation_input_error(exc, source, schema=ScenarioSpec, union_tags=UNION_TAGS) from None
    if spec.name is None:
        spec = spec.model_copy(update={"name": sanitised_name(default_name, "scenario")})
    if text is None:
        text = yaml.safe_dump(data, sort_keys=False)
    model = _resolve_model(spec, source, Path(base_dir) if base_dir is not None else Path.cwd())
    _check_against_model(spec, model, source)
    _check_sensors(spec, model, source)
    scenario = Scenario(spec=spec, model=model, source=source, sha256=hashlib.sha256(text.encode()).hexdigest(),
                        text=text, folder=Path(base_dir) if base_dir is not None else None)
    scenario.prebuild()                # no rest attitude, unknown controller or bad parameters: fail now
    return scenario


def _resolve_model(spec: ScenarioSpec, source: str | None, base_dir: Path) -> Model:
    """Load ``spec.model`` (a path relative to ``base_dir``, or a bundled name) and apply the overrides."""
    candidate = Path(spec.model).expanduser()
    if not candidate.is_absolute():
        candidate = base_dir / candidate
    if candidate.exists():
        target: str | Path = candidate
    elif spec.model in bundled_models():
        target = spec.model
    else:
        raise UvmsInputError(f"no such model file {candidate} (nor a bundled model: {', '.join(bundled_models())})",
                             source, "model")
    try:
        model = load_model(target)
    except UvmsInputError as exc:
        raise UvmsInputError(str(exc), source, "model") from None
    return apply_overrides(model, spec.model_overrides)


def _check_against_model(spec: ScenarioSpec, model: Model, source: str | None) -> None:
    """Vector lengths that depend on the model's joint count ``n``."""
    n = model.n_joints
    vectors = spec.inputs.torque_vectors()
    vectors += [(f"initial_state.{k}", getattr(spec.initial_state, k)) for k in ("q", "qd")]
    if spec.inputs.joint_trajectory is not None:
        vectors += [(f"inputs.joint_trajectory.angles[{k}]", row)
                    for k, row in enumerate(spec.inputs.joint_trajectory.angles)]
    for path, values in vectors:
        if values is not None and len(values) != n:
            raise UvmsInputError(f"expected {n} values (one per joint of model {model.name!r}), found "
                                 f"{len(values)}: {show(list(values))}", source, path)


def _check_sensors(spec: ScenarioSpec, model: Model, source: str | None) -> None:
    """The ``sensors:`` against the model (bodies, joints) and the step and record grid (each period a whole
    multiple of the record period: :func:`uvms.sim.sensing.record_every_for`)."""
    from uvms.sim.scenario.sensor_specs import build_sensors
    from uvms.sim.sensing import record_every_for

    sensors = build_sensors(spec.sensors, model, source)
    record = spec.outputs.record_period
    try:
        record_every_for(sensors, spec.step, None if record is None else max(1, int(round(record / spec.step))))
    except UvmsInputError as exc:
        raise UvmsInputError(exc.message, source, exc.path) from None
    if sensors and spec.inputs.joint_motion is not None:
        raise UvmsInputError("expected no simulated sensors with a prescribed joint_motion (their truth needs the "
                             "free dynamics' acceleration)", source, "sensors")
