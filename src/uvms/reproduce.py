"""Reproduce the paper's Section 6: three cases, Figures 4-8, metrics, and a report with a verdict per claim.

Cases (10 s each, RK4 at 1 ms, the paper's joint torques ``[2.5, 0, 0]`` N m until 2 s then ``[0.01, 0, 0]``):

- ``fixed``: vehicle clamped, control off (a land-based arm: "the pilot's true intent");
- ``released``: vehicle released, control off;
- ``controlled``: vehicle released, ``smc-ab`` with the paper's values and the paper's 60 % model error
  (controller model added mass and drag = 0.4 x the plant's), updated every 10 ms.

``paper(out_dir=..., actuators=...)`` writes the figures, ``metrics.json``, ``report.md`` and ``report.html``
and returns the metrics. Actuators: ``ideal`` (the commanded wrench is applied), ``healey`` (Healey thrusters
in the paper layout plus a sway thruster) or ``paper-layout`` (the paper's three Healey thrusters, which
cannot push sideways).
"""

from __future__ import annotations

import base64
import json
import math
import time as _time
from pathlib import Path
from typing import Any, Callable

import numpy as np

from uvms.output import atomic_write_text, staged_directory

PAPER_LAMBDA = 3.14
"""Sliding-surface bandwidth lambda [1/s] (appendix)."""
PAPER_PHI = 0.02
"""Boundary-layer thickness Phi (appendix)."""
PAPER_MODEL_ERROR = 0.4
"""Controller model's added mass and drag = 0.4 x the plant's: the paper's "differed by 60 %"."""
DURATION = 10.0
STEP = 1e-3
CONTROL_PERIOD = 0.01
ACTUATORS = {"ideal": "ideal", "healey": "paper-sway", "paper-layout": "paper"}
"""``--actuators`` choices and the thruster layout each one uses."""
AXES = ("surge", "sway", "yaw")
COMMAND_OF_AXIS = {"surge": "X", "sway": "Y", "yaw": "N"}
FIGURES = ("fig4_ee_path.png", "fig5_uncontrolled.png", "fig6_controlled.png", "fig7_sliding.png",
           "fig8_control.png")


def _simulate_case(model, case: str, actuators: str, *, boundary_layer: float = PAPER_PHI):
    from uvms.control.registry import make_controller
    from uvms.sim.inputs import paper_torques
    from uvms.sim.run import Actuation, simulate

    controller = None
    actuation = None
    if case == "controlled":
        controller = make_controller("smc-ab", model, period=CONTROL_PERIOD,
                                     parameters={"hydro_scale": PAPER_MODEL_ERROR, "boundary_layer": boundary_layer})
        actuation = Actuation.named(ACTUATORS[actuators])
    return simulate(model, duration=DURATION, step=STEP, joint_torques=paper_torques(), fixed_base=(case == "fixed"),
                    controller=controller, actuation=actuation, control_period=CONTROL_PERIOD,
                    metadata={"case": case, "actuators": actuators})


def case_metrics(result, fixed, *, bandwidth: float = PAPER_LAMBDA, phi: float = PAPER_PHI) -> dict[str, Any]:
    """The metrics of one case (see ``docs/reproduce.md``); ``fixed`` is the fixed-base run for the ee path."""
    from uvms.control.compare import axis_series, sign_changes
    series = axis_series(result, bandwidth=bandwidth)
    err = series["error"]
    pos = result.position - result.position[0]
    yaw = result.euler[:, 2] - result.euler[0, 2]             # unwrapped: a drift past 180 deg counts in full
    dt = float(np.median(np.diff(result.time)))
    out: dict[str, Any] = {
        "peak_abs_x_m": float(np.abs(pos[:, 0]).max()),
        "peak_abs_y_m": float(np.abs(pos[:, 1]).max()),
        "peak_abs_yaw_rad": float(np.abs(yaw).max()),
        "peak_body_error_xy_m": float(np.hypot(err[:, 0], err[:, 1]).max()),
        "peak_ee_deviation_m": float(np.linalg.norm(result.end_effector - fixed.end_effector, axis=1).max()),
        "max_abs_s": {}, "time_outside_boundary_s": {}, "peak_command": {}, "command_sign_changes": {},
        "final_q": result.q[-1].tolist(),
        "complete": bool(result.complete),
    }
    for j, axis in enumerate(AXES):
        s = result.signals.get(f"s_{axis}", series["s"][:, j])
        s = np.where(np.isfinite(s), s, series["s"][:, j])
        out["max_abs_s"][axis] = float(np.abs(s).max())
        out["time_outside_boundary_s"][axis] = float(np.count_nonzero(np.abs(s) > phi) * dt)
        c = result.signals.get(f"command_{COMMAND_OF_AXIS[axis]}")
        out["peak_command"][axis] = float(np.nanmax(np.abs(c))) if c is not None else 0.0
        out["command_sign_changes"][axis] = sign_changes(c) if c is not None else 0
    return out


