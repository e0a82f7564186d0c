"""What a scenario's water is: the keyword arguments of :class:`uvms.hydro.flow.Flow` built from its file.

:func:`flow_parts` is the one translation of a scenario's ``inputs.current`` (the uniform part), its
``environment.waves`` (:mod:`uvms.hydro.waves`) and ``environment.current`` (:mod:`uvms.hydro.currents`) into the
arrays of the compiled fluid object: ``times, velocity, acceleration`` (the uniform table), ``profile``,
``field``, ``waves`` and ``surface``, all in the world frame of the model's convention (``docs/environment.md``).
A field file's name is relative to the scenario file and must lie in its folder (:mod:`uvms.input_paths`).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from uvms.errors import UvmsInputError
from uvms.hydro.currents import CurrentField, CurrentProfile, current_profile, power_law_profile, read_field
from uvms.hydro.waves import Spectrum, WaveComponents, irregular_waves, regular_waves
from uvms.model.model import Model
from uvms.sim.inputs import CurrentTable
from uvms.sim.scenario.schema import EnvironmentSpec, ScenarioSpec, SpatialCurrentSpec, WavesSpec


def uniform_current(spec: ScenarioSpec, model: Model) -> CurrentTable | None:
    """The uniform current of ``inputs.current`` (``None``: the model's environment current)."""
    c = spec.inputs.current
    if c is None:
        return None
    if c.table is None:
        return CurrentTable.constant(c.constant, model.fluid_acceleration)
    t = np.array(c.table.times, dtype=float)
    v = np.array(c.table.velocity, dtype=float)
    if c.table.acceleration is not None:
        return CurrentTable(t, v, np.array(c.table.acceleration, dtype=float))
    return CurrentTable.from_velocity_table(t, v, spec.duration, spec.step)


def build_waves(spec: WavesSpec, gravity: float, source: str | None = None,
                field: str = "environment.waves") -> WaveComponents:
    """The :class:`~uvms.hydro.waves.WaveComponents` of ``environment.waves`` (``gravity``: the model's
    ``|g|`` [m/s^2], used in the dispersion relation).

    Raises:
        UvmsInputError: what :mod:`uvms.hydro.waves` refuses, naming ``field`` in ``source``.
    """
    depth = math.inf if spec.water_depth is None else spec.water_depth
    try:
        if spec.type == "regular":
            return regular_waves(spec.height, spec.period, direction=spec.direction, water_depth=depth,
                                 gravity=gravity, phase=spec.phase)
        span = spec.frequencies()
        if spec.spectrum == "table":
            spectrum = Spectrum.table(spec.table.frequencies, spec.table.densities, span)
        elif spec.spectrum == "jonswap":
            spectrum = Spectrum.jonswap(spec.significant_height, spec.peak_period, spec.peak_factor, span)
        else:
            spectrum = Spectrum.pierson_moskowitz(spec.significant_height, spec.peak_period, span)
        return irregular_waves(spectrum, components=spec.components, seed=spec.seed, direction=spec.direction,
                               spreading=spec.spreading, water_depth=depth, gravity=gravity)
    except UvmsInputError as exc:
        raise UvmsInputError(exc.message, source, f"{field}.{exc.path}" if exc.path else field) from None


def build_spatial_current(spec: SpatialCurrentSpec, folder: Path, source: str | None = None,
                          field: str = "environment.current") -> tuple[CurrentProfile | None, CurrentField | None]:
    """The ``(profile, field)`` of ``environment.current`` (one of them ``None``); a field file is read
    relative to ``folder`` and must lie inside it.

    Raises:
        UvmsInputError: a file outside the folder, unreadable, ragged, with NaN or non-monotonic axes (one line
            naming the file and the field).
    """
    if spec.profile is not None:
        p = spec.profile
        if p.power_law is not None:
            law = p.power_law
            return power_law_profile(law.surface_velocity, law.water_depth, law.exponent), None
        return current_profile(p.depth, p.velocity, source=source, field=f"{field}.profile"), None
    from uvms.input_paths import data_file

    path = data_file(spec.field.file, folder, source, f"{field}.field.file")
    try:
        return None, read_field(path, spec.field.outside)
    except UvmsInputError as exc:
        where = f"{field}.field.file ({exc.source})"
        raise UvmsInputError(exc.message, source, f"{where}: {exc.path}" if exc.path else where) from None


def flow_parts(spec: ScenarioSpec, model: Model, source: str | None = None, folder: Path | None = None
               ) -> dict[str, Any]:
    """The keyword arguments of :class:`uvms.hydro.flow.Flow` for a scenario on ``model``: the uniform table
    (``inputs.current``, else the model's constant current and fluid acceleration), ``profile``, ``field``,
    ``waves`` (``None`` when absent) and ``surface``, world frame of the model's convention. A field file is
    read from ``folder`` (default: the folder of ``source``, else the working folder).

    Raises:
        UvmsInputError: a bad wave or current input (one line naming the file and the field).
    """
    uniform = uniform_current(spec, model) or CurrentTable.constant(model.current, model.fluid_acceleration)
    env: EnvironmentSpec = spec.environment
    if folder is None:
        folder = Path(source).parent if source is not None else Path.cwd()
    profile = field = waves = None
    if env.current is not None:
        profile, field = build_spatial_current(env.current, folder, source)
    if env.waves is not None:
        waves = build_waves(env.waves, float(np.linalg.norm(model.gravity)), source)
    return dict(times=uniform.times.copy(), velocity=uniform.velocity.copy(), acceleration=uniform.acceleration.copy(),
                profile=profile, field=field, waves=waves, surface=float(env.surface))


def has_real_water(spec: ScenarioSpec) -> bool:
    """Whether the scenario has waves or a current varying in space (what needs :class:`uvms.hydro.flow.Flow`)."""
    return spec.environment.waves is not None or spec.environment.current is not None
