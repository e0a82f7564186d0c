"""Figures of saved runs (matplotlib, object-oriented API: no pyplot, no global state, any backend).

Each ``plot_*`` function draws one panel onto a given ``Axes`` from a run's table (the pandas DataFrame of
``result.csv``, column names as in :meth:`uvms.sim.result.Result.columns`) and returns the ``Axes``;
:func:`timeseries_figure` assembles them. Angles are drawn in degrees for the vehicle and radians for the
joints; world axes as the run's frame convention says (x north, y east, z down for `ned`; x, y, z up for `enu`).
"""

from __future__ import annotations

import os
import re
import tempfile
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

from uvms.output import naming, publish

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

_STATE_COLUMN = re.compile(
    r"t_s|[xyz]_m|(roll|pitch|yaw)_rad|[pqr]_rad_s|[uvw]_m_s|ee_[xyz]_m|actuator\d+")   # and the joints' columns
_FORCE_AXES = {"command_X": "X (surge)", "command_Y": "Y (sway)", "command_Z": "Z (heave)"}
_MOMENT_AXES = {"command_K": "K (roll)", "command_M": "M (pitch)", "command_N": "N (yaw)"}


def literal(text: str) -> str:
    """``text`` drawn as written: a ``$`` in a run or signal name is not taken as the start of mathtext."""
    return text.replace("$", r"\$")


def _style(ax: Axes, title: str, ylabel: str, xlabel: str = "time t [s]") -> Axes:
    ax.set_title(literal(title))
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.4)
    if len(ax.get_legend_handles_labels()[0]) > 1:      # a single entry says nothing the axis label does not
        ax.legend(fontsize="small", loc="best")
    return ax


SMALL_LENGTH = 0.1
"""[m] Lengths whose largest magnitude is below this are drawn in millimetres."""


def length_unit(*values) -> tuple[float, str]:
    """``(scale, unit)`` to draw lengths given in metres: ``(1e3, "mm")`` when every finite value is below
    :data:`SMALL_LENGTH` in magnitude, else ``(1.0, "m")``."""
    import numpy as np

    finite = [np.abs(np.asarray(v, dtype=float)) for v in values]
    peak = max((float(np.nanmax(v)) for v in finite if v.size and np.isfinite(v).any()), default=0.0)
    return (1e3, "mm") if peak < SMALL_LENGTH else (1.0, "m")


def draw_path(ax: Axes, north, east, *, color: str, label: str | None = None, line: dict | None = None,
              markers: bool = True, arrows: int = 2) -> None:
    """A path in the world's horizontal plane, drawn as a map: east to the right, north up (the one orientation
    of every X-Y path in uvms: ``uvms plot`` and the paper's Figure 4). The start is a circle, the end a
    square, and ``arrows`` arrowheads along the path (at equal arc-length fractions) show the direction.
    ``line``: ``linestyle`` (default ``"-"``), ``linewidth`` (1.5) and ``zorder`` (2)."""
    import numpy as np

    line = {"linestyle": "-", "linewidth": 1.5, "zorder": 2, **(line or {})}
    linestyle, linewidth, zorder = line["linestyle"], line["linewidth"], line["zorder"]

    north, east = np.asarray(north, dtype=float), np.asarray(east, dtype=float)
    ax.plot(east, north, color=color, linestyle=linestyle, linewidth=linewidth, zorder=zorder, label=label)
    if markers and north.size:
        ax.plot(east[0], north[0], "o", color=color, markersize=6, zorder=zorder + 0.1, markerfacecolor="white")
        ax.plot(east[-1], north[-1], "s", color=color, markersize=6, zorder=zorder + 0.1)
    steps = np.hypot(np.diff(east), np.diff(north))
    length = float(np.nansum(steps))
    if arrows and length > 0:
        arc = np.concatenate([[0.0], np.nancumsum(steps)])
        for frac in (np.arange(arrows) + 1) / (arrows + 1):
            k = int(min(np.searchsorted(arc, frac * length), len(arc) - 2))
            j = int(min(np.searchsorted(arc, frac * length + 0.02 * length), len(arc) - 1))
            if j > k:
                ax.annotate("", xy=(east[j], north[j]), xytext=(east[k], north[k]), zorder=zorder + 0.2,
                            arrowprops=dict(arrowstyle="-|>", color=color, lw=linewidth, mutation_scale=14))


