"""Static 3-D pictures with matplotlib (PNG, PDF, SVG for papers) and the frames of videos (mp4, gif).

Draws the same :class:`~uvms.view.scene.Snapshot` as :mod:`uvms.view.plotly_html`, with the same colours and
the same orientation (the world's up drawn up: in ned, x north, y east, z down, the y and z axes reversed, z
downwards on the page and the picture unmirrored; in enu, z up, no axis reversed), equal scales on the three
axes.
"""

from __future__ import annotations

import numpy as np

from uvms.view.plotly_html import (AXIS_COLORS, COB_COLOR, COM_COLOR, EE_TRAIL_COLOR, JOINT_COLOR, THRUSTER_COLOR,
                                   VEHICLE_TRAIL_COLOR, WORLD_LABELS)
from uvms.view.scene import Scene, Snapshot, arrow_head

ELEVATION = 22.0
"""Camera elevation [deg] (matplotlib ``view_init``), above the horizontal plane in the picture."""
AZIMUTH = 45.0
"""Camera azimuth [deg] (matplotlib ``view_init``, measured in the drawn axes)."""


def new_figure(size=(8.0, 7.0)):
    """A matplotlib Figure (no pyplot, no window) with one 3-D axes."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, layout="constrained")
    ax = fig.add_subplot(projection="3d")
    return fig, ax


def style_axes(ax, ranges: np.ndarray, title: str, scene: Scene | None = None) -> None:
    """Equal scales, the axes of :attr:`Scene.reversed_axes` reversed (y and z in ned: seen unmirrored, down is
    down; none in enu), labelled axes (ned without a scene)."""
    labels = WORLD_LABELS if scene is None else scene.world_labels
    reverse = (False, True, True) if scene is None else scene.reversed_axes
    for k, set_lim in enumerate((ax.set_xlim, ax.set_ylim, ax.set_zlim)):
        set_lim(*((ranges[k, 1], ranges[k, 0]) if reverse[k] else (ranges[k, 0], ranges[k, 1])))
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel(f"{labels[0]} [m]")
    ax.set_ylabel(f"{labels[1]} [m]")
    ax.set_zlabel(f"{labels[2]} [m]")
    ax.view_init(elev=ELEVATION, azim=AZIMUTH)
    ax.set_title(title, fontsize="medium")


def _poly(ax, V: np.ndarray, F: np.ndarray, color: str, alpha: float) -> None:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    coll = Poly3DCollection(V[F], facecolors=color, edgecolors=color, linewidths=0.0, alpha=alpha, shade=True)
    ax.add_collection3d(coll)


def _segments(ax, a: np.ndarray, b: np.ndarray, **kwargs) -> None:
    for p, q in zip(np.asarray(a).reshape(-1, 3), np.asarray(b).reshape(-1, 3)):
        ax.plot([p[0], q[0]], [p[1], q[1]], [p[2], q[2]], **kwargs)


def draw_world(ax, scene: Scene) -> None:
    """The world axes at the origin, labelled."""
    L = scene.world_axis_length
    for a in range(3):
        tip = L * np.eye(3)[a]
        ax.plot([0, tip[0]], [0, tip[1]], [0, tip[2]], color=AXIS_COLORS[a], lw=1.2, ls=":")
        ax.text(*(1.12 * tip), scene.world_labels[a], color=AXIS_COLORS[a], fontsize=9)


def draw_snapshot(ax, scene: Scene, snap: Snapshot, *, labels: bool = True) -> None:
    """Shapes, body triads, joint axes, centres of mass and buoyancy, thruster arrows."""
    for prim, (V, F) in zip(scene.primitives, snap.meshes):
        _poly(ax, V, F, prim.color, max(prim.opacity, 0.2))
    L = scene.triad_length
    for a in range(3):
        _segments(ax, snap.frame_origin, snap.frame_origin + L * snap.frame_axes[:, :, a], color=AXIS_COLORS[a],
                  lw=1.6)
    _segments(ax, snap.joint_axis[:, 0], snap.joint_axis[:, 1], color=JOINT_COLOR, lw=2.2, ls="--")
    ax.scatter(*snap.com.T, color=COM_COLOR, s=18, marker="o", depthshade=False, label="centre of mass")
    ax.scatter(*snap.cob.T, color=COB_COLOR, s=22, marker="D", depthshade=False, label="centre of buoyancy")
    if scene.thrusters:
        _segments(ax, snap.thruster_base, snap.thruster_tip, color=THRUSTER_COLOR, lw=2.5)
        for b, t, thr in zip(snap.thruster_base, snap.thruster_tip, scene.thrusters):
            if np.linalg.norm(t - b) > 1e-6:   # no head on a zero thrust
                V, F = arrow_head(b, t, 0.3 * scene.arrow_length)
                _poly(ax, V, F, THRUSTER_COLOR, 1.0)
            if labels:
                ax.text(*t, " " + thr.name, color=THRUSTER_COLOR, fontsize=8)


def draw_trails(ax, vehicle: np.ndarray, ee: np.ndarray) -> None:
    ax.plot(*vehicle.T, color=VEHICLE_TRAIL_COLOR, lw=1.5, label="vehicle trail")
    ax.plot(*ee.T, color=EE_TRAIL_COLOR, lw=1.5, label="end-effector trail")


def draw_target(ax, scene: Scene, target: Snapshot) -> None:
    L = 1.3 * scene.triad_length
    o = target.frame_origin[0]
    for a in range(3):
        tip = o + L * target.frame_axes[0, :, a]
        ax.plot([o[0], tip[0]], [o[1], tip[1]], [o[2], tip[2]], color=AXIS_COLORS[a], lw=1.0, ls="--")
    ax.scatter(*o, color="#444444", marker="x", s=30, depthshade=False, label="target (initial pose)")


def legend(ax, scene: Scene) -> None:
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color=AXIS_COLORS[0], lw=2, label="x axes (red), y green, z blue"),
               Line2D([], [], color=JOINT_COLOR, lw=2, ls="--", label="joint axes")]
    if scene.thrusters:
        handles.append(Line2D([], [], color=THRUSTER_COLOR, lw=2.5, label="thrusters"))
    existing, names = ax.get_legend_handles_labels()
    ax.legend(handles=handles + existing, labels=[h.get_label() for h in handles] + names, loc="upper left",
              fontsize=8, framealpha=0.8)


def draw_water(ax, water, k: int = 0) -> None:
    """The free surface and current arrows of frame ``k`` of a :class:`uvms.view.water.Water`."""
    from uvms.view.water import ARROW_COLOR, SURFACE_COLOR

    X, Y = np.meshgrid(water.x, water.y)
    ax.plot_surface(X, Y, water.heights[k], color=SURFACE_COLOR, alpha=0.35, linewidth=0, shade=False)
    if water.starts.shape[0]:
        _segments(ax, water.starts, water.starts + water.scale * water.velocities[k], color=ARROW_COLOR, lw=1.2)


def pose_figure(scene: Scene, snap: Snapshot, ranges: np.ndarray, *, title: str, water=None):
    """A matplotlib Figure of ``scene`` at one pose (with ``water``, a :class:`uvms.view.water.Water`, if
    given)."""
    fig, ax = new_figure()
    draw_world(ax, scene)
    if water is not None:
        draw_water(ax, water)
    draw_snapshot(ax, scene, snap)
    style_axes(ax, ranges, title, scene)
    legend(ax, scene)
    return fig
