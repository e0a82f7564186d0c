"""Sweep files: a base scenario, parameters gridded or drawn at dotted paths, controllers, metrics.

A sweep file is validated like a scenario file (pydantic v2, unknown keys rejected, one-line errors naming the
file and the field path), then its first run per controller is checked as a full scenario, so that a
misspelt parameter path or controller parameter fails before anything runs. ``docs/sweeps.md`` documents
the format; ``uvms/sweeps/*.yaml`` are bundled examples, loadable by name.

Runs: the grid parameters (a list, ``{grid: [...]}`` or ``{value: x}``) form a Cartesian product; at every
grid point ``runs`` random draws of the random parameters (``uniform``, ``normal``, ``choice``,
``uniform_vector``) are made. Draw ``r`` of parameter ``p`` comes from its own generator seeded with
``(seed, r, crc32(p))``: the same file always gives the same values, every grid point sees the same random
values (common random numbers), and adding a parameter leaves the others' values unchanged. Each parameter
set is run once per controller (a paired comparison).
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
import math
import os
import re
import zlib
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path
from typing import Annotated, Any, ClassVar

import numpy as np
from pydantic import (
    AfterValidator,
    BeforeValidator,
    Field,
    PlainValidator,
    Strict,
    ValidationError,
    field_validator,
    model_validator,
)

from uvms.bundled import bundled_names, resolve_path
from uvms.errors import UvmsInputError
from uvms.model.load import read_yaml
from uvms.safe_yaml import read_yaml_mapping
from uvms.schema_base import RunName, Spec, Vector, fail, numbers, sanitised_name, show, validation_input_error
from uvms.sim.scenario import Scenario, resolve_scenario_path, scenario_from_data

_SWEEPS = files("uvms") / "sweeps"

FORMAT_VERSION = 1
MAX_RUNS = 1_000_000
"""Most runs in one sweep (grid points x ``runs`` x controllers), checked before any run is built: at the
paper's 1.6 s per run this is about 18 CPU-days; split a larger study into several sweeps."""
"""Version of the ``runs.csv`` / ``sweep.json`` layout; part of the sweep hash."""

MAX_PATH = 200
"""Longest parameter path (a key of ``parameters``)."""
MAX_ENTRIES = 1000
"""Most parameters, controllers or metrics in one sweep file."""
_SEGMENT = r"[A-Za-z_][A-Za-z0-9_-]*(?:\[\d+\])*"
_PATH = re.compile(rf"{_SEGMENT}(?:\.{_SEGMENT})*")

# ---------------------------------------------------------------------------------------------- distributions


def _values(value: Any) -> tuple[Any, ...]:
    if isinstance(value, (list, tuple)) and len(value) > 0:
        return tuple(value)
    raise fail(f"expected a non-empty list of values, found {show(value)}")


class Distribution(Spec):
    """A parameter's values: random (``sample``) or a grid (``values``)."""

    random: ClassVar[bool] = False

    def sample(self, rng: np.random.Generator) -> Any:  # pragma: no cover - overridden by random forms
        raise NotImplementedError

    @property
    def values(self) -> tuple[Any, ...]:  # pragma: no cover - overridden by grid forms
        raise NotImplementedError


class Uniform(Distribution):
    """``{uniform: [low, high]}``: uniform on ``[low, high]``."""

    uniform: Annotated[tuple[float, float], numbers(2, what="[low, high]")]
    random: ClassVar[bool] = True

    @field_validator("uniform")
    @classmethod
    def _ordered(cls, bounds: tuple[float, float]) -> tuple[float, float]:
        if bounds[0] > bounds[1]:
            raise fail(f"expected [low, high] with low <= high, found {show(list(bounds))}")
        return bounds

    def sample(self, rng: np.random.Generator) -> float:
        return float(rng.uniform(*self.uniform))