def plant_effective_inertia(model, result, *, every: int = 50) -> dict[str, list[float]]:
    """Range over a run of the plant's effective surge/sway mass and yaw inertia, ``1 / (IA_0^-1)_jj`` with
    ``IA_0`` the articulated inertia of the whole system at the vehicle (arm and added mass included): the
    quantity the paper's ``b`` bounds (Eqs. 27-29) must contain."""
    from uvms.control.smc import effective_inertia
    from uvms.dynamics.aba import aba
    from uvms.dynamics.kernel_model import make_workspace
    from uvms.rotations import rotation_from_quaternion

    n = model.n_joints
    ws = make_workspace(model.n_bodies)
    values = []
    for x in result.states[::every]:
        aba(model.kernel, ws, rotation_from_quaternion(x[3:7]), x[7:13].copy(), x[13:13 + n].copy(),
            x[13 + n:13 + 2 * n].copy(), np.zeros(n), np.zeros(6), np.zeros(6), np.zeros(3), np.zeros(3), False,
            np.zeros(6), np.zeros(n))
        values.append(effective_inertia(ws.IA[0]))
    v = np.array(values)
    return {axis: [float(v[:, j].min()), float(v[:, j].max())] for j, axis in enumerate(AXES)}


def run(model=None, *, actuators: str = "ideal", progress: Callable[[str], None] | None = None) -> dict:
    """The three runs ``{"fixed", "released", "controlled"}: Result``."""
    import uvms

    if actuators not in ACTUATORS:
        from uvms.errors import UvmsInputError

        raise UvmsInputError(f"unknown actuators {actuators!r}; expected one of: {', '.join(ACTUATORS)}",
                             path="--actuators")
    model = model or uvms.load_model("paper")
    results = {}
    for case in ("fixed", "released", "controlled"):
        if progress:
            progress(f"case {case}")
        results[case] = _simulate_case(model, case, actuators)
    return results


def comparison(model, *, factors=(0.4, 1.0, 1.6), actuators=("ideal", "healey"),
               progress: Callable[[str], None] | None = None):
    """Controllers side by side on the controlled case: ``smc-ab``, ``smc-ne`` (noisy IMU), ``smc-vehicle``,
    ``pid``, for each model-error factor and actuator set. Returns a pandas DataFrame."""
    import pandas as pd

    from uvms.control.compare import Case, compare_controllers
    from uvms.sim.run import Actuation

    cases = (Case("smc-ab", "smc-ab"),
             Case("smc-ne (noisy IMU)", "smc-ne", {"imu_noise": 0.05, "imu_delay": 2, "imu_seed": 1}),
             Case("smc-vehicle", "smc-vehicle"), Case("pid", "pid"))
    frames = []
    for act in actuators:
        for factor in factors:
            if progress:
                progress(f"comparison: {act} actuators, model error factor {factor}")
            df = compare_controllers(model, cases, duration=DURATION, step=STEP, period=CONTROL_PERIOD,
                                     hydro_scale=factor, actuation=Actuation.named(ACTUATORS[act]))
            df.insert(1, "actuators", act)
            df.insert(2, "model_error_factor", factor)
            frames.append(df)
    return pd.concat(frames, ignore_index=True)


