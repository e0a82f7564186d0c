"""The paper's Figures 4-8 from three runs (fixed, released, controlled), with matplotlib (Agg), and a 3-D
replay of case 2 beside case 3 (plotly, through :mod:`uvms.view`).

Each figure function takes :class:`~uvms.sim.result.Result` objects and a file path (``.png``, ``.svg`` or
``.pdf``: the format from the extension), draws one figure with a title, axis labels with units and, where it
has more than one entry, a legend, writes it atomically (temporary file + rename) and returns its caption.
Every number in a subtitle or caption is computed from the runs drawn, never a fixed string. Lengths are in
millimetres where they stay small (:func:`uvms.plots.length_unit`); X-Y paths are maps, east right and north up
(:func:`uvms.plots.draw_path`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

CASE_STYLE = {
    "fixed": dict(label="URV fixed, control off", color="0.25", linestyle="--"),
    "released": dict(label="URV released, control off", color="tab:red", linestyle="-"),
    "controlled": dict(label="URV released, control on (smc-ab)", color="tab:blue", linestyle="-"),
}
PAPER_ORDER = ("fixed", "released", "controlled")
"""The cases in the paper's order (its legends: case 1, 2, 3)."""
AXES = ("surge", "sway", "yaw")
VISIBLE = 0.2
"""Fig. 6 draws epsilon in a panel when the data reach at least this fraction of it (otherwise it would squash
the data to a line, and the subtitle states it instead); Fig. 7 always draws Phi and adds an inset of ``s`` on
its own scale below this fraction."""


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path: Path) -> Path:
    import matplotlib

    from uvms.plots import save_figure

    fig.tight_layout()
    try:
        with matplotlib.rc_context({"svg.fonttype": "none", "pdf.fonttype": 42}):   # text stays text
            return save_figure(fig, path, dpi=120)
    finally:
        _pyplot().close(fig)


def _title(ax, head: str, note: str, width: int = 80) -> None:
    """``head`` and the computed ``note`` (wrapped) as the panel's title."""
    import textwrap

    ax.set_title(head + "\n" + textwrap.fill(note, width), fontsize=9)


def fig4_ee_path(results: dict, path) -> str:
    """End-effector path in the world X-Y plane for the three cases (paper Figure 4), as a map (east right,
    north up), start and end marked, arrows for the direction, legend in the paper's order."""
    from matplotlib.lines import Line2D

    from uvms.plots import draw_path, length_unit

    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 6.0))
    cases = [c for c in PAPER_ORDER if c in results]
    scale, unit = length_unit(*(results[c].end_effector[:, :2] for c in cases))
    draw_order = [c for c in ("released", "controlled", "fixed") if c in results]    # fixed (dashed) on top
    for case in draw_order:
        ee = results[case].end_effector * scale
        st = CASE_STYLE[case]
        draw_path(ax, ee[:, 0], ee[:, 1], color=st["color"], arrows=2 if case != "controlled" else 0,
                  line={"linestyle": st["linestyle"], "linewidth": 2.6 if case == "controlled" else 1.4,
                        "zorder": 3 if case == "fixed" else 2})
    handles = [Line2D([], [], color=CASE_STYLE[c]["color"], linestyle=CASE_STYLE[c]["linestyle"],
                      linewidth=2.6 if c == "controlled" else 1.4, label=CASE_STYLE[c]["label"]) for c in cases]
    handles += [Line2D([], [], marker="o", color="0.3", markerfacecolor="white", linestyle="", label="start"),
                Line2D([], [], marker="s", color="0.3", linestyle="", label="end")]
    ax.legend(handles=handles, loc="best", fontsize=8)
    ax.set_xlabel(f"Y (east) [{unit}]")
    ax.set_ylabel(f"X (north) [{unit}]")
    note = "End-effector path in the world X-Y plane"
    if "fixed" in results:
        dev = {c: float(np.linalg.norm(results[c].end_effector - results["fixed"].end_effector, axis=1).max())
               for c in cases if c != "fixed"}
        note += ("; peak distance from the fixed-base path: "
                 + ", ".join(f"{c} {d * 1e3:.3g} mm" for c, d in dev.items()))
    _title(ax, "Fig. 4: end-effector path in the world X-Y plane", note.split("; ", 1)[-1], width=70)
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, alpha=0.3)
    _save(fig, path)
    return note