class Normal(Distribution):
    """``{normal: [mean, std]}``: Gaussian."""

    normal: Annotated[tuple[float, float], numbers(2, what="[mean, std]")]
    random: ClassVar[bool] = True

    @field_validator("normal")
    @classmethod
    def _std(cls, value: tuple[float, float]) -> tuple[float, float]:
        if value[1] < 0:
            raise fail(f"expected [mean, std] with std >= 0, found {show(list(value))}")
        return value

    def sample(self, rng: np.random.Generator) -> float:
        return float(rng.normal(*self.normal))


class Choice(Distribution):
    """``{choice: [a, b, ...]}``: one of the values, each equally likely."""

    choice: Annotated[tuple[Any, ...], BeforeValidator(_values)]
    random: ClassVar[bool] = True

    def sample(self, rng: np.random.Generator) -> Any:
        return self.choice[int(rng.integers(len(self.choice)))]


class VectorBounds(Spec):
    low: Vector
    high: Vector


class UniformVector(Distribution):
    """``{uniform_vector: {low: [...], high: [...]}}``: each component uniform on ``[low_i, high_i]``."""

    uniform_vector: VectorBounds
    random: ClassVar[bool] = True

    @field_validator("uniform_vector")
    @classmethod
    def _consistent(cls, b: VectorBounds) -> VectorBounds:
        if len(b.low) != len(b.high):
            raise fail(f"expected as many values as 'low' ({len(b.low)}), found {len(b.high)}", "high")
        if any(lo > hi for lo, hi in zip(b.low, b.high)):
            raise fail(f"expected high >= low component by component, found {show(list(b.high))}", "high")
        return b

    def sample(self, rng: np.random.Generator) -> list[float]:
        return [float(x) for x in rng.uniform(self.uniform_vector.low, self.uniform_vector.high)]


class Grid(Distribution):
    """``{grid: [a, b, ...]}`` or a plain list: every value, crossed with the other grid parameters."""

    grid: Annotated[tuple[Any, ...], BeforeValidator(_values)]

    @property
    def values(self) -> tuple[Any, ...]:
        return self.grid


class Value(Distribution):
    """``{value: x}``: one fixed value (a grid of one)."""

    value: Any

    @property
    def values(self) -> tuple[Any, ...]:
        return (self.value,)


FORMS: dict[str, type[Distribution]] = {"uniform": Uniform, "normal": Normal, "choice": Choice,
                                        "uniform_vector": UniformVector, "grid": Grid, "value": Value}
"""The distribution forms by their key."""


def _distribution(value: Any) -> Distribution:
    """Parse one ``parameters`` entry: a plain list is a grid, a scalar a fixed value, a mapping has exactly one
    key of :data:`FORMS`."""
    if isinstance(value, Distribution):
        return value
    if isinstance(value, (list, tuple)):
        value = {"grid": list(value)}
    elif isinstance(value, (int, float, str)):  # bool is an int
        value = {"value": value}
    if not (isinstance(value, dict) and len(value) == 1 and next(iter(value)) in FORMS):
        raise fail(f"expected a number or string (a fixed value), a list (a grid) or a mapping with one key of: "
                   f"{', '.join(FORMS)}; found {show(value)}")
    try:
        return FORMS[next(iter(value))].model_validate(value)
    except ValidationError as exc:
        error = validation_input_error(exc, None, schema=FORMS[next(iter(value))])
        raise fail(error.message, "" if error.path == "(top level)" else (error.path or "")) from None


def _jsonable(value: Any, where: str) -> None:
    try:
        json.dumps(value, allow_nan=False)
    except (TypeError, ValueError):
        raise fail(f"expected plain YAML values (numbers, strings, lists, mappings), found {show(value)}",
                   where) from None


def _metric(name: str) -> str:
    from uvms.sweep.metrics import check_metric

    try:
        check_metric(name)
    except ValueError as exc:
        raise fail(str(exc)) from None
    return name


# ---------------------------------------------------------------------------------------------- schema