def claims(metrics: dict, chatter: dict) -> list[dict[str, str]]:
    """Each claim of the paper next to what was measured, with a verdict."""
    c, r = metrics["cases"]["controlled"], metrics["cases"]["released"]
    eps = metrics["epsilon_m"]
    s_ratio = max(c["max_abs_s"][a] for a in AXES) / PAPER_PHI
    b = metrics["plant_b"]
    paper_b = {"surge": (36.0, 44.44), "sway": (36.0, 44.44), "yaw": (1.287, 1.5889)}
    inside = all(paper_b[a][0] <= b[a][0] and b[a][1] <= paper_b[a][1] for a in AXES)
    rows = [
        {"claim": "Premise of Eqs. 27-29: the b bounds contain the plant's effective mass and inertia",
         "measured": "plant over the controlled run: " + ", ".join(
             f"{a} {b[a][0]:.3g}-{b[a][1]:.3g} (paper {paper_b[a][0]:g}-{paper_b[a][1]:g})" for a in AXES),
         "verdict": "holds" if inside else "does not hold"},
        {"claim": "The position error stays within the guaranteed precision epsilon = Phi/lambda (Eq. 30)",
         "measured": f"peak body-frame xy error {c['peak_body_error_xy_m'] * 1e3:.2f} mm vs epsilon "
                     f"{eps * 1e3:.2f} mm",
         "verdict": "holds" if c["peak_body_error_xy_m"] <= eps else "does not hold"},
        {"claim": "s remains inside the boundary layers (Fig. 7)",
         "measured": f"max abs(s) / Phi = {s_ratio:.2f}; time outside: "
                     + ", ".join(f"{a} {c['time_outside_boundary_s'][a]:.3f} s" for a in AXES),
         "verdict": "holds" if s_ratio <= 1.0 else "does not hold"},
        {"claim": "The controller gives the arm a fixed base: the end-effector path follows the fixed-URV path "
                  "(Fig. 4)",
         "measured": f"peak end-effector deviation from the fixed case: controlled "
                     f"{c['peak_ee_deviation_m'] * 1e3:.1f} mm, uncontrolled {r['peak_ee_deviation_m'] * 1e3:.0f} mm",
         "verdict": "holds" if c["peak_ee_deviation_m"] < 0.01 < r["peak_ee_deviation_m"] else "does not hold"},
        {"claim": "Without control the arm's reaction moves the vehicle (Fig. 5)",
         "measured": f"peak drift x {r['peak_abs_x_m']:.2f} m, y {r['peak_abs_y_m']:.2f} m, yaw "
                     f"{math.degrees(r['peak_abs_yaw_rad']):.0f} deg",
         "verdict": "holds" if max(r["peak_abs_x_m"], r["peak_abs_y_m"]) > 0.1 else "does not hold"},
        {"claim": "The commanded forces are smooth, free of chattering, thanks to the boundary layer (Fig. 8)",
         "measured": f"sign changes of the command's slope with Phi = {PAPER_PHI}: "
                     + ", ".join(f"{k} {v}" for k, v in chatter["paper"].items())
                     + "; with Phi/100: " + ", ".join(f"{k} {v}" for k, v in chatter["small"].items()),
         "verdict": "holds" if sum(chatter["small"].values()) > 5 * max(sum(chatter["paper"].values()), 1)
         else "does not hold"},
    ]
    return rows


def _table_md(df) -> str:
    cols = list(df.columns)
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for _, row in df.iterrows():
        cells = [f"{v:.3g}" if isinstance(v, float) else str(v) for v in row]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def write_report(out_dir: Path, metrics: dict, claim_rows: list[dict], table) -> None:
    """``report.md`` and ``report.html`` (figures embedded) in ``out_dir``."""
    md = ["# Reproduction of the paper's Section 6", "",
          f"Actuators: `{metrics['actuators']}`; model error factor {PAPER_MODEL_ERROR} (the paper's 60 %); "
          f"Phi = {PAPER_PHI}, lambda = {PAPER_LAMBDA} 1/s, epsilon = {metrics['epsilon_m'] * 1e3:.2f} mm; "
          f"{DURATION:g} s at {STEP * 1e3:g} ms RK4, controller every {CONTROL_PERIOD * 1e3:g} ms.", "",
          "## The paper's claims", "", "| claim | measured here | verdict |", "|---|---|---|"]
    md += [f"| {r['claim']} | {r['measured']} | **{r['verdict']}** |" for r in claim_rows]
    md += ["", "## Cases", "", "| case | peak x [m] | peak y [m] | peak yaw [deg] | peak body xy error [mm] | "
           "peak ee deviation [mm] | max abs s (surge, sway, yaw) |", "|---|---|---|---|---|---|---|"]
    for name, c in metrics["cases"].items():
        md.append(f"| {name} | {c['peak_abs_x_m']:.4f} | {c['peak_abs_y_m']:.4f} | "
                  f"{math.degrees(c['peak_abs_yaw_rad']):.2f} | {c['peak_body_error_xy_m'] * 1e3:.2f} | "
                  f"{c['peak_ee_deviation_m'] * 1e3:.1f} | "
                  + ", ".join(f"{c['max_abs_s'][a]:.4f}" for a in AXES) + " |")
    if table is not None:
        md += ["", "## Controllers compared (released vehicle, paper torques)", "",
               "Model error factor: the controller model's added mass and drag relative to the plant's.", "",
               _table_md(table)]
    md += ["", "## Figures", ""] + [f"![{f}]({f})" for f in FIGURES]
    atomic_write_text(out_dir / "report.md", "\n".join(md) + "\n")

    def img(name: str) -> str:
        data = base64.b64encode((out_dir / name).read_bytes()).decode()
        return f'<figure><img src="data:image/png;base64,{data}" alt="{name}"><figcaption>{name}</figcaption></figure>'

    rows = "".join(f"<tr><td>{r['claim']}</td><td>{r['measured']}</td><td><b>{r['verdict']}</b></td></tr>"
                   for r in claim_rows)
    html = ["<!doctype html><html><head><meta charset='utf-8'><title>uvms: paper reproduction</title>",
            "<style>body{font-family:sans-serif;max-width:1100px;margin:auto}table{border-collapse:collapse}"
            "td,th{border:1px solid #bbb;padding:4px 8px;font-size:90%}img{max-width:100%}</style></head><body>",
            "<h1>Reproduction of the paper's Section 6</h1>",
            f"<p>Actuators: {metrics['actuators']}; epsilon = {metrics['epsilon_m'] * 1e3:.2f} mm.</p>",
            "<h2>The paper's claims</h2><table><tr><th>claim</th><th>measured</th><th>verdict</th></tr>", rows,
            "</table>"]
    if table is not None:
        html += ["<h2>Controllers compared</h2>", table.to_html(index=False, float_format=lambda v: f"{v:.3g}")]
    html += ["<h2>Figures</h2>"] + [img(f) for f in FIGURES] + ["</body></html>"]
    atomic_write_text(out_dir / "report.html", "\n".join(html))