def _error_figure(result, series, title: str, path, *, epsilon: float | None = None) -> str:
    from uvms.plots import length_unit

    plt = _pyplot()
    fig, axes = plt.subplots(3, 1, figsize=(7.0, 6.6), sharex=True)
    t = result.time
    e = series["error"]
    units = [length_unit(e[:, j]) for j in range(2)]            # per panel: millimetres where small
    yaw = np.degrees(np.unwrap(e[:, 2]))                          # unwrapped past 180 deg
    peaks = [float(np.abs(e[:, 0]).max()), float(np.abs(e[:, 1]).max())]
    hidden = []
    for j, ax in enumerate(axes):
        scale, unit = units[j] if j < 2 else (1.0, "deg")
        y = yaw if j == 2 else e[:, j] * scale
        ax.plot(t, y, color="tab:blue" if epsilon is not None else "tab:red", label="body-frame error")
        if epsilon is not None and j < 2:
            if peaks[j] >= VISIBLE * epsilon:
                ax.axhline(epsilon * scale, color="0.4", linestyle=":", label=r"$\pm\varepsilon = \Phi/\lambda$")
                ax.axhline(-epsilon * scale, color="0.4", linestyle=":")
                ax.legend(loc="best", fontsize=8)
            else:
                hidden.append("xy"[j])
        ax.set_ylabel(f"{'xy'[j]} error [{unit}]" if j < 2 else "yaw error [deg]")
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    peak_xy = float(np.hypot(e[:, 0], e[:, 1]).max())
    note = (f"peak abs body-frame error x {peaks[0] * units[0][0]:.3g} {units[0][1]}, "
            f"y {peaks[1] * units[1][0]:.3g} {units[1][1]}, "
            f"yaw {np.abs(yaw).max():.3g} deg")
    if epsilon is not None:
        ratio = peak_xy / epsilon
        where = "within" if ratio <= 1 else "outside"
        note += (f"; peak xy error {peak_xy * 1e3:.3g} mm = {ratio:.2g} epsilon: {where} the guaranteed bound "
                 f"epsilon = Phi/lambda = {epsilon * 1e3:.3g} mm")
        if hidden:
            note += f" (not drawn on the {' and '.join(hidden)} panel{'s' if len(hidden) > 1 else ''}: "
            note += f"beyond {'their' if len(hidden) > 1 else 'its'} axes)"
    _title(axes[0], title, note, width=85)
    _save(fig, path)
    return note


def fig5_uncontrolled(result, series, path) -> str:
    """Vehicle position and heading errors in the body frame, released without control (Figure 5)."""
    return _error_figure(result, series, "Fig. 5: uncontrolled URV location errors (body frame)", path)


def fig6_controlled(result, series, path, epsilon: float) -> str:
    """Vehicle position and heading errors in the body frame with smc-ab (Figure 6), with +/- epsilon where
    the data reach it; the subtitle states the peak error against epsilon, whatever the run."""
    return _error_figure(result, series, "Fig. 6: controlled URV location errors (body frame)", path,
                         epsilon=epsilon)


