"""A saved run replayed in 3-D: frame sampling, the plotly page, mp4 and gif videos.

Frames are taken at a fixed playback rate: a run of duration ``D`` played at ``speed`` lasts ``D / speed``
seconds of wall time and is cut into ``fps`` frames per second, each showing the recorded sample nearest to
its time (no interpolation: what is drawn was computed). At most ``max_frames`` frames are drawn; a longer
replay keeps its duration and lowers its frame rate. Thruster arrows are the commanded thrusts
(``thrust_cmd_<name>`` signals of the run), all scaled by the largest one of the run.
"""

from __future__ import annotations

import math
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from uvms.errors import UvmsInputError
from uvms.sim.result import check_times
from uvms.view import DEFAULT_FPS, DEFAULT_MAX_FRAMES
from uvms.view.scene import Scene, Snapshot, equal_ranges, pose_scene, scene_from_model

VIDEO_SUFFIXES = (".mp4", ".gif")


@dataclass(frozen=True)
class Replay:
    """The frames of a replay.

    Attributes:
        scene: what is drawn.
        snaps: one snapshot per frame.
        times: (N,) simulation time of each frame [s].
        samples: (N,) index of the recorded sample each frame shows.
        fps: frames per second of wall time.
        target: the station-keeping target (the vehicle at its initial pose).
        vehicle_path, ee_path: (N, 3) positions of the vehicle and the end effector per frame [m].
        peak_thrust: largest commanded thrust magnitude of the run [N] (0 without thrust signals).
        title: a one-line description.
        water: the free surface and flow arrows per frame (:mod:`uvms.view.water`), ``None`` in still water.
    """

    scene: Scene
    snaps: list[Snapshot]
    times: np.ndarray
    samples: np.ndarray
    fps: float
    target: Snapshot
    vehicle_path: np.ndarray
    ee_path: np.ndarray
    peak_thrust: float
    title: str
    water: Any = None

    def ranges(self) -> np.ndarray:
        return equal_ranges(np.vstack([s.points() for s in self.snaps]
                                      + [1.15 * self.scene.world_axis_length * np.eye(3)]
                                      + ([self.water.points()] if self.water is not None else [])))


def frame_samples(time: np.ndarray, *, fps: float, speed: float, max_frames: int) -> tuple[np.ndarray, float]:
    """Indices of the recorded samples shown by each frame, and the frame rate actually used."""
    time = np.asarray(time, dtype=float)
    if not (fps > 0 and math.isfinite(fps)):
        raise UvmsInputError(f"expected a positive frame rate, found {fps}", None, "--fps")
    if not (speed > 0 and math.isfinite(speed)):
        raise UvmsInputError(f"expected a positive playback speed, found {speed}", None, "--speed")
    if max_frames < 1:
        raise UvmsInputError(f"expected at least 1 frame, found {max_frames}", None, "--max-frames")
    check_times(time)
    wall = (float(time[-1]) - float(time[0])) / speed if len(time) else 0.0
    if not math.isfinite(wall):
        raise UvmsInputError(f"expected a playback speed at which the replay lasts a finite time, found {speed}",
                             None, "--speed")
    frames = wall * fps + 1e-9          # may overflow to inf for a huge span: compared before any int()
    wanted_count = int(math.floor(frames)) + 1 if frames < max_frames else max_frames + 1
    count = min(wanted_count, max_frames, len(time))
    if count <= 1:
        return np.zeros(1, dtype=int), fps
    used = fps if count == wanted_count else (count - 1) / wall
    wanted = time[0] + np.arange(count) * (speed / used)
    idx = np.clip(np.searchsorted(time, wanted), 1, len(time) - 1)
    nearer_left = (wanted - time[idx - 1]) <= (time[idx] - wanted)
    return np.where(nearer_left, idx - 1, idx), used


def _thrust_fractions(result, scene: Scene) -> tuple[np.ndarray, float]:
    """(K, m) commanded thrust of each thruster as a fraction of the run's largest; and that largest [N]."""
    K = len(result.time)
    T = np.zeros((K, len(scene.thrusters)))
    for j, t in enumerate(scene.thrusters):
        s = result.signals.get(f"thrust_cmd_{t.name}")
        if s is not None:
            T[:, j] = np.nan_to_num(np.asarray(s, dtype=float))
    peak = float(np.max(np.abs(T))) if T.size else 0.0
    return (T / peak if peak > 0 else T), peak


REPLAY_LIMIT = 1e6
"""Largest vehicle position [m] or joint angle [rad] drawn (plotly draws in 32-bit floats, which overflow near
3e38; a run keeps no such state: divergence stops it at 1e4 m)."""


def drawable_samples(result) -> int:
    """How many leading samples of ``result`` can be drawn: position, orientation and joint angles finite, the
    position and joint angles within :data:`REPLAY_LIMIT`. A replay stops before the first other one."""
    pose = np.hstack([np.asarray(result.position, dtype=float), np.asarray(result.q, dtype=float)])
    good = np.all(np.isfinite(pose) & (np.abs(np.nan_to_num(pose)) <= REPLAY_LIMIT), axis=1)
    good &= np.all(np.isfinite(np.asarray(result.quaternion, dtype=float)), axis=1)
    bad = np.flatnonzero(~good)
    return int(bad[0]) if bad.size else len(good)