class SweepSpec(Spec):
    """A whole sweep file."""

    name: RunName | None = None                    # default: the file name without .yaml
    description: str | None = None
    base: Annotated[str, Field(min_length=1)]      # a scenario: bundled name or path (relative: to this file)
    runs: Annotated[int, Strict(), Field(ge=1, le=1_000_000)] = 1  # random draws per grid point (true is no count)
    seed: Annotated[int, Strict(), Field(ge=0)] = 0
    controllers: tuple[Annotated[str, Field(min_length=1)], ...] | None = None  # default: the base's controller
    parameters: dict[str, Annotated[Distribution, PlainValidator(_distribution)]] = {}
    metrics: tuple[Annotated[str, AfterValidator(_metric)], ...] | None = None  # default: metrics.default_metrics

    @model_validator(mode="before")
    @classmethod
    def _sizes(cls, data: Any) -> Any:
        """Refuse over-long lists before any entry is validated."""
        if isinstance(data, dict):
            for field in ("parameters", "controllers", "metrics"):
                value = data.get(field)
                if isinstance(value, (dict, list, tuple)) and len(value) > MAX_ENTRIES:
                    raise fail(f"expected at most {MAX_ENTRIES} {field}, found {len(value)}", field)
        return data

    @field_validator("controllers")
    @classmethod
    def _controllers(cls, names: tuple[str, ...] | None) -> tuple[str, ...] | None:
        if names is not None:
            if not names:
                raise fail("expected a non-empty list of controller names (or leave the key out)")
            _once(names, "controller")
        return names

    @field_validator("parameters")
    @classmethod
    def _paths(cls, parameters: dict[str, Distribution]) -> dict[str, Distribution]:
        if len(parameters) > MAX_ENTRIES:
            raise fail(f"expected at most {MAX_ENTRIES} parameters, found {len(parameters)}")
        keys = set(parameters)
        for key in parameters:
            if len(key) > MAX_PATH:
                raise fail(f"expected a field path of at most {MAX_PATH} characters, found {len(key)}",
                           show(key, 60)[1:-1])
            if not _PATH.fullmatch(key):
                raise fail("expected a dotted field path such as controller.parameters.hydro_scale or "
                           "inputs.joint_torques[0].torques", key)
            for cut in (m.start() for m in re.finditer(r"[.\[]", key)):  # every shorter path on the way to key
                if key[:cut] in keys:
                    raise fail(f"overlaps parameter {show(key)}: set one or the other", key[:cut])
            d = parameters[key]
            for k, v in enumerate(d.values if not d.random else getattr(d, "choice", ())):
                _jsonable(v, f"{key}[{k}]")
        return parameters

    @field_validator("metrics")
    @classmethod
    def _metrics(cls, names: tuple[str, ...] | None) -> tuple[str, ...] | None:
        if names is not None:
            if not names:
                raise fail("expected a non-empty list of metric names (or leave the key out for the default set)")
            _once(names, "metric")
        return names


def _once(names: tuple[str, ...], what: str) -> None:
    """Refuse more than :data:`MAX_ENTRIES` names, or a name listed twice (in linear time)."""
    if len(names) > MAX_ENTRIES:
        raise fail(f"expected at most {MAX_ENTRIES} {what}s, found {len(names)}")
    seen: set[str] = set()
    for k, name in enumerate(names):
        if name in seen:
            raise fail(f"expected each {what} once, found {show(name)} twice", k)
        seen.add(name)


# ---------------------------------------------------------------------------------------------- sweep


@dataclass(frozen=True)
class SweepRun:
    """One run of a sweep: a parameter set (draw ``draw``) with one controller.

    Attributes:
        run_id: ``<draw>-<controller>-<hash>``, stable: the same sweep file always gives the same ids.
        draw: index of the parameter set (shared by the controllers: a paired comparison).
        controller: the controller name (``None``: the base scenario's own controller, or none).
        parameters: dotted path -> value.
    """

    run_id: str
    draw: int
    controller: str | None
    parameters: dict[str, Any]