def _present(table, names) -> list[str]:
    """The columns of ``names`` in ``table`` that hold at least one number."""
    return [c for c in names if c in table.columns and table[c].notna().any()]


def joint_columns(table, kind: str) -> list[tuple[str, str]]:
    """``(joint, column)`` of every joint's ``kind`` column (``"q"``, ``"qd"`` or ``"tau"``) present in the
    table, in joint order (named ``q_<joint>_rad`` ..., or an older file's ``q1_rad``: :mod:`uvms.sim.columns`)."""
    from uvms.sim.columns import table_joints

    tokens, columns = table_joints(table.columns)
    return [(t, c) for t, c in zip(tokens, getattr(columns, kind)) if c in table.columns]


def controller_columns(table) -> list[str]:
    """Columns that are controller or actuator signals (everything that is not a state column)."""
    from uvms.sim.columns import table_joints

    joints = set(table_joints(table.columns)[1].all())
    return [c for c in table.columns if not _STATE_COLUMN.fullmatch(c) and c not in joints and table[c].notna().any()]


def plot_vehicle_position(ax: Axes, table) -> Axes:
    """Vehicle position x, y, z in the world frame [m, or mm when it stays within :data:`SMALL_LENGTH`]."""
    scale, unit = length_unit(*(table[f"{a}_m"] for a in "xyz"))
    for axis, label in zip("xyz", _POSITION_LABELS[_frame(table)]):
        ax.plot(table["t_s"], table[f"{axis}_m"] * scale, label=label)
    return _style(ax, "Vehicle position (world frame)", f"position [{unit}]")


def plot_euler_angles(ax: Axes, table) -> Axes:
    """Vehicle roll, pitch and yaw [deg]."""
    import numpy as np

    for name in ("roll", "pitch", "yaw"):
        ax.plot(table["t_s"], np.degrees(table[f"{name}_rad"]), label=name)
    return _style(ax, "Vehicle orientation (ZYX Euler angles)", "angle [deg]")


def plot_joint_angles(ax: Axes, table) -> Axes:
    """Joint angles q_i [rad]."""
    for joint, c in joint_columns(table, "q"):
        ax.plot(table["t_s"], table[c], label=joint)
    return _style(ax, "Joint angles", "angle [rad]")


def plot_joint_torques(ax: Axes, table) -> Axes:
    """Applied joint torques tau_i [N m]."""
    for joint, c in joint_columns(table, "tau"):
        ax.plot(table["t_s"], table[c], label=joint, drawstyle="steps-post")
    return _style(ax, "Applied joint torques", "torque [N m]")


def plot_end_effector_path(ax: Axes, table) -> Axes:
    """End-effector path in the world X-Y plane (the paper's Figure 4) as a map seen from above, with the
    vehicle centre's path; start (circle), end (square), direction (arrows). A z-down (``ned``) run is drawn
    east right and north up (:func:`draw_path`); a z-up (``enu``) run x right and y up, which is the same view
    from above of its own right-handed axes."""
    scale, unit = length_unit(table["ee_x_m"], table["ee_y_m"], table["x_m"], table["y_m"])
    ned = _frame(table) == "ned"
    for (x, y), style in ((("ee_x_m", "ee_y_m"), dict(color="tab:blue", label="end effector")),
                          (("x_m", "y_m"), dict(color="tab:gray", line={"linestyle": "--"}, label="vehicle centre",
                                                arrows=1))):
        vertical, horizontal = (table[x], table[y]) if ned else (table[y], table[x])
        draw_path(ax, vertical * scale, horizontal * scale, **style)
    ax.plot([], [], "o", color="0.3", markerfacecolor="white", label="start")
    ax.plot([], [], "s", color="0.3", label="end")
    ax.set_aspect("equal", adjustable="datalim")
    if ned:
        return _style(ax, "End-effector path (world X-Y plane)", f"X (north) [{unit}]", xlabel=f"Y (east) [{unit}]")
    return _style(ax, "End-effector path (world X-Y plane, z up)", f"Y [{unit}]", xlabel=f"X [{unit}]")


def plot_commanded_forces(ax: Axes, table) -> Axes:
    """The controller's commanded body forces X, Y, Z [N]."""
    for c in _present(table, _FORCE_AXES):
        ax.plot(table["t_s"], table[c], label=_FORCE_AXES[c])
    return _style(ax, "Commanded force (body axes)", "force [N]")