def replay(result, model, *, fps: float = DEFAULT_FPS, speed: float = 1.0, max_frames: int = DEFAULT_MAX_FRAMES,
           thrusters=None, title: str | None = None, flow=None) -> Replay:
    """The frames of ``result`` (a :class:`~uvms.sim.result.Result`) drawn with ``model``'s scene; ``thrusters``
    (default: the model's) are the run's thruster layout; ``flow`` (the keyword arguments of the run's fluid
    object, :func:`uvms.sim.scenario.environment.flow_parts`) adds the free surface and flow arrows."""
    from uvms.dynamics.poses import forward_kinematics

    if len(result.time) == 0:
        raise UvmsInputError("the run has no samples to show")
    if model.n_joints != result.n_joints:
        raise UvmsInputError(f"the run has {result.n_joints} joints, its model {model.name!r} has "
                             f"{model.n_joints}")
    check_times(result.time)
    drawn = drawable_samples(result)
    if drawn == 0:
        raise UvmsInputError("nothing to replay: the pose of the first sample (position, orientation, joint "
                             f"angles) is not finite or beyond {REPLAY_LIMIT:g}")
    scene = scene_from_model(model, thrusters)
    samples, used = frame_samples(np.asarray(result.time)[:drawn], fps=fps, speed=speed, max_frames=max_frames)
    fractions, peak = _thrust_fractions(result, scene)
    local = [prim.local_mesh() for prim in scene.primitives]
    snaps = []
    for k in samples:
        poses = forward_kinematics(model, result.state(int(k)))
        snaps.append(pose_scene(scene, poses.rotation, poses.position, fractions[k], _local=local))
    first = forward_kinematics(model, result.state(0))
    target = pose_scene(scene, first.rotation, first.position, np.zeros(len(scene.thrusters)), _local=local)
    name = title or str(result.metadata.get("scenario") or "run")
    arrows = f"; arrows: commanded thrust, longest {peak:.3g} N" if peak > 0 else ""
    speed_text = f", played at {speed:g}x" if speed != 1 else ""
    head = f"{name} (model {model.name}){speed_text}{arrows}"
    if drawn < len(result.time):
        head += (f"; stops at t = {result.time[drawn - 1]:.4g} s (later poses not finite or beyond "
                 f"{REPLAY_LIMIT:g})")
    times = np.asarray(result.time)[samples]
    water = None
    if flow is not None:
        from uvms.view.water import water_drawing

        water = water_drawing(flow, model.convention, times, np.vstack([s.points() for s in snaps]))
    return Replay(scene=scene, snaps=snaps, times=times, samples=samples, fps=used,
                  target=target, vehicle_path=np.array([s.vehicle for s in snaps]),
                  ee_path=np.array([s.end_effector for s in snaps]), peak_thrust=peak, title=head, water=water)


def replay_figure(rp: Replay, *, start: int = 0):
    """The plotly figure of a replay (play/pause, time slider, trails, target)."""
    from uvms.view.plotly_html import animation_figure

    return animation_figure(rp, start=start)


def write_replay_html(rp: Replay, path, *, start: int = 0, ghost: Replay | None = None,
                      ghost_name: str = "log") -> Path:
    """Write the replay as one self-contained HTML page (atomically); ``ghost``: a second robot on the same
    frame times drawn faint in the same scene (:func:`uvms.view.plotly_html.animation_figure`)."""
    from uvms.view.plotly_html import animation_figure, write_html

    fig = animation_figure(rp, start=start, ghost=ghost, ghost_name=ghost_name)
    return write_html(fig, path, frame_names=[f.name for f in fig.frames], times=rp.times)


def ffmpeg_available() -> bool:
    from matplotlib.animation import FFMpegWriter

    return bool(FFMpegWriter.isAvailable())


def fitted_title(fig, text: str, *, fontsize="medium", share: float = 0.94) -> str:
    """``text`` broken at spaces into lines no wider than ``share`` of the figure's width (measured with the
    figure's renderer; the ratio does not depend on the dpi a video is written at): a video frame has no room
    beyond its edges, so a long title would be cut there."""
    import textwrap

    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = fig.canvas if hasattr(fig.canvas, "get_renderer") else FigureCanvasAgg(fig)
    renderer = canvas.get_renderer()
    room = share * fig.get_figwidth() * fig.dpi
    probe = fig.text(0, 0, "", fontsize=fontsize)
    try:
        for width in range(len(text), 9, -1):
            lines = textwrap.fill(text, width, break_long_words=False)
            probe.set_text(lines)
            if probe.get_window_extent(renderer).width <= room:
                return lines
        return textwrap.fill(text, 10, break_long_words=False)
    finally:
        probe.remove()