def paper(out_dir="reproduce-paper", *, actuators: str = "ideal", compare: bool = True,
          progress: Callable[[str], None] | None = None) -> dict:
    """Run the three cases, write figures, ``metrics.json``, ``report.md``/``.html`` into ``out_dir``; return
    the metrics (``{"epsilon_m", "actuators", "cases": {"fixed"|"released"|"controlled": {...}}, ...}``).

    Everything is written into a temporary sibling folder that replaces ``out_dir`` in one rename at the end, so
    an interrupted run never leaves a mix of old and new files.
    """
    wall0 = _time.perf_counter()
    final = _check_output(Path(out_dir))
    with staged_directory(final, kind="reproduction") as out:
        metrics = _reproduce_into(out, actuators, compare, progress, wall0)
    return metrics


def _check_output(out: Path) -> Path:
    """The output folder may be new, empty, or an earlier reproduction holding nothing else (then replaced whole)."""
    from uvms.output import check_destination

    out = out.resolve()
    check_destination(out, "--output", kind="replaced folder")
    return out


def _reproduce_into(out: Path, actuators: str, compare: bool, progress, wall0: float) -> dict:
    """Everything of :func:`paper`, written into ``out``."""
    import uvms
    from uvms import paper_figures as figs
    from uvms.control.compare import axis_series, sign_changes

    model = uvms.load_model("paper")
    results = run(model, actuators=actuators, progress=progress)
    fixed = results["fixed"]
    metrics: dict[str, Any] = {"epsilon_m": PAPER_PHI / PAPER_LAMBDA, "actuators": actuators,
                               "cases": {name: case_metrics(res, fixed) for name, res in results.items()}}
    if progress:
        progress("chatter check: Phi / 100")
    small = _simulate_case(model, "controlled", actuators, boundary_layer=PAPER_PHI / 100)
    chatter = {"paper": {k: sign_changes(results["controlled"].signals[f"command_{k}"]) for k in ("X", "Y", "N")},
               "small": {k: sign_changes(small.signals[f"command_{k}"]) for k in ("X", "Y", "N")}}
    metrics["chatter"] = chatter
    metrics["plant_b"] = plant_effective_inertia(model, results["controlled"])
    if progress:
        progress("figures")
    figs.fig4_ee_path(results, out / FIGURES[0])
    figs.fig5_uncontrolled(results["released"], axis_series(results["released"]), out / FIGURES[1])
    figs.fig6_controlled(results["controlled"], axis_series(results["controlled"]), out / FIGURES[2],
                         metrics["epsilon_m"])
    figs.fig7_sliding(results["controlled"], out / FIGURES[3], PAPER_PHI)
    figs.fig8_control(results["controlled"], out / FIGURES[4])
    table = comparison(model, progress=progress) if compare else None
    if table is not None:
        atomic_write_text(out / "comparison.csv", table.to_csv(index=False))
    claim_rows = claims(metrics, chatter)
    metrics["claims"] = claim_rows
    metrics["wall_time_s"] = _time.perf_counter() - wall0
    atomic_write_text(out / "metrics.json", json.dumps(metrics, indent=2))
    write_report(out, metrics, claim_rows, table)
    return metrics
