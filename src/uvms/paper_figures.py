"""The paper's Figures 4-8 from three runs (fixed, released, controlled), with matplotlib (Agg).

Each function takes :class:`~uvms.sim.result.Result` objects and a file path, draws one figure with a title,
axis labels with units and a legend, and writes the PNG atomically (temporary file + rename).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

CASE_STYLE = {
    "fixed": dict(label="URV fixed, control off", color="0.25", linestyle="--"),
    "released": dict(label="URV released, control off", color="tab:red", linestyle="-"),
    "controlled": dict(label="URV released, control on (smc-ab)", color="tab:blue", linestyle="-"),
}
AXES = ("surge", "sway", "yaw")


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path: Path) -> Path:
    from uvms.plots import save_figure

    fig.tight_layout()
    try:
        return save_figure(fig, path, dpi=120)
    finally:
        _pyplot().close(fig)


def fig4_ee_path(results: dict, path) -> Path:
    """End-effector path in the world X-Y plane for the three cases (paper Figure 4)."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 5.6))
    order = [c for c in ("released", "controlled", "fixed") if c in results]     # fixed (dashed) drawn on top
    for case in order:
        res = results[case]
        ee = res.end_effector
        width = 2.6 if case == "controlled" else 1.4
        ax.plot(ee[:, 1], ee[:, 0], linewidth=width, zorder=3 if case == "fixed" else 2, **CASE_STYLE[case])
        ax.plot(ee[0, 1], ee[0, 0], "o", color=CASE_STYLE[case]["color"], markersize=4)
    ax.set_xlabel("Y (east) [m]")
    ax.set_ylabel("X (north) [m]")
    ax.set_title("Fig. 4: end-effector path in the world X-Y plane")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    return _save(fig, path)


def _error_figure(result, series, title: str, path, *, scale: float, unit: str, epsilon: float | None = None):
    plt = _pyplot()
    fig, axes = plt.subplots(3, 1, figsize=(7.0, 6.4), sharex=True)
    t = result.time
    e = series["error"]
    off_scale = False
    labels = (f"x error [{unit}]", f"y error [{unit}]", "yaw error [deg]")
    for j, ax in enumerate(axes):
        y = np.degrees(np.unwrap(e[:, j])) if j == 2 else e[:, j] * scale      # yaw unwrapped past 180 deg
        ax.plot(t, y, color="tab:blue" if epsilon else "tab:red", label="body-frame error")
        if epsilon is not None and j < 2:
            if np.abs(y).max() > 0.2 * epsilon * scale:
                ax.axhline(epsilon * scale, color="0.4", linestyle=":", label=r"$\pm\varepsilon = \Phi/\lambda$")
                ax.axhline(-epsilon * scale, color="0.4", linestyle=":")
            else:
                off_scale = True
        ax.set_ylabel(labels[j])
        ax.grid(True, alpha=0.3)
    axes[0].legend(loc="best", fontsize=8)
    axes[-1].set_xlabel("time [s]")
    if off_scale:
        title += f"\nguaranteed bound $\\pm\\varepsilon = \\Phi/\\lambda$ = $\\pm${epsilon * scale:.2f} {unit}, far outside these axes"
    axes[0].set_title(title)
    return _save(fig, path)


def fig5_uncontrolled(result, series, path) -> Path:
    """Vehicle position and heading errors in the body frame, released without control (Figure 5)."""
    return _error_figure(result, series, "Fig. 5: uncontrolled URV location errors (body frame)", path,
                         scale=1.0, unit="m")


def fig6_controlled(result, series, path, epsilon: float) -> Path:
    """Vehicle position and heading errors in the body frame with smc-ab (Figure 6), with +/- epsilon."""
    return _error_figure(result, series, "Fig. 6: controlled URV location errors (body frame)", path,
                         scale=1e3, unit="mm", epsilon=epsilon)


def fig7_sliding(result, path, phi: float) -> Path:
    """``s`` per axis with the boundary layer +/- Phi (Figure 7)."""
    plt = _pyplot()
    fig, axes = plt.subplots(3, 1, figsize=(7.0, 6.4), sharex=True)
    units = ("m/s", "m/s", "rad/s")
    for j, ax in enumerate(axes):
        s = result.signals.get(f"s_{AXES[j]}")
        if s is not None:
            ax.plot(result.time, s, color="tab:blue", label=f"s ({AXES[j]})")
        ax.axhline(phi, color="tab:red", linestyle="--", label=r"$\pm\Phi$ boundary layer")
        ax.axhline(-phi, color="tab:red", linestyle="--")
        ax.set_ylabel(f"s {AXES[j]} [{units[j]}]")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("time [s]")
    axes[0].set_title("Fig. 7: sliding variables and boundary layer")
    return _save(fig, path)


def fig8_control(result, path) -> Path:
    """Commanded surge and sway forces and yaw moment (Figure 8)."""
    plt = _pyplot()
    fig, axes = plt.subplots(3, 1, figsize=(7.0, 6.4), sharex=True)
    for ax, (name, label) in zip(axes, (("X", "X (surge) [N]"), ("Y", "Y (sway) [N]"), ("N", "N (yaw) [N m]"))):
        c = result.signals.get(f"command_{name}")
        if c is not None:
            ax.plot(result.time, c, color="tab:green", label=f"commanded {name}")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("time [s]")
    axes[0].set_title("Fig. 8: control activity (commanded body wrench)")
    return _save(fig, path)
