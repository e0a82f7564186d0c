"""The water drawn by ``uvms show --scenario`` and ``uvms animate``: the free surface and flow arrows.

Drawn from the arrays of a scenario's fluid object (:func:`uvms.sim.scenario.environment.flow_parts`), without
interpolating anything the fluid object computes: the surface is the wave elevation
(:func:`uvms.hydro.waves.elevation`) on a grid around what is drawn, ``z = surface - eta`` in a ``ned`` world
(z down) and ``surface + eta`` in ``enu``; the arrows are the current where it is given, at a depth profile's
knots (a column above the vehicle's start) or at a gridded field's nodes (at most :data:`MAX_ARROWS`, the
field's time nearest the frame), each plus the uniform current at the frame's time. The waves' particle
velocities are not drawn as arrows (``docs/environment.md``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from uvms.hydro.waves import elevation

GRID = 25
"""Points per side of the drawn surface."""
MAX_ARROWS = 150
"""Most flow arrows drawn."""
SURFACE_COLOR = "#3d8fd1"
ARROW_COLOR = "#0b5394"


@dataclass(frozen=True)
class Water:
    """What is drawn of the water at each frame.

    Attributes:
        x, y: ``(nx,)``, ``(ny,)`` world grid of the surface [m].
        heights: ``(N, ny, nx)`` world z of the free surface at each frame [m].
        starts: ``(A, 3)`` world points of the arrows [m].
        velocities: ``(N, A, 3)`` world current at each arrow and frame [m/s].
        scale: arrow length per speed [s] (the fastest arrow of the replay is ``0.4`` of the surface's half width).
    """

    x: np.ndarray
    y: np.ndarray
    heights: np.ndarray
    starts: np.ndarray
    velocities: np.ndarray
    scale: float

    def points(self) -> np.ndarray:
        """Corners of the surface at its extreme heights and the arrows' ends (for the plot's ranges)."""
        corners = [[x, y, z] for x in (self.x[0], self.x[-1]) for y in (self.y[0], self.y[-1])
                   for z in (self.heights.min(), self.heights.max())]
        ends = (self.starts[None] + self.scale * self.velocities).reshape(-1, 3)
        return np.vstack([np.array(corners), self.starts, ends])


def flow_of_scenario(scenario) -> dict[str, Any] | None:
    """The keyword arguments of the fluid object of a scenario with waves or a current varying in space
    (:meth:`uvms.sim.scenario.Scenario.flow_parts`), else ``None`` (still water: nothing drawn)."""
    from uvms.sim.scenario.environment import has_real_water

    return scenario.flow_parts() if has_real_water(scenario.spec) else None


def water_drawing(parts: dict[str, Any], convention: str, times, around) -> Water:
    """The :class:`Water` of a fluid object's keyword arguments ``parts`` at ``times`` [s], on a square around
    the world points ``around`` ``(M, 3)`` (the drawn vehicle and arm) with a margin of 1 m, at least 4 m wide."""
    times = np.atleast_1d(np.asarray(times, dtype=float))
    around = np.atleast_2d(np.asarray(around, dtype=float))
    down = 1.0 if convention == "ned" else -1.0           # world z of a depth d: surface + down * d
    centre = 0.5 * (around[:, :2].min(axis=0) + around[:, :2].max(axis=0))
    half = max(2.0, 0.5 * float(np.ptp(around[:, :2], axis=0).max()) + 1.0)
    x = np.linspace(centre[0] - half, centre[0] + half, GRID)
    y = np.linspace(centre[1] - half, centre[1] + half, GRID)
    X, Y = np.meshgrid(x, y)
    surface = float(parts["surface"])
    heights = np.full((times.size, GRID, GRID), surface)
    if parts.get("waves") is not None:
        for k, t in enumerate(times):
            heights[k] -= down * elevation(parts["waves"], t, X, Y)
    starts, local = _arrows(parts, centre, surface, down, around, times)
    uniform = np.stack([np.interp(times, parts["times"], parts["velocity"][:, j]) for j in range(3)], axis=-1)
    velocities = local + uniform[:, None, :]
    fastest = float(np.linalg.norm(velocities, axis=-1).max()) if velocities.size else 0.0
    return Water(x=x, y=y, heights=heights, starts=starts, velocities=velocities,
                 scale=0.4 * half / fastest if fastest > 0 else 0.0)


def _arrows(parts, centre, surface, down, around, times) -> tuple[np.ndarray, np.ndarray]:
    """Arrow points ``(A, 3)`` and the non-uniform current there ``(N, A, 3)`` (module doc)."""
    profile, field = parts.get("profile"), parts.get("field")
    if profile is not None:
        deepest = max(0.0, float(np.max(down * (around[:, 2] - surface)))) + 1.0
        keep = profile.depth <= deepest
        keep[0] = True                                                     # at least the shallowest knot
        depth = profile.depth[keep]
        pick = np.unique(np.linspace(0, depth.size - 1, min(depth.size, 12)).round().astype(int))
        depth = depth[pick]
        starts = np.column_stack([np.full(depth.size, centre[0]), np.full(depth.size, centre[1]),
                                  surface + down * depth])
        values = profile.velocity[keep][pick]
        return starts, np.broadcast_to(values, (times.size, *values.shape)).copy()
    if field is not None:
        Z, Y, X = np.meshgrid(field.z, field.y, field.x, indexing="ij")
        nodes = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
        pick = np.unique(np.linspace(0, nodes.shape[0] - 1, min(nodes.shape[0], MAX_ARROWS)).round().astype(int))
        nearest = np.abs(field.t[None, :] - times[:, None]).argmin(axis=1)
        values = field.velocity.reshape(field.t.size, -1, 3)[:, pick][nearest]
        return nodes[pick], values
    return np.zeros((0, 3)), np.zeros((times.size, 0, 3))


def _arrow_lines(water: Water, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each arrow as a segment ``start -> start + scale v``, separated by ``None`` gaps (plotly lines)."""
    ends = water.starts + water.scale * water.velocities[k]
    n = water.starts.shape[0]
    xyz = np.full((3 * n, 3), np.nan)
    xyz[0::3], xyz[1::3] = water.starts, ends
    return xyz[:, 0], xyz[:, 1], xyz[:, 2]


def water_traces(water: Water, k: int) -> list:
    """The plotly traces of frame ``k``: the surface, then the arrows."""
    import plotly.graph_objects as go

    x, y, z = _arrow_lines(water, k)
    return [go.Surface(x=water.x, y=water.y, z=water.heights[k], name="free surface", showscale=False,
                       opacity=0.45, colorscale=[[0, SURFACE_COLOR], [1, SURFACE_COLOR]], showlegend=True,
                       hoverinfo="skip"),
            go.Scatter3d(x=x, y=y, z=z, mode="lines", name="current", line=dict(color=ARROW_COLOR, width=3),
                         connectgaps=False)]


def water_frame_data(water: Water, k: int) -> list[dict]:
    """What changes in frame ``k`` (merged into :func:`water_traces`' traces)."""
    x, y, z = _arrow_lines(water, k)
    return [dict(type="surface", z=water.heights[k]), dict(type="scatter3d", x=x, y=y, z=z)]
