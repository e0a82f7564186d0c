"""3-D views of a model and replays of runs (``uvms show``, ``uvms animate``; ``docs/viewing.md``).

* :func:`show` - the model at a pose, an interactive plotly Figure (Jupyter, or ``.write_html``).
* :func:`picture` - the same as a matplotlib Figure (PNG/PDF/SVG for papers).
* :func:`animate_run` - a saved or fresh run replayed with play/pause and a time slider (plotly Figure).

What is drawn comes from one place, :func:`uvms.view.scene.scene_from_model`.
"""

from __future__ import annotations

import importlib
from typing import Any

from uvms.errors import UvmsInputError

DEFAULT_FPS = 20.0
"""Frames per second of a replay's playback."""
DEFAULT_MAX_FRAMES = 250
"""Most frames of a replay (a longer one keeps its duration at a lower frame rate)."""

_SCENE_NAMES = ("Primitive", "Scene", "Snapshot", "scene_from_model", "pose_scene")
__all__ = [*_SCENE_NAMES, "show", "picture", "animate_run", "state_at", "DEFAULT_FPS", "DEFAULT_MAX_FRAMES"]


def __getattr__(name: str) -> Any:   # numpy and the scene on first use: `uvms --help` stays fast
    if name in _SCENE_NAMES:
        return getattr(importlib.import_module("uvms.view.scene"), name)
    raise AttributeError(f"module 'uvms.view' has no attribute {name!r}")


def as_model(model, argument: str = "model"):
    """``model`` itself if it is a :class:`~uvms.model.model.Model`, else loaded by name or path
    (:func:`uvms.load_model`: ``show("paper")`` works); anything else is a one-line
    :class:`~uvms.errors.UvmsInputError` naming ``argument``."""
    import os

    from uvms.model.model import Model

    if isinstance(model, Model):
        return model
    if isinstance(model, (str, os.PathLike)):
        from uvms.model.load import load_model

        return load_model(model)
    from uvms.errors import show as render

    raise UvmsInputError(f"expected a Model, a bundled model name or a model file path, found "
                         f"{type(model).__name__} {render(model)}", None, argument)


def _state(model, state):
    """``state`` checked to be a :class:`~uvms.state.State` (or ``None``)."""
    from uvms.state import State

    if state is not None and not isinstance(state, State):
        raise UvmsInputError(f"expected a uvms.State (or None), found {type(state).__name__}", None, "state")
    if state is not None and state.q.size != model.n_joints:
        raise UvmsInputError(f"expected a state of model {model.name!r} ({model.n_joints} joints), found one with "
                             f"{state.q.size} joints", None, "state")
    return state


def state_at(model, state=None, *, q=None):
    """``state`` (default: the vehicle at the origin, level), with the joint angles ``q`` [rad] if given."""
    import numpy as np

    from uvms.state import State

    state = State.zero(model) if _state(model, state) is None else state
    if q is not None:
        q = np.asarray(q, dtype=float).reshape(-1)
        if q.size != model.n_joints:
            raise UvmsInputError(f"expected {model.n_joints} joint angles for model {model.name!r}, found {q.size}",
                                 None, "--q")
        if not np.all(np.isfinite(q)):
            raise UvmsInputError("expected finite joint angles", None, "--q")
        state = state.replace(q=q)
    return state


def _snapshot(model, state, q, thrusters):
    from uvms.dynamics.poses import forward_kinematics
    from uvms.view.scene import pose_scene, scene_from_model

    state = state_at(model, state, q=q)
    scene = scene_from_model(model, thrusters)
    poses = forward_kinematics(model, state)
    return scene, pose_scene(scene, poses.rotation, poses.position), state


def _title(model, state) -> str:
    q = ", ".join(f"{v:.3g}" for v in state.q)
    return f"{model.name}: q = [{q}] rad" if state.q.size else str(model.name)


def show(model, state=None, *, q=None, thrusters=None, title: str | None = None, flow=None, time: float = 0.0):
    """The model (a Model, or a bundled model name or file path) at ``state`` (default: at the origin, joints at
    zero; ``q`` overrides the joint angles) as an interactive plotly Figure: shapes, body frames, joint axes,
    centres of mass and buoyancy, thrusters; with ``flow`` (a scenario's fluid keywords,
    :func:`uvms.view.water.flow_of_scenario`) the free surface and flow arrows at ``time`` [s] too."""
    from uvms.view.plotly_html import pose_figure

    model = as_model(model)
    scene, snap, state = _snapshot(model, state, q, thrusters)
    water = None
    if flow is not None:
        from uvms.view.water import water_drawing

        water = water_drawing(flow, model.convention, [time], snap.points())
    return pose_figure(scene, snap, title=title or _title(model, state), water=water)


def picture(model, state=None, *, q=None, thrusters=None, title: str | None = None, flow=None, time: float = 0.0):
    """:func:`show` as a static matplotlib Figure (for ``.png``, ``.pdf``, ``.svg``)."""
    import numpy as np

    from uvms.view import png
    from uvms.view.scene import equal_ranges

    model = as_model(model)
    scene, snap, state = _snapshot(model, state, q, thrusters)
    points = [snap.points(), 1.15 * scene.world_axis_length * np.eye(3)]
    water = None
    if flow is not None:
        from uvms.view.water import water_drawing

        water = water_drawing(flow, model.convention, [time], snap.points())
        points.append(water.points())
    ranges = equal_ranges(np.vstack(points))
    return png.pose_figure(scene, snap, ranges, title=title or _title(model, state), water=water)


def animate_run(result, model=None, *, fps: float = DEFAULT_FPS, speed: float = 1.0,
                max_frames: int = DEFAULT_MAX_FRAMES,
                thrusters=None, start: int = 0):
    """A run replayed in 3-D as a plotly Figure (play/pause, time slider, trails, thrust arrows).

    ``model`` defaults to the model of the run folder ``result`` was read from (:meth:`Result.load
    <uvms.sim.result.Result.load>`: its ``scenario.yaml``), and ``thrusters`` to that run's thruster layout."""
    from uvms.view.animate import model_of_run, replay, replay_figure

    if model is None:
        directory = getattr(result, "_directory", None)
        if directory is None:
            raise UvmsInputError("pass the model: the result was not read from a run folder (Result.load)")
        model, layout = model_of_run(directory)
        thrusters = layout if thrusters is None else thrusters
    model = as_model(model)
    rp = replay(result, model, fps=fps, speed=speed, max_frames=max_frames, thrusters=thrusters)
    return replay_figure(rp, start=start)