@dataclass(frozen=True, eq=False)
class Sweep:
    """A validated sweep file with its base scenario and every run.

    Attributes:
        spec: the validated file content.
        base: the base scenario (as loaded, before any parameter is applied).
        base_data: the base scenario's parsed YAML mapping.
        base_dir: folder that relative model paths in the base scenario resolve against.
        runs: every run, in order (draw-major, then controller).
        source: the sweep file (``None`` when built from data).
        sha256: hash of the validated content and the base scenario's text (resume refuses another hash).
        text: the sweep file's text.
    """

    spec: SweepSpec
    base: Scenario
    base_data: dict[str, Any]
    base_dir: str
    runs: tuple[SweepRun, ...]
    source: str | None
    sha256: str
    text: str

    @property
    def name(self) -> str:
        return self.spec.name or "sweep"

    @property
    def metrics(self) -> tuple[str, ...]:
        from uvms.sweep.metrics import default_metrics

        return self.spec.metrics or default_metrics(controlled=self.controlled)

    @property
    def controlled(self) -> bool:
        """Whether the runs have a controller."""
        return self.spec.controllers is not None or self.base.spec.controller is not None

    def scenario_data(self, run: SweepRun) -> dict[str, Any]:
        """The base scenario's data with the run's controller and parameters applied."""
        data = copy.deepcopy(self.base_data)
        if run.controller is not None:
            controller = data.get("controller")
            data["controller"] = {**controller, "name": run.controller} if isinstance(controller, dict) else {
                "name": run.controller}
        for path, value in run.parameters.items():
            set_path(data, path, copy.deepcopy(value))
        return data


def parameter_sets(spec: SweepSpec) -> list[dict[str, Any]]:
    """Every parameter set: the grid points (Cartesian product, file order) x ``runs`` random draws."""
    grid = [(k, d.values) for k, d in spec.parameters.items() if not d.random]
    random = [(k, d) for k, d in spec.parameters.items() if d.random]
    draws = []
    for r in range(spec.runs):
        draws.append({k: d.sample(np.random.default_rng([spec.seed, r, zlib.crc32(k.encode())])) for k, d in random})
    sets = []
    for point in itertools.product(*(values for _, values in grid)):
        fixed = {k: v for (k, _), v in zip(grid, point)}
        for draw in draws:
            merged = {**fixed, **draw}
            sets.append({k: merged[k] for k in spec.parameters})  # file order
    return sets


def make_runs(spec: SweepSpec) -> tuple[SweepRun, ...]:
    """Every run: each parameter set once per controller, with its stable ``run_id``."""
    sets = parameter_sets(spec)
    width = max(4, len(str(len(sets) - 1)))
    runs = []
    for draw, parameters in enumerate(sets):
        for controller in spec.controllers or (None,):
            digest = hashlib.sha256(json.dumps([draw, controller, parameters], sort_keys=True).encode()).hexdigest()
            label = controller or "base"
            runs.append(SweepRun(f"{draw:0{width}d}-{label}-{digest[:8]}", draw, controller, parameters))
    return tuple(runs)


def bundled_sweeps() -> list[str]:
    """Names of the sweeps shipped with uvms."""
    return bundled_names(_SWEEPS)


def resolve_sweep_path(name_or_path: str | os.PathLike[str]) -> Path:
    """An existing file path as given, else the bundled sweep of that name."""
    return resolve_path(name_or_path, _SWEEPS, "sweep")


def load_sweep(name_or_path: str | os.PathLike[str]) -> Sweep:
    """Load and validate a sweep file: a bundled name (see :func:`bundled_sweeps`) or a YAML file path.

    Raises:
        UvmsInputError: missing file, YAML syntax error, invalid content, a parameter path or value that the
            base scenario rejects, unknown controller or metric (one-line message).
    """
    path = resolve_sweep_path(name_or_path)
    data = read_yaml_mapping(path, "sweep fields")
    text = path.read_text(encoding="utf-8")
    return sweep_from_data(data, source=str(path), base_dir=path.parent, text=text, default_name=path.stem)