def plot_commanded_moments(ax: Axes, table) -> Axes:
    """The controller's commanded body moments K, M, N [N m]."""
    for c in _present(table, _MOMENT_AXES):
        ax.plot(table["t_s"], table[c], label=_MOMENT_AXES[c])
    return _style(ax, "Commanded moment (body axes)", "moment [N m]")


def plot_signals(ax: Axes, table, names: list[str], *, title: str = "Controller signals",
                 ylabel: str = "value [signal units]", strip: str = "", scale: float = 1.0) -> Axes:
    """Named signal columns against time (``strip`` removed from the labels; at most 10 labelled), multiplied
    by ``scale`` (a unit change, e.g. 1e3 for m -> mm)."""
    for k, c in enumerate(names):
        ax.plot(table["t_s"], table[c] * scale, label=literal(c.removeprefix(strip)) if k < 10 else None)
    return _style(ax, title, ylabel)


def plot_sliding_variables(ax: Axes, table, names: list[str], *, ylabel: str = "s [m/s, rad/s]",
                           title: str = "Sliding variables s and boundary layer") -> Axes:
    """Sliding variables ``s_<axis>`` and, when logged as ``Phi``, the boundary layer +/-Phi (dashed)."""
    for c in names:
        ax.plot(table["t_s"], table[c], label=literal(c))
    if "Phi" in table.columns and table["Phi"].notna().any():
        for sign in (1, -1):
            ax.plot(table["t_s"], sign * table["Phi"], "--", color="black", linewidth=0.8,
                    label="boundary layer \u00b1Phi" if sign > 0 else None)
    return _style(ax, title, ylabel)


_GROUPS = {  # signal prefix -> (panel title, unit of the translational axes, unit of the rotational axes)
    "e": ("Station-keeping errors (body frame)", "m", "rad"),
    "f_hat": ("Predicted acceleration f_hat (controller's model)", "m/s^2", "rad/s^2"),
    "k": ("Switching gains k", "m/s^2", "rad/s^2"),
    "b_hat": ("Effective mass / inertia b_hat", "kg", "kg m^2"),
}
_AXIS_SUFFIX = re.compile(r"(.+)_(surge|sway|heave|roll|pitch|yaw|[xyzKMNXYZ])")
_ROTATION = ("roll", "pitch", "yaw", "K", "M", "N")


def split_by_unit(names: list[str]) -> tuple[list[str], list[str]]:
    """Per-axis signal names split into translational (surge, sway, heave, X, Y, Z) and rotational (roll, pitch,
    yaw, K, M, N) ones: one panel, one unit."""
    rotational = [c for c in names if (m := _AXIS_SUFFIX.fullmatch(c)) and m.group(2) in _ROTATION]
    return [c for c in names if c not in rotational], rotational


def signal_groups(names: list[str]) -> dict[str, list[str]]:
    """Signals grouped by quantity: ``s_surge, s_sway -> {"s": [...]}``, ``thrust_cmd_<thruster>`` and
    ``unachieved_<axis>`` by their prefix; others stand alone."""
    groups: dict[str, list[str]] = {}
    for c in names:
        per_thruster = next((p for p in ("thrust_cmd", "unachieved") if c.startswith(p + "_")), None)
        m = _AXIS_SUFFIX.fullmatch(c)
        groups.setdefault(per_thruster or (m.group(1) if m else c), []).append(c)
    return groups


