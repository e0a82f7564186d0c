"""Interactive 3-D views with plotly: a model at one pose, and a run replayed with play/pause and a time slider.

The page is one self-contained HTML file (plotly.js embedded, ``include_plotlyjs=True``): it opens offline,
from disk, with no server; in Jupyter the same :class:`plotly.graph_objects.Figure` displays inline.

The world is the model's convention (:attr:`Scene.frame`). In ned (x north, y east, z down) both the y and the
z axis are drawn reversed (z grows downwards on the screen, y to the left when seen from the default camera):
reversing two axes is a rotation by 180 degrees about x, so the picture is the true, unmirrored NED world
(reversing z alone would mirror it: port would be drawn on the starboard side). In enu (z up) no axis is
reversed. Either way the world's up direction (:attr:`Scene.up`) points up on the screen.

An animation page reads ``#frame=K`` (or ``#t=SECONDS``) from its address and starts at that frame, so a
link can point at a moment of a run.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from uvms.view.scene import Scene, Snapshot, arrow_head, equal_ranges

AXIS_COLORS = ("#d62728", "#2ca02c", "#1f77b4")   # x red, y green, z blue
THRUSTER_COLOR = "#ff7f0e"
JOINT_COLOR = "#9467bd"
COM_COLOR = "#111111"
COB_COLOR = "#17becf"
VEHICLE_TRAIL_COLOR = "#b8860b"
EE_TRAIL_COLOR = "#e377c2"
GHOST_COLOR = "#7f7f7f"
"""The second robot of a comparison page (a log's motion beside the simulation), drawn faint."""
GHOST_OPACITY = 0.3
WORLD_LABELS = ("x north", "y east", "z down")
"""The ned world's axis labels (a scene's own are :attr:`Scene.world_labels`)."""


def _segments(starts: np.ndarray, ends: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Line segments as one polyline broken by NaN gaps (one trace for many segments), float32 (compact in the
    page: plotly stores numpy arrays as typed binary arrays)."""
    a = np.asarray(starts, dtype=float).reshape(-1, 3)
    b = np.asarray(ends, dtype=float).reshape(-1, 3)
    pts = np.stack([a, b, np.full_like(a, np.nan)], axis=1).reshape(-1, 3).astype(np.float32)
    return pts[:, 0], pts[:, 1], pts[:, 2]


def _lines(starts, ends, *, name: str, color: str, width: float = 5, dash: str | None = None,
           showlegend: bool = True, hover: str | None = None):
    import plotly.graph_objects as go

    x, y, z = _segments(starts, ends)
    return go.Scatter3d(x=x, y=y, z=z, mode="lines", name=name, showlegend=showlegend, legendgroup=name,
                        line=dict(color=color, width=width, dash=dash), hoverinfo="name" if hover is None else "text",
                        hovertext=hover)


def _merged_mesh(parts) -> tuple[np.ndarray, np.ndarray]:
    Vs, Fs, offset = [], [], 0
    for V, F in parts:
        Vs.append(V)
        Fs.append(F + offset)
        offset += len(V)
    if not Vs:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=int)
    return np.vstack(Vs), np.vstack(Fs)


def _mesh(V: np.ndarray, F: np.ndarray, *, name: str, color: str, opacity: float, showlegend: bool = True,
          legendgroup: str | None = None, hover: str | None = None):
    import plotly.graph_objects as go

    V = np.asarray(V, dtype=np.float32)
    F = np.asarray(F, dtype=np.int32)
    return go.Mesh3d(x=V[:, 0], y=V[:, 1], z=V[:, 2], i=F[:, 0], j=F[:, 1], k=F[:, 2], color=color,
                     opacity=opacity, name=name, showlegend=showlegend, legendgroup=legendgroup or name,
                     hovertext=hover or name, hoverinfo="text", flatshading=True,
                     lighting=dict(ambient=0.55, diffuse=0.7, specular=0.1, roughness=0.9),
                     lightposition=dict(x=-1000, y=-500, z=-2000))


def moving_points(scene: Scene, snap: Snapshot) -> list[np.ndarray]:
    """The points of every moving trace, (P, 3) each, in the order of :func:`moving_traces` (what an
    animation frame changes): shapes, body triads (x, y, z), joint axes, centres of mass and buoyancy,
    thruster shafts, thruster heads, thruster labels."""
    def polyline(a, b) -> np.ndarray:
        return np.column_stack(_segments(a, b))

    points = [V for V, _ in snap.meshes]
    ends = [snap.frame_origin + scene.triad_length * snap.frame_axes[:, :, a] for a in range(3)]
    points += [polyline(snap.frame_origin, e) for e in ends]
    points += [polyline(snap.joint_axis[:, 0], snap.joint_axis[:, 1]), snap.com, snap.cob]
    if scene.thrusters:
        head = 0.3 * scene.arrow_length
        V, _ = _merged_mesh([arrow_head(b, t, head) for b, t in zip(snap.thruster_base, snap.thruster_tip)])
        points += [polyline(snap.thruster_base, snap.thruster_tip), V, snap.thruster_tip]
    return [np.asarray(p, dtype=np.float32) for p in points]


def moving_traces(scene: Scene, snap: Snapshot) -> list:
    """The traces that follow the robot, styled, in the order of :func:`moving_points` (the same count for
    every pose of a scene)."""
    import plotly.graph_objects as go

    traces = []
    seen: set[str] = set()
    for prim, (V, F) in zip(scene.primitives, snap.meshes):
        group = {"vehicle": "vehicle", "link": "links", "visual": "visual meshes"}.get(prim.role, prim.role)
        traces.append(_mesh(V, F, name=group, color=prim.color, opacity=prim.opacity,
                            showlegend=group not in seen, legendgroup=group, hover=prim.name or prim.kind))
        seen.add(group)
    L = scene.triad_length
    origins = snap.frame_origin
    labels = list(scene.body_names) + ["end effector"]
    for a in range(3):
        ends = origins + L * snap.frame_axes[:, :, a]
        traces.append(_lines(origins, ends, name=f"body {'xyz'[a]} axes", color=AXIS_COLORS[a], width=4,
                             hover=[f"{lab}: {'xyz'[a]} axis" for lab in labels for _ in range(3)]))
    traces.append(_lines(snap.joint_axis[:, 0], snap.joint_axis[:, 1], name="joint axes", color=JOINT_COLOR,
                         width=7, dash="dash",
                         hover=[f"joint {i + 1} axis" for i in range(len(snap.joint_axis)) for _ in range(3)]))
    names = scene.body_names
    traces.append(go.Scatter3d(x=snap.com[:, 0], y=snap.com[:, 1], z=snap.com[:, 2], mode="markers",
                               name="centre of mass", marker=dict(size=5, color=COM_COLOR, symbol="circle"),
                               hovertext=[f"CoM {n}" for n in names], hoverinfo="text"))
    traces.append(go.Scatter3d(x=snap.cob[:, 0], y=snap.cob[:, 1], z=snap.cob[:, 2], mode="markers",
                               name="centre of buoyancy", marker=dict(size=5, color=COB_COLOR, symbol="diamond"),
                               hovertext=[f"CoB {n}" for n in names], hoverinfo="text"))
    if scene.thrusters:
        tnames = [t.name for t in scene.thrusters]
        traces.append(_lines(snap.thruster_base, snap.thruster_tip, name="thrusters", color=THRUSTER_COLOR,
                             width=8, hover=[n for n in tnames for _ in range(3)]))
        head = 0.3 * scene.arrow_length
        V, F = _merged_mesh([arrow_head(b, t, head) for b, t in zip(snap.thruster_base, snap.thruster_tip)])
        traces.append(_mesh(V, F, name="thruster heads", color=THRUSTER_COLOR, opacity=1.0, showlegend=False,
                            legendgroup="thrusters"))
        traces.append(go.Scatter3d(x=snap.thruster_tip[:, 0], y=snap.thruster_tip[:, 1],
                                   z=snap.thruster_tip[:, 2], mode="text", text=tnames, name="thruster names",
                                   showlegend=False, legendgroup="thrusters", hoverinfo="skip",
                                   textfont=dict(color=THRUSTER_COLOR, size=11)))
    return traces


def world_traces(scene: Scene, length: float | None = None) -> list:
    """The world axes at the origin, labelled with their directions."""
    import plotly.graph_objects as go

    L = scene.world_axis_length if length is None else length
    labels = scene.world_labels
    traces = [_lines(np.zeros((1, 3)), L * np.eye(3)[a][None, :], name=f"world {labels[a]}",
                     color=AXIS_COLORS[a], width=3, dash="dot", showlegend=False) for a in range(3)]
    tips = 1.12 * L * np.eye(3)
    traces.append(go.Scatter3d(x=tips[:, 0], y=tips[:, 1], z=tips[:, 2], mode="text", text=list(labels),
                               name="world axes", showlegend=False, hoverinfo="skip",
                               textfont=dict(color=list(AXIS_COLORS), size=12)))
    return traces


def scene_layout(ranges: np.ndarray, title: str, scene: Scene | None = None) -> dict:
    """Layout of a 3-D scene: equal scales, the axes of :attr:`Scene.reversed_axes` reversed (the world's up
    drawn up, unmirrored: y and z in ned), labelled with :attr:`Scene.world_labels` (ned without a scene)."""
    labels = WORLD_LABELS if scene is None else scene.world_labels
    reverse = (False, True, True) if scene is None else scene.reversed_axes

    def axis(k: int) -> dict:
        lo, hi = (float(v) for v in ranges[k])
        return dict(title=dict(text=f"{labels[k]} [m]"), range=[hi, lo] if reverse[k] else [lo, hi],
                    autorange=False, backgroundcolor="#f4f6f8", gridcolor="#d5dbe1", zerolinecolor="#9aa5b1")

    return dict(
        title=dict(text=title, x=0.02, font=dict(size=14)),
        scene=dict(xaxis=axis(0), yaxis=axis(1), zaxis=axis(2), aspectmode="cube",
                   camera=dict(eye=dict(x=1.35, y=1.35, z=0.85), up=dict(x=0, y=0, z=1))),
        legend=dict(x=0.0, y=0.0, xanchor="left", yanchor="bottom", bgcolor="rgba(255,255,255,0.7)",
                    font=dict(size=11)),
        margin=dict(l=0, r=0, t=40, b=0),
        paper_bgcolor="white",
    )


def pose_figure(scene: Scene, snap: Snapshot, *, title: str, water=None):
    """A plotly figure of ``scene`` at one pose (the snapshot), with ``water`` (a :class:`uvms.view.water.Water`
    of one frame) if given."""
    import plotly.graph_objects as go

    world = world_traces(scene)
    points = np.vstack([snap.points(), 1.15 * scene.world_axis_length * np.eye(3)])
    extra = []
    if water is not None:
        from uvms.view.water import water_traces

        extra = water_traces(water, 0)
        points = np.vstack([points, water.points()])
    fig = go.Figure(data=world + moving_traces(scene, snap) + extra)
    fig.update_layout(**scene_layout(equal_ranges(points), title, scene))
    return fig


def add_player(layout: dict, *, fps: float, times, names: list[str], start: int = 0, decimals: int = 2) -> None:
    """Play/pause buttons and a time slider over the frames ``names`` (at ``times`` [s]) in a plotly layout."""
    ms = 1000.0 / fps
    play = dict(label="\u25b6 play", method="animate",
                args=[None, dict(frame=dict(duration=ms, redraw=True), transition=dict(duration=0),
                                 fromcurrent=True, mode="immediate")])
    pause = dict(label="\u275a\u275a pause", method="animate",
                 args=[[None], dict(frame=dict(duration=0, redraw=False), transition=dict(duration=0),
                                    mode="immediate")])
    layout["updatemenus"] = [dict(type="buttons", direction="left", x=0.02, y=0.06, xanchor="left", yanchor="top",
                                  pad=dict(r=8, t=8), showactive=False, buttons=[play, pause])]
    layout["sliders"] = [dict(
        active=start, x=0.2, y=0.06, len=0.78, xanchor="left", yanchor="top", pad=dict(t=8, b=4),
        currentvalue=dict(prefix="t = ", suffix=" s", visible=True, xanchor="left"),
        transition=dict(duration=0),
        steps=[dict(label=f"{t:.{decimals}f}", method="animate",
                    args=[[name], dict(frame=dict(duration=0, redraw=True), transition=dict(duration=0),
                                       mode="immediate")]) for t, name in zip(times, names)])]


def ghost_traces(scene: Scene, snap: Snapshot, name: str) -> list:
    """A second robot's shapes, one faint grey mesh per shape in one legend entry ``name`` (the order of
    :func:`ghost_points`)."""
    return [_mesh(V, F, name=name, color=GHOST_COLOR, opacity=GHOST_OPACITY, showlegend=k == 0, legendgroup=name,
                  hover=f"{name}: {prim.name or prim.kind}")
            for k, (prim, (V, F)) in enumerate(zip(scene.primitives, snap.meshes))]


def ghost_points(snap: Snapshot) -> list[np.ndarray]:
    """The points of :func:`ghost_traces`."""
    return [np.asarray(V, dtype=np.float32) for V, _ in snap.meshes]


def animation_figure(replay, *, start: int = 0, ghost=None, ghost_name: str = "log"):
    """A plotly figure of a :class:`uvms.view.animate.Replay`: its ``snaps`` (one per entry of ``times`` [s])
    at ``fps`` frames per second of wall time, with play/pause buttons, a time slider, trails of the vehicle
    and the end effector (``vehicle_path``, ``ee_path``, up to the current frame) and the station-keeping
    target (``target``: the vehicle frame drawn faintly, or ``None``), from frame ``start``.

    ``ghost``: a second replay of the same model on the same frame times (e.g. a log's motion beside its
    simulation), drawn in the same scene as faint grey shapes with its own vehicle trail, named ``ghost_name``.
    """
    import plotly.graph_objects as go

    scene, snaps, times, title, fps = replay.scene, replay.snaps, replay.times, replay.title, replay.fps
    if ghost is not None and (len(ghost.snaps) != len(snaps) or not np.allclose(ghost.times, times, atol=1e-9)):
        raise ValueError("the second robot must have the first's frame times")
    target, vehicle_path, ee_path = replay.target, replay.vehicle_path, replay.ee_path
    static = world_traces(scene)
    if target is not None:
        L = scene.triad_length
        for a in range(3):
            o = target.frame_origin[:1]
            static.append(_lines(o, o + 1.3 * L * target.frame_axes[0, :, a][None], name="target (initial pose)",
                                 color=AXIS_COLORS[a], width=2, dash="dash", showlegend=a == 0))
        static.append(go.Scatter3d(x=[target.vehicle[0]], y=[target.vehicle[1]], z=[target.vehicle[2]],
                                   mode="markers", name="target (initial pose)", legendgroup="target (initial pose)",
                                   showlegend=False, marker=dict(size=6, color="#444", symbol="x")))

    def trails(k: int) -> list:
        return [go.Scatter3d(x=vehicle_path[: k + 1, 0], y=vehicle_path[: k + 1, 1], z=vehicle_path[: k + 1, 2],
                             mode="lines", name="vehicle trail", line=dict(color=VEHICLE_TRAIL_COLOR, width=4)),
                go.Scatter3d(x=ee_path[: k + 1, 0], y=ee_path[: k + 1, 1], z=ee_path[: k + 1, 2], mode="lines",
                             name="end-effector trail", line=dict(color=EE_TRAIL_COLOR, width=4))]

    def ghost_trail(k: int) -> list:
        path = ghost.vehicle_path
        return [go.Scatter3d(x=path[: k + 1, 0], y=path[: k + 1, 1], z=path[: k + 1, 2], mode="lines",
                             name=f"{ghost_name}: vehicle trail", line=dict(color=GHOST_COLOR, width=4, dash="dot"))]

    start = int(np.clip(start, 0, len(snaps) - 1))
    first = moving_traces(scene, snaps[start]) + trails(start)
    if ghost is not None:
        first += ghost_traces(ghost.scene, ghost.snaps[start], ghost_name) + ghost_trail(start)
    kinds = [t.type for t in first]
    water = getattr(replay, "water", None)
    if water is not None:
        from uvms.view.water import water_frame_data, water_traces

        first += water_traces(water, start)

    def positions(k: int) -> list:
        """Only what moves (the points): a frame's traces are merged into the drawn ones."""
        pts = moving_points(scene, snaps[k]) + [np.asarray(vehicle_path[: k + 1], dtype=np.float32),
                                                 np.asarray(ee_path[: k + 1], dtype=np.float32)]
        if ghost is not None:
            pts += ghost_points(ghost.snaps[k]) + [np.asarray(ghost.vehicle_path[: k + 1], dtype=np.float32)]
        moved = [dict(type=kind, x=p[:, 0], y=p[:, 1], z=p[:, 2]) for kind, p in zip(kinds, pts, strict=True)]
        return moved + (water_frame_data(water, k) if water is not None else [])

    moving_index = list(range(len(static), len(static) + len(first)))
    names = [str(k) for k in range(len(snaps))]          # unique, whatever the spacing of the times
    steps = np.diff(np.asarray(times, dtype=float))
    smallest = float(steps[steps > 0].min()) if np.any(steps > 0) else 1.0
    decimals = int(min(6, max(2, np.ceil(-np.log10(smallest)))))
    frames = [go.Frame(data=positions(k), traces=moving_index, name=names[k]) for k in range(len(snaps))]
    drawn = snaps + (ghost.snaps if ghost is not None else [])
    points = np.vstack([s.points() for s in drawn] + [1.15 * scene.world_axis_length * np.eye(3)]
                       + ([water.points()] if water is not None else []))
    fig = go.Figure(data=static + first, frames=frames)
    layout = scene_layout(equal_ranges(points), title, scene)
    add_player(layout, fps=fps, times=times, names=names, start=start, decimals=decimals)
    layout["legend"].update(y=0.12)
    layout["margin"] = dict(l=0, r=0, t=40, b=70)
    fig.update_layout(**layout)
    return fig


_SEEK_SCRIPT = """
(function () {
  var gd = document.getElementById('{plot_id}');
  var names = %s, times = %s;
  function seek() {
    var m = /(frame|t)=([0-9.eE+-]+)/.exec(window.location.hash || '');
    if (!m) return;
    var k = 0, v = parseFloat(m[2]);
    if (m[1] === 'frame') { k = Math.round(v); }
    else { var best = Infinity; for (var i = 0; i < times.length; i++) {
      if (Math.abs(times[i] - v) < best) { best = Math.abs(times[i] - v); k = i; } } }
    k = Math.max(0, Math.min(names.length - 1, k));
    Plotly.animate(gd, [names[k]], {mode: 'immediate', frame: {duration: 0, redraw: true},
                                   transition: {duration: 0}});
    Plotly.relayout(gd, {'sliders[0].active': k});
  }
  seek();
  window.addEventListener('hashchange', seek);
})();
"""


def html_text(fig, *, frame_names: list[str] | None = None, times=None) -> str:
    """The figure as one self-contained HTML page (plotly.js embedded: works offline and from disk). An
    animation page also seeks to ``#frame=K`` / ``#t=SECONDS`` given in its address."""
    post = None
    if frame_names:
        post = _SEEK_SCRIPT % (json.dumps(frame_names), json.dumps([float(t) for t in times]))
    return fig.to_html(include_plotlyjs=True, full_html=True, post_script=post, auto_play=False,
                       config=dict(displaylogo=False, responsive=True))


def write_html(fig, path, **kwargs) -> Path:
    """Write :func:`html_text` atomically."""
    from uvms.output import atomic_write_text

    path = Path(path)
    atomic_write_text(path, html_text(fig, **kwargs))
    return path