def sweep_from_data(data: Any, *, source: str | None = None, base_dir: str | os.PathLike[str] | None = None,
                    text: str | None = None, default_name: str = "sweep") -> Sweep:
    """Validate sweep ``data`` (the parsed YAML mapping); a relative ``base`` path resolves against ``base_dir``
    (default: the working directory)."""
    import yaml

    if not isinstance(data, dict):
        found = "an empty file" if data is None else show(data)
        raise UvmsInputError(f"expected a mapping of sweep fields at the top level, found {found}", source)
    try:
        spec = SweepSpec.model_validate(data)
    except ValidationError as exc:
        raise validation_input_error(exc, source, schema=SweepSpec) from None
    if spec.name is None:
        spec = spec.model_copy(update={"name": sanitised_name(default_name, "sweep")})
    _check_size(spec, source)
    if spec.runs > 1 and not any(d.random for d in spec.parameters.values()):
        raise UvmsInputError(f"expected runs: 1 when no parameter is random (all {spec.runs} draws would be the "
                             "same)", source, "runs")
    if spec.controllers is not None:
        from uvms.control.registry import controller_names

        known = controller_names()
        for k, name in enumerate(spec.controllers):
            if name not in known:
                raise UvmsInputError(f"unknown controller {name!r}; expected one of: {', '.join(known)}", source,
                                     f"controllers[{k}]")
        if "controller.name" in spec.parameters:
            raise UvmsInputError("sets the controller's name, which 'controllers' already chooses; use one of them",
                                 source, "parameters.controller.name")

    folder = Path(base_dir) if base_dir is not None else Path.cwd()
    candidate = Path(spec.base).expanduser()
    candidate = candidate if candidate.is_absolute() else folder / candidate
    try:
        base_path = resolve_scenario_path(candidate if candidate.exists() else spec.base)
    except UvmsInputError as exc:
        raise UvmsInputError(exc.message, source, "base") from None
    try:
        base_data = read_yaml(base_path)
    except UvmsInputError as exc:
        raise UvmsInputError(f"{exc.source}: {exc.message}", source, "base") from None
    if not isinstance(base_data, dict):  # name the path and the kind, never the content of whatever file it is
        found = "an empty file" if base_data is None else f"a YAML {_kind(base_data)}"
        raise UvmsInputError(f"{base_path}: expected a scenario file (a mapping of scenario fields), found {found}",
                             source, "base")
    try:
        base = scenario_from_data(base_data, source=str(base_path), base_dir=base_path.parent,
                                  text=base_path.read_text(encoding="utf-8"), default_name=base_path.stem)
    except UvmsInputError as exc:
        raise UvmsInputError(f"base scenario is invalid: {exc}", source, "base") from None

    runs = make_runs(spec)
    content = {"format": FORMAT_VERSION, "sweep": spec.model_dump(mode="json", exclude={"parameters"}),
               "parameters": {k: d.model_dump(mode="json") for k, d in spec.parameters.items()},
               "base_sha256": base.sha256}
    digest = hashlib.sha256(json.dumps(content, sort_keys=True, default=str).encode()).hexdigest()
    if text is None:
        text = yaml.safe_dump(data, sort_keys=False)
    sweep = Sweep(spec=spec, base=base, base_data=base_data, base_dir=str(base_path.parent), runs=runs,
                  source=source, sha256=digest, text=text)
    _check_first_runs(sweep)
    return sweep


def run_count(spec: SweepSpec) -> int:
    """Runs the sweep ``spec`` makes: (product of the grid sizes) x ``runs`` x (number of controllers),
    computed without building any of them."""
    return math.prod(len(d.values) for d in spec.parameters.values() if not d.random) * spec.runs * len(
        spec.controllers or (None,))