def _panels(table) -> list[Callable[[Axes], Axes]]:
    """The panels to draw for this table, each a function of the ``Axes``."""
    panels: list[Callable[[Axes], Axes]] = [partial(f, table=table) for f in (plot_vehicle_position, plot_euler_angles, plot_joint_angles,
                                                 plot_joint_torques, plot_end_effector_path)]
    if _present(table, _FORCE_AXES):
        panels.append(partial(plot_commanded_forces, table=table))
    if _present(table, _MOMENT_AXES):
        panels.append(partial(plot_commanded_moments, table=table))
    groups = signal_groups([c for c in controller_columns(table) if c not in _FORCE_AXES and c not in _MOMENT_AXES])
    groups.pop("command", None)  # per-axis copies of the commanded wrench
    if "thrust_cmd" in groups:
        panels.append(partial(plot_signals, table=table, names=groups.pop("thrust_cmd"), strip="thrust_cmd_",
                              title="Commanded thrust per thruster", ylabel="thrust [N]"))
    residual = groups.pop("unachieved", [])
    if any(table[c].abs().max() > 1e-6 for c in residual):  # more than round-off
        forces, moments = split_by_unit(residual)
        for names, kind, unit in ((forces, "force", "N"), (moments, "moment", "N m")):
            if names:
                panels.append(partial(plot_signals, table=table, names=names, strip="unachieved_",
                                      title=f"Unachieved {kind} (thrust limits, allocation)",
                                      ylabel=f"{kind} [{unit}]"))
    if "s" in groups:
        linear, angular = split_by_unit(groups.pop("s"))
        for names, unit, part in ((linear, "m/s", "translation"), (angular, "rad/s", "rotation")):
            if names:
                panels.append(partial(plot_sliding_variables, table=table, names=names, ylabel=f"s [{unit}]",
                                      title=f"Sliding variables s and boundary layer ({part})"))
        groups.pop("Phi", None)
    for prefix, (title, unit_linear, unit_angular) in _GROUPS.items():
        if prefix not in groups:
            continue
        linear, angular = split_by_unit(groups.pop(prefix))
        for names, unit, part in ((linear, unit_linear, "translation"), (angular, unit_angular, "rotation")):
            if not names:
                continue
            scale = 1.0
            if unit == "m":
                scale, unit = length_unit(*(table[c] for c in names))
            panels.append(partial(plot_signals, table=table, names=names, title=f"{title}, {part}",
                                  ylabel=f"{prefix} [{unit}]", scale=scale))
    other = [c for names in groups.values() for c in names if table[c].nunique(dropna=True) > 1]
    if other:  # constant signals (parameters logged every update) are left out
        panels.append(partial(plot_signals, table=table, names=other, title="Other controller signals"))
    return panels


DRAW_LIMIT = 1e100
"""Values of larger magnitude are left out of a figure, as NaN and inf are (matplotlib's axis arithmetic
overflows near 1e308: ``Axis limits cannot be NaN or Inf``). A run keeps no such state: divergence stops it at
1e4 m, 1e3 m/s or rad/s, 1e6 of an actuator state."""


def drawable(table):
    """``table`` with every value that is not finite or beyond :data:`DRAW_LIMIT` in magnitude set to NaN (not
    drawn), and how many such values there were."""
    import numpy as np

    values = table.to_numpy(dtype=float)
    hidden = ~np.isfinite(values) | (np.abs(np.nan_to_num(values)) > DRAW_LIMIT)
    count = int(np.count_nonzero(hidden & ~np.isnan(values)))
    if not hidden.any():
        return table, 0
    return table.mask(hidden), count


def check_drawable(table, source: str | None = None) -> None:
    """Refuse a run with nothing to draw: no finite value (within :data:`DRAW_LIMIT`) in any of the columns
    ``uvms plot`` always draws (position, attitude, end effector). One line naming ``source``."""
    import numpy as np

    from uvms.errors import UvmsInputError
    from uvms.sim.result import PLOTTED_COLUMNS

    columns = [c for c in PLOTTED_COLUMNS[1:] if c in table.columns]
    values = table[columns].to_numpy(dtype=float)
    if not np.any(np.isfinite(values) & (np.abs(np.nan_to_num(values)) <= DRAW_LIMIT)):
        raise UvmsInputError(f"nothing to draw: every value of {', '.join(columns)} is NaN, infinite or beyond "
                             f"{DRAW_LIMIT:g}", source)


def _frame(table) -> str:
    """The frame convention of a run's table (``table.attrs["frame"]``, set from the run's metadata; ``ned``
    for older runs)."""
    return table.attrs.get("frame", "ned") if hasattr(table, "attrs") else "ned"


_POSITION_LABELS = {"ned": ("x (north)", "y (east)", "z (down)"), "enu": ("x", "y", "z (up)")}


