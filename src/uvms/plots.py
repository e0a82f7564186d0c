"""Figures of saved runs (matplotlib, object-oriented API: no pyplot, no global state, any backend).

Each ``plot_*`` function draws one panel onto a given ``Axes`` from a run's table (the pandas DataFrame of
``result.csv``, column names as in :meth:`uvms.sim.result.Result.columns`) and returns the ``Axes``;
:func:`timeseries_figure` assembles them. Angles are drawn in degrees for the vehicle and radians for the
joints; world frame x north, y east, z down.
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
    r"t_s|[xyz]_m|(roll|pitch|yaw)_rad|[pqr]_rad_s|[uvw]_m_s|q\d+_rad|qd\d+_rad_s|tau\d+_Nm|ee_[xyz]_m|actuator\d+")
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
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize="small", loc="best")
    return ax


def _present(table, names) -> list[str]:
    """The columns of ``names`` in ``table`` that hold at least one number."""
    return [c for c in names if c in table.columns and table[c].notna().any()]


def joint_columns(table, prefix: str, suffix: str) -> list[str]:
    """``<prefix>1<suffix>, <prefix>2<suffix>, ...`` present in the table, in joint order."""
    pattern = re.compile(rf"{re.escape(prefix)}(\d+){re.escape(suffix)}")
    found = [(int(m.group(1)), c) for c in table.columns if (m := pattern.fullmatch(c))]
    return [c for _, c in sorted(found)]


def controller_columns(table) -> list[str]:
    """Columns that are controller or actuator signals (everything that is not a state column)."""
    return [c for c in table.columns if not _STATE_COLUMN.fullmatch(c) and table[c].notna().any()]


def plot_vehicle_position(ax: Axes, table) -> Axes:
    """Vehicle position x, y, z in the world frame [m]."""
    for axis, label in zip("xyz", ("x (north)", "y (east)", "z (down)")):
        ax.plot(table["t_s"], table[f"{axis}_m"], label=label)
    return _style(ax, "Vehicle position (world frame)", "position [m]")


def plot_euler_angles(ax: Axes, table) -> Axes:
    """Vehicle roll, pitch and yaw [deg]."""
    import numpy as np

    for name in ("roll", "pitch", "yaw"):
        ax.plot(table["t_s"], np.degrees(table[f"{name}_rad"]), label=name)
    return _style(ax, "Vehicle orientation (ZYX Euler angles)", "angle [deg]")


def plot_joint_angles(ax: Axes, table) -> Axes:
    """Joint angles q_i [rad]."""
    for c in joint_columns(table, "q", "_rad"):
        ax.plot(table["t_s"], table[c], label=c.removesuffix("_rad"))
    return _style(ax, "Joint angles", "angle [rad]")


def plot_joint_torques(ax: Axes, table) -> Axes:
    """Applied joint torques tau_i [N m]."""
    for c in joint_columns(table, "tau", "_Nm"):
        ax.plot(table["t_s"], table[c], label=c.removesuffix("_Nm"), drawstyle="steps-post")
    return _style(ax, "Applied joint torques", "torque [N m]")


def plot_end_effector_path(ax: Axes, table) -> Axes:
    """End-effector path in the world X-Y plane [m] (the paper's Figure 4), start and end marked."""
    x, y = table["ee_x_m"], table["ee_y_m"]
    ax.plot(x, y, label="end effector")
    ax.plot(x.iloc[0], y.iloc[0], "o", color="tab:green", label="start")
    ax.plot(x.iloc[-1], y.iloc[-1], "s", color="tab:red", label="end")
    ax.plot(table["x_m"], table["y_m"], "--", color="tab:gray", label="vehicle centre")
    ax.set_aspect("equal", adjustable="datalim")
    return _style(ax, "End-effector path (world X-Y plane)", "Y (east) [m]", xlabel="X (north) [m]")


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
                 ylabel: str = "value [signal units]", strip: str = "") -> Axes:
    """Named signal columns against time (``strip`` removed from the labels; at most 10 labelled)."""
    for k, c in enumerate(names):
        ax.plot(table["t_s"], table[c], label=literal(c.removeprefix(strip)) if k < 10 else None)
    return _style(ax, title, ylabel)


def plot_sliding_variables(ax: Axes, table, names: list[str]) -> Axes:
    """Sliding variables ``s_<axis>`` and, when logged as ``Phi``, the boundary layer +/-Phi (dashed)."""
    for c in names:
        ax.plot(table["t_s"], table[c], label=literal(c))
    if "Phi" in table.columns and table["Phi"].notna().any():
        for sign in (1, -1):
            ax.plot(table["t_s"], sign * table["Phi"], "--", color="black", linewidth=0.8,
                    label="boundary layer \u00b1Phi" if sign > 0 else None)
    return _style(ax, "Sliding variables s and boundary layer", "s [m/s, rad/s]")


_GROUPS = {  # signal prefix -> (panel title, y label), for the names the sliding-mode controllers log
    "e": ("Station-keeping errors (body frame)", "error [m, rad]"),
    "f_hat": ("Predicted acceleration f_hat (controller's model)", "f_hat [m/s^2, rad/s^2]"),
    "k": ("Switching gains k", "k [m/s^2, rad/s^2]"),
    "b_hat": ("Effective mass / inertia b_hat", "b_hat [kg, kg m^2]"),
}
_AXIS_SUFFIX = re.compile(r"(.+)_(surge|sway|heave|roll|pitch|yaw|[xyzKMNXYZ])")


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
        panels.append(partial(plot_signals, table=table, names=residual, strip="unachieved_",
                              title="Unachieved wrench (thrust limits, allocation)", ylabel="force [N], moment [N m]"))
    if "s" in groups:
        panels.append(partial(plot_sliding_variables, table=table, names=groups.pop("s")))
        groups.pop("Phi", None)
    for prefix, (title, ylabel) in _GROUPS.items():
        if prefix in groups:
            panels.append(partial(plot_signals, table=table, names=groups.pop(prefix), title=title, ylabel=ylabel))
    other = [c for names in groups.values() for c in names if table[c].nunique(dropna=True) > 1]
    if other:  # constant signals (parameters logged every update) are left out
        panels.append(partial(plot_signals, table=table, names=other, title="Other controller signals"))
    return panels


def timeseries_figure(table, *, title: str | None = None) -> Figure:
    """A multi-panel figure of one run: vehicle position and attitude, joints, end-effector path, and the
    controller's signals when there are any (two panels per row)."""
    from matplotlib.figure import Figure

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