def _check_size(spec: SweepSpec, source: str | None) -> None:
    """Refuse a sweep of more than :data:`MAX_RUNS` runs, before anything is built."""
    count = run_count(spec)
    if count <= MAX_RUNS:
        return
    grid = [f"{show(key, 40)[1:-1]} {len(d.values)}" for key, d in spec.parameters.items() if not d.random and len(d.values) > 1]
    factors = [*grid, *([f"runs {spec.runs}"] if spec.runs > 1 else []),
               *([f"{len(spec.controllers)} controllers"] if spec.controllers and len(spec.controllers) > 1 else [])]
    shown = " x ".join(factors[:6]) + (" x ..." if len(factors) > 6 else "")
    field = "parameters" if grid else ("runs" if spec.runs > 1 else "controllers")
    raise UvmsInputError(f"expected at most {MAX_RUNS:,} runs in one sweep, found {_count(count)} ({shown}); split "
                         "the sweep", source, field)


def _count(n: int) -> str:
    """A run count, exactly up to 10^15, else as a power of ten."""
    return f"{n:,}" if n < 10**15 else f"about 10^{len(str(n)) - 1}"


def _kind(value: Any) -> str:
    return {str: "string", list: "list", int: "number", float: "number", bool: "boolean"}.get(type(value), "value")


def _check_first_runs(sweep: Sweep) -> None:
    """Build the first run of each controller as a full scenario: bad paths and values fail here, in one line."""
    seen: set[str | None] = set()
    for run in sweep.runs:
        if run.controller in seen:
            continue
        seen.add(run.controller)
        where = f" (run {run.run_id})"
        try:
            data = sweep.scenario_data(run)
            scenario_from_data(data, source=None, base_dir=sweep.base_dir)
        except UvmsInputError as exc:
            key = _blame(exc.path, list(run.parameters))
            if key is None:
                path = "controllers" if exc.path == "controller.name" and run.controller else "base"
                raise UvmsInputError(f"{exc.path + ': ' if exc.path else ''}{exc.message}{where}", sweep.source,
                                     path) from None
            inner = f"{exc.path}: " if exc.path and exc.path != key else ""
            raise UvmsInputError(f"{inner}{exc.message}{where}", sweep.source, f"parameters.{key}") from None


def _blame(path: str | None, keys: list[str]) -> str | None:
    """The parameter key that an error at scenario field ``path`` concerns (the longest match), if any."""
    if not path:
        return None
    matches = [k for k in keys if path == k or path.startswith((k + ".", k + "[")) or k.startswith((path + ".",
                                                                                                     path + "["))]
    return max(matches, key=len) if matches else None


# ---------------------------------------------------------------------------------------------- dotted paths


def path_segments(path: str) -> list[str | int]:
    """``"inputs.joint_torques[0].torques"`` -> ``["inputs", "joint_torques", 0, "torques"]``."""
    segments: list[str | int] = []
    for part in path.split("."):
        name, _, rest = part.partition("[")
        segments.append(name)
        segments += [int(i) for i in re.findall(r"(\d+)\]", "[" + rest if rest else "")]
    return segments


def set_path(data: dict[str, Any], path: str, value: Any) -> None:
    """Set ``value`` at dotted ``path`` in nested mappings and lists, creating missing mappings on the way.

    Raises:
        UvmsInputError: a list index out of range, or a step into something that is not a mapping or list.
    """
    segments = path_segments(path)
    node: Any = data
    for k, segment in enumerate(segments):
        last = k == len(segments) - 1
        where = _render(segments[:k]) or "the top level"
        if isinstance(segment, int):
            if not isinstance(node, list):
                raise UvmsInputError(f"cannot index {where} with [{segment}]: it is not a list in the base scenario",
                                     path=path)
            if segment >= len(node):
                raise UvmsInputError(f"index [{segment}] out of range: {where} has {len(node)} entries", path=path)
        elif not isinstance(node, dict):
            raise UvmsInputError(f"cannot set {segment!r} in {where}: it is not a mapping in the base scenario",
                                 path=path)
        if last:
            node[segment] = value
        else:
            if isinstance(node, dict) and node.get(segment) is None:
                node[segment] = {}
            node = node[segment]


def _render(segments: list[str | int]) -> str:
    text = ""
    for s in segments:
        text += f"[{s}]" if isinstance(s, int) else (f".{s}" if text else s)
    return text