def write_video(rp: Replay, path, *, option: str = "--output", dpi: int = 100) -> Path:
    """Write the replay as an mp4 (matplotlib's FFMpegWriter: needs the ``ffmpeg`` program) or a gif
    (PillowWriter), through a temporary file renamed into place."""
    from matplotlib.animation import FFMpegWriter, PillowWriter

    from uvms.output import naming, publish
    from uvms.view import png

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".mp4":
        if not ffmpeg_available():
            raise UvmsInputError("writing .mp4 needs the ffmpeg program, which is not installed (install ffmpeg, "
                                 "or write a .gif or .html)", str(path), option)
        writer = FFMpegWriter(fps=rp.fps, codec="h264", extra_args=["-pix_fmt", "yuv420p"])
    elif suffix == ".gif":
        writer = PillowWriter(fps=rp.fps)
    else:
        raise UvmsInputError(f"expected a {' or '.join(VIDEO_SUFFIXES)} file name", str(path), option)
    ranges, water = rp.ranges(), rp.water
    fig, ax = png.new_figure(size=(7.2, 6.4))
    title = fitted_title(fig, rp.title)
    with naming(path):
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=suffix, dir=path.parent)
        os.close(fd)
        try:
            with writer.saving(fig, tmp, dpi):
                for k, snap in enumerate(rp.snaps):
                    ax.cla()
                    png.draw_world(ax, rp.scene)
                    if water is not None:          # the free surface and flow arrows at this frame's time
                        png.draw_water(ax, water, k)
                    png.draw_target(ax, rp.scene, rp.target)
                    png.draw_trails(ax, rp.vehicle_path[: k + 1], rp.ee_path[: k + 1])
                    png.draw_snapshot(ax, rp.scene, snap)
                    png.style_axes(ax, ranges, f"{title}\nt = {rp.times[k]:.2f} s", rp.scene)
                    writer.grab_frame()
            publish(tmp, path)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
    return path


def model_of_run(directory):
    """The model and thruster layout of a saved run, from its ``scenario.yaml`` (:func:`scenario_of_run`)."""
    from uvms.sim.run import Actuation

    scenario = scenario_of_run(directory)
    return scenario.model, Actuation.named(scenario.spec.actuators, scenario.model).thrusters


def scenario_of_run(directory):
    """The scenario of a saved run, from its ``scenario.yaml`` (written by ``uvms run``).

    The copy is the user's scenario verbatim, so a relative ``model:`` path and data files (a current field, a
    joint-motion table) are relative to the folder the scenario file was in when it ran
    (``metadata.scenario_folder`` of ``result.json``; older runs: the folder of ``metadata.scenario_source``),
    not to the run folder; the run folder is used when that folder no longer holds them (a run moved together
    with its files)."""
    from uvms.safe_yaml import read_yaml_mapping
    from uvms.sim.result import load_result_summary
    from uvms.sim.scenario import scenario_from_data

    directory = Path(directory)
    path = directory / "scenario.yaml"
    if not path.is_file():
        raise UvmsInputError("no scenario.yaml here, so the model of the run is unknown (a folder written by "
                             "'uvms run SCENARIO -o DIR' has one)", str(directory))
    data = read_yaml_mapping(path, "scenario fields")
    text = path.read_text(encoding="utf-8")
    metadata = load_result_summary(directory).get("metadata") or {}
    scenario = scenario_from_data(data, source=str(path), base_dir=_scenario_folder(data, directory, metadata),
                                  text=text, default_name=directory.name)
    return scenario


def _scenario_folder(data: dict, directory: Path, metadata: dict) -> Path:
    """The folder a run's relative paths resolve against (see :func:`scenario_of_run`): the scenario's own folder
    when it still holds the model file (unless the model is a bundled one) and every data file the scenario
    names (a current field, a joint-motion table), else the run folder."""
    from uvms.model import bundled_models

    def relative(name) -> bool:
        return isinstance(name, str) and bool(name) and "\0" not in name and not Path(name).expanduser().is_absolute()

    model, files = data.get("model"), []
    environment, inputs = data.get("environment"), data.get("inputs")
    current = environment.get("current") if isinstance(environment, dict) else None
    if isinstance(current, dict) and isinstance(current.get("field"), dict):
        files.append(current["field"].get("file"))
    if isinstance(inputs, dict) and isinstance(inputs.get("joint_motion"), dict):
        files.append(inputs["joint_motion"].get("file"))
    files = [name for name in files if relative(name)]
    bundled = not relative(model) or model in bundled_models()
    candidates = [metadata.get("scenario_folder"), metadata.get("scenario_source")]
    folders = [Path(candidates[0])] if isinstance(candidates[0], str) and "\0" not in candidates[0] else []
    if isinstance(candidates[1], str) and "\0" not in candidates[1]:
        folders.append(Path(candidates[1]).parent)
    for folder in folders:
        try:
            if (bundled or (folder / model).exists()) and all((folder / name).exists() for name in files) \
                    and (files or not bundled):
                return folder
        except OSError:
            continue
    return directory