def fig7_axes(result, phi: float):
    """Figure 7 drawn, not saved: ``(figure, axes, note)``. Each panel shows ``s`` of one axis and the boundary
    layer +/- Phi, always inside the panel's limits (the y range covers +/- 1.15 max(max abs(s), Phi)); where
    ``s`` stays below :data:`VISIBLE` of Phi, and would be a flat line at that scale, an inset repeats it on its
    own scale. Surge and sway in mm/s, yaw in mrad/s when small."""
    plt = _pyplot()
    fig, axes = plt.subplots(3, 1, figsize=(7.0, 6.6), sharex=True)
    ratios = []
    for j, ax in enumerate(axes):
        s = result.signals.get(f"s_{AXES[j]}")
        s = np.zeros_like(result.time) if s is None else np.asarray(s, dtype=float)
        peak = float(np.nanmax(np.abs(s))) if np.isfinite(s).any() else 0.0
        ratios.append(peak / phi)
        small = max(peak, phi) < 0.1
        scale = 1e3 if small else 1.0
        unit = ("mm/s" if small else "m/s") if j < 2 else ("mrad/s" if small else "rad/s")
        ax.plot(result.time, s * scale, color="tab:blue", label="s")
        ax.axhline(phi * scale, color="tab:red", linestyle="--", label=r"$\pm\Phi$ boundary layer")
        ax.axhline(-phi * scale, color="tab:red", linestyle="--")
        limit = 1.15 * max(peak, phi) * scale
        ax.set_ylim(-limit, limit)
        if 0 < peak < VISIBLE * phi:
            inset = ax.inset_axes([0.62, 0.08, 0.36, 0.36])
            inset.plot(result.time, s * scale, color="tab:blue", linewidth=0.8)
            inset.set_title("s, own scale", fontsize=7)
            inset.tick_params(labelsize=6)
        ax.legend(loc="upper left", fontsize=8)
        ax.set_ylabel(f"s {AXES[j]} [{unit}]")
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    note = "max abs(s) / Phi: " + ", ".join(f"{a} {r:.2g}" for a, r in zip(AXES, ratios))
    zoomed = [a for a, r in zip(AXES, ratios) if 0 < r < VISIBLE]
    if zoomed:
        note += f"; inset: s on its own scale ({', '.join(zoomed)})"
    _title(axes[0], "Fig. 7: sliding variables and boundary layer", note, width=85)
    return fig, axes, note


def fig7_sliding(result, path, phi: float) -> str:
    """``s`` per axis with the boundary layer +/- Phi inside every panel (Figure 7, :func:`fig7_axes`),
    written to ``path``; returns the caption."""
    fig, _, note = fig7_axes(result, phi)
    _save(fig, path)
    return note


def fig8_control(result, path) -> str:
    """Commanded surge and sway forces and yaw moment (Figure 8)."""
    from uvms.control.compare import sign_changes

    plt = _pyplot()
    fig, axes = plt.subplots(3, 1, figsize=(7.0, 6.6), sharex=True)
    parts = []
    for ax, (name, label, unit) in zip(axes, (("X", "X (surge)", "N"), ("Y", "Y (sway)", "N"),
                                              ("N", "N (yaw)", "N m"))):
        c = result.signals.get(f"command_{name}")
        if c is not None:
            ax.plot(result.time, c, color="tab:green")
            parts.append(f"{name} peak {np.nanmax(np.abs(c)):.3g} {unit}, {sign_changes(c)} slope sign changes")
        ax.set_ylabel(f"{label} [{unit}]")
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    note = "commanded body wrench: " + "; ".join(parts)
    _title(axes[0], "Fig. 8: control activity (commanded body wrench)", "; ".join(parts), width=85)
    _save(fig, path)
    return note


# -- case 2 beside case 3 in 3-D