def timeseries_figure(table, *, title: str | None = None) -> Figure:
    """A multi-panel figure of one run: vehicle position and attitude, joints, end-effector path, and the
    controller's signals when there are any (two panels per row). Values that are not finite or beyond
    :data:`DRAW_LIMIT` are left out (:func:`drawable`) and counted in the title; a run with nothing to draw is
    refused (:func:`check_drawable`)."""
    from matplotlib.figure import Figure

    check_drawable(table)
    table, hidden = drawable(table)
    if hidden:
        note = f"{hidden} value{'s' if hidden > 1 else ''} not finite or beyond {DRAW_LIMIT:g} not drawn"
        title = f"{title}\n({note})" if title else f"({note})"
    panels = _panels(table)
    rows = (len(panels) + 1) // 2
    fig = Figure(figsize=(13, 3.6 * rows), layout="constrained")
    axes = fig.subplots(rows, 2, squeeze=False).ravel()
    for ax, draw in zip(axes, panels):
        draw(ax)
    for ax in axes[len(panels):]:
        ax.set_visible(False)
    if title:
        fig.suptitle(literal(title), fontsize="large")
    return fig


FIGURE_SUFFIXES = (".png", ".pdf", ".svg", ".jpg", ".jpeg")


def check_figure_path(path: str | os.PathLike[str], option: str) -> Path:
    """``path`` as a figure file a command can write (a known image extension, a writable place), or a
    one-line :class:`~uvms.errors.UvmsInputError` naming ``option``; checked before any drawing."""
    from uvms.errors import UvmsInputError
    from uvms.output import check_destination

    path = Path(path)
    if path.suffix.lower() not in FIGURE_SUFFIXES:
        raise UvmsInputError("expected a .png, .pdf, .svg or .jpg file name", str(path), option)
    check_destination(path, option, kind="file")
    return path


def save_figure(fig: Figure, path: str | os.PathLike[str], *, dpi: int = 110) -> Path:
    """Save a figure atomically (a temporary file in the same folder, then a rename); the format from the
    file extension."""
    path = Path(path)
    with naming(path):
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=path.suffix or ".png", dir=path.parent)
        os.close(fd)
        try:
            fig.savefig(tmp, dpi=dpi)
            publish(tmp, path)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
    return path


_SIGNAL_LABELS = {"roll": "roll [deg]", "pitch": "pitch [deg]", "yaw": "yaw change [deg]",
                  "depth": "depth change [{}]", "x": "x change [{}]", "y": "y change [{}]"}


def comparison_figure(times, measured: dict, simulated: dict, *, held: dict | None = None,
                      scores: dict | None = None, title: str | None = None, labels=("log", "uvms")) -> Figure:
    """Log against simulation, one panel per signal (``uvms replay``'s overlay; ``docs/logs.md``).

    ``measured`` and ``simulated`` map signal names (``roll``, ``pitch``, ``yaw``, ``depth``, ``x``, ``y``;
    :mod:`uvms.identify.experiment`) to values at ``times`` [s] in rad and m; angles are drawn in degrees.
    ``held`` (optional) is the no-skill prediction (the start value held), drawn dashed; ``scores`` maps a
    signal to its RMSE (shown in the panel's title)."""
    import numpy as np
    from matplotlib.figure import Figure

    names = [s for s in _SIGNAL_LABELS if s in measured and s in simulated]
    rows = (len(names) + 1) // 2
    fig = Figure(figsize=(12, 3.3 * rows), layout="constrained")
    axes = fig.subplots(rows, 2, squeeze=False).ravel()
    for ax, name in zip(axes, names):
        angle = name in ("roll", "pitch", "yaw")
        scale, unit = (np.degrees(1.0), "deg") if angle else length_unit(measured[name], simulated[name])
        ax.plot(times, scale * np.asarray(measured[name]), color="black", lw=1.4, label=labels[0])
        ax.plot(times, scale * np.asarray(simulated[name]), color="tab:blue", lw=1.2, label=labels[1])
        if held is not None and name in held:
            ax.plot(times, scale * np.asarray(held[name]), color="tab:gray", lw=1.0, ls="--",
                    label="held at start")
        heading = name
        if scores and name in scores:
            heading = f"{name}: RMSE {scores[name] * (1.0 if angle else scale):.3g} {unit}"
        _style(ax, heading, _SIGNAL_LABELS[name].format(unit))
    for ax in axes[len(names):]:
        ax.set_visible(False)
    if title:
        fig.suptitle(literal(title), fontsize="large")
    return fig