def case_animation(released, controlled, model, path, *, fixed=None, thrusters=None, fps: float = 10.0,
                   max_frames: int = 120) -> Path:
    """Case 2 (released, control off) and case 3 (controlled) replayed side by side on one time slider, in
    two 3-D scenes with the same axes ranges (:mod:`uvms.view`: the same scene, frame sampling and page as
    ``uvms animate``); ``fixed`` adds the fixed case's end-effector path, dashed, to both. One self-contained
    HTML page, written atomically."""
    import plotly.graph_objects as go

    from uvms.view.animate import replay
    from uvms.view.plotly_html import (add_player, moving_points, moving_traces, scene_layout, world_traces,
                                       write_html)
    from uvms.view.scene import equal_ranges

    runs = (("case 2: released, control off", released, ()),          # no control, no thrusters drawn
            ("case 3: released, control on (smc-ab)", controlled, thrusters))
    replays = [replay(res, model, fps=fps, max_frames=max_frames, thrusters=th, title=name)
               for name, res, th in runs]
    n = min(len(rp.snaps) for rp in replays)
    points = np.vstack([s.points() for rp in replays for s in rp.snaps[:n]]
                       + [1.15 * replays[0].scene.world_axis_length * np.eye(3)])
    ranges = equal_ranges(points)
    static, moving, kinds, scene_of = [], [], [], []
    for i, rp in enumerate(replays):
        sc = "scene" if i == 0 else "scene2"
        for tr in world_traces(rp.scene):
            static.append(tr.update(scene=sc))
        if fixed is not None:
            ee = fixed.end_effector
            static.append(go.Scatter3d(x=ee[:, 0], y=ee[:, 1], z=ee[:, 2], mode="lines", scene=sc,
                                       name="fixed case's end-effector path", showlegend=i == 0,
                                       line=dict(color="#444", width=3, dash="dash")))
    for i, rp in enumerate(replays):
        sc = "scene" if i == 0 else "scene2"
        trs = moving_traces(rp.scene, rp.snaps[0]) + [
            go.Scatter3d(x=rp.vehicle_path[:1, 0], y=rp.vehicle_path[:1, 1], z=rp.vehicle_path[:1, 2], mode="lines",
                         name="vehicle trail", line=dict(color="#b8860b", width=4)),
            go.Scatter3d(x=rp.ee_path[:1, 0], y=rp.ee_path[:1, 1], z=rp.ee_path[:1, 2], mode="lines",
                         name="end-effector trail", line=dict(color="#e377c2", width=4))]
        for tr in trs:
            tr.update(scene=sc)
            if i == 1:
                tr.update(showlegend=False)
            moving.append(tr)
            kinds.append(tr.type)
            scene_of.append(i)

    def positions(k: int) -> list:
        pts = []
        for rp in replays:
            pts += moving_points(rp.scene, rp.snaps[k]) + [np.asarray(rp.vehicle_path[: k + 1], dtype=np.float32),
                                                           np.asarray(rp.ee_path[: k + 1], dtype=np.float32)]
        return [dict(type=kind, x=p[:, 0], y=p[:, 1], z=p[:, 2]) for kind, p in zip(kinds, pts, strict=True)]

    index = list(range(len(static), len(static) + len(moving)))
    names = [str(k) for k in range(n)]
    times = replays[0].times[:n]
    frames = [go.Frame(data=positions(k), traces=index, name=names[k]) for k in range(n)]
    fig = go.Figure(data=static + moving, frames=frames)
    title = "Paper Section 6: case 2 (left) and case 3 (right), the same time, the same axes"
    layout = scene_layout(ranges, title, replays[0].scene)
    left, right = dict(layout["scene"]), dict(layout["scene"])
    left["domain"] = dict(x=[0.15, 0.575], y=[0.08, 0.95])               # the legend on the left of both
    right["domain"] = dict(x=[0.575, 1.0], y=[0.08, 0.95])
    layout["scene"], layout["scene2"] = left, right
    layout["annotations"] = [dict(text=rp.title, x=0.3625 + 0.425 * i, y=0.97, xref="paper", yref="paper",
                                  showarrow=False, font=dict(size=12)) for i, rp in enumerate(replays)]
    add_player(layout, fps=replays[0].fps, times=times, names=names)
    layout["legend"].update(y=0.12)
    layout["margin"] = dict(l=0, r=0, t=40, b=70)
    fig.update_layout(**layout)
    return write_html(fig, path, frame_names=names, times=times)
