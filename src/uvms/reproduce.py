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

Beyond the three cases the report runs: the controlled case with ``Phi / 100`` (chatter check), the controlled
case with the paper's own three thrusters (``paper-layout``: a measured finding), and ``smc-ne`` with a noisy,
delayed IMU (the paper's central claim, against ``smc-ab``). Every verdict and explanation in the report is a
function of the measured numbers (:func:`claims`, :func:`central_claim`, :func:`model_error_explanation`); the
report itself is one structure (:class:`Section` with paragraphs, tables, figures) rendered twice, as Markdown
and as HTML (:func:`render_markdown`, :func:`render_html`). ``docs/reproduce.md`` describes the files.
"""

from __future__ import annotations

import base64
import json
import math
import time as _time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from uvms.control.compare import IMU_NOISE
from uvms.control.smc import SlidingModeParameters
from uvms.output import atomic_write_text, staged_directory

_PAPER = SlidingModeParameters()
"""The paper's controller values: the defaults of the sliding-mode parameters, their one definition."""
PAPER_LAMBDA = _PAPER.bandwidth[0]         # the same on every paper axis
"""Sliding-surface bandwidth lambda [1/s] (appendix)."""
PAPER_PHI = _PAPER.boundary_layer[0]
"""Boundary-layer thickness Phi (appendix)."""
PAPER_MODEL_ERROR = _PAPER.hydro_scale
"""Controller model's added mass and drag = 0.4 x the plant's: the paper's "differed by 60 %"."""
ACTUATORS = {"ideal": "ideal", "healey": "paper-sway", "paper-layout": "paper"}
"""``--actuators`` choices and the thruster layout each one uses."""
AXES = ("surge", "sway", "yaw")
COMMAND_OF_AXIS = {"surge": "X", "sway": "Y", "yaw": "N"}
FIGURE_STEMS = ("fig4_ee_path", "fig5_uncontrolled", "fig6_controlled", "fig7_sliding", "fig8_control")
FIGURES = tuple(f"{stem}.png" for stem in FIGURE_STEMS)
"""The figures' file names in the default format (``--format png``)."""
FORMATS = ("png", "svg", "pdf")
"""``--format`` choices for the figures."""
PAPER_B = dict(zip(AXES, _PAPER.b_limits()))
"""The paper's bounds ``[b_min, b_max]`` of Eqs. 27-29 [kg, kg, kg m^2] (the defaults of :mod:`uvms.control.smc`)."""
SAME_PRECISION = 0.25
"""Two peak position errors are "the same precision" when they differ by at most this fraction of the larger."""
CHATTER_RATIO = 5.0
"""One command chatters more than another when it has at least this many times as many slope sign changes."""
CASE_FOLDER = "cases"
"""Subfolder of the report holding every run's time series (``cases/<name>/result.csv`` and ``.json``)."""


CASE_SCENARIOS = {"fixed": "paper_case1_fixed", "released": "paper_case2_released",
                  "controlled": "paper_case3_controlled"}
"""The bundled scenario file (``src/uvms/scenarios/``) that defines each case: duration, step, joint torques,
vehicle fixed or released, controller, its period and parameters (the paper's: the defaults). The report
overrides only the actuators of the controlled case (``--actuators``) and, for the chatter check, the
boundary layer (Phi / 100)."""


def __getattr__(name: str):
    """``DURATION``, ``STEP`` [s] and ``CONTROL_PERIOD`` [s]: the controlled case's scenario file's values (read
    on first use, never re-typed)."""
    if name in ("DURATION", "STEP", "CONTROL_PERIOD"):
        spec = _case_spec("controlled")
        return {"DURATION": spec.duration, "STEP": spec.step, "CONTROL_PERIOD": spec.controller.period}[name]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _case_spec(case: str):
    from uvms.sim.scenario import load_scenario

    return load_scenario(CASE_SCENARIOS[case]).spec


def _simulate_case(model, case: str, actuators: str, *, boundary_layer: float | None = None):
    """One case, as its scenario file defines it (:data:`CASE_SCENARIOS`, through
    :meth:`~uvms.sim.scenario.Scenario.simulate_options`) on ``model``, the controlled case with ``actuators``
    and, if given, the controller's ``boundary_layer``."""
    from uvms.control.registry import make_controller
    from uvms.sim.health import actuation_metadata
    from uvms.sim.run import Actuation, simulate
    from uvms.sim.scenario import load_scenario

    scenario = load_scenario(CASE_SCENARIOS[case]).with_model(model)
    spec = scenario.spec
    options = scenario.simulate_options()
    metadata = {key: value for key, value in options["metadata"].items() if key != "thrust_limits_N"}
    if spec.controller is not None:
        parameters = dict(spec.controller.parameters)
        if boundary_layer is not None:
            parameters["boundary_layer"] = boundary_layer
        actuation = Actuation.named(ACTUATORS[actuators])
        options.update(controller=make_controller(spec.controller.name, model, period=spec.controller.period,
                                                  parameters=parameters),
                       actuation=actuation, control_period=spec.controller.period)
        metadata.update(actuation_metadata(actuation))
    options["metadata"] = {**metadata, "case": case, "actuators": actuators}
    return simulate(**options)


def case_metrics(result, fixed, *, bandwidth: float = PAPER_LAMBDA, phi: float = PAPER_PHI) -> dict[str, Any]:
    """The metrics of one case (see ``docs/reproduce.md``), named metrics of :mod:`uvms.sim.metrics`; ``fixed``
    is the fixed-base run for the end-effector path."""
    from uvms.sim.metrics import Series

    series = Series(result, bandwidth=bandwidth)
    s_states = series.axis()["s"]
    dt = float(np.median(np.diff(result.time)))

    def or_zero(value: float) -> float:
        return value if np.isfinite(value) else 0.0

    out: dict[str, Any] = {
        "peak_abs_x_m": series.metric("peak_abs_x_m"),
        "peak_abs_y_m": series.metric("peak_abs_y_m"),
        "peak_abs_yaw_rad": series.metric("peak_abs_yaw_rad"),   # unwrapped: a drift past 180 deg counts in full
        "peak_body_error_xy_m": series.metric("peak_body_error_xy_m"),
        "peak_body_error_x_m": series.metric("max_abs_axis_error_surge"),   # R^T (p - p0), as Figs. 5-6 draw it
        "peak_body_error_y_m": series.metric("max_abs_axis_error_sway"),
        "peak_ee_deviation_m": float(np.linalg.norm(result.end_effector - fixed.end_effector, axis=1).max()),
        "max_abs_s": {}, "time_outside_boundary_s": {}, "peak_command": {}, "command_sign_changes": {},
        "final_q": result.q[-1].tolist(),
        "complete": bool(result.complete),
    }
    for j, axis in enumerate(AXES):
        s = result.signals.get(f"s_{axis}", s_states[:, j])      # the controller's own s where it logged one
        s = np.where(np.isfinite(s), s, s_states[:, j])
        out["max_abs_s"][axis] = float(np.abs(s).max())
        out["time_outside_boundary_s"][axis] = float(np.count_nonzero(np.abs(s) > phi) * dt)
        command = f"command_{COMMAND_OF_AXIS[axis]}"
        out["peak_command"][axis] = or_zero(series.metric(f"max_abs_{command}"))
        out["command_sign_changes"][axis] = int(or_zero(series.metric(f"sign_changes_{command}")))
    return out


def plant_effective_inertia(model, result, *, every: int = 50) -> dict[str, list[float]]:
    """Range over a run of the plant's effective surge/sway mass and yaw inertia, ``1 / (IA_0^-1)_jj`` with
    ``IA_0`` the articulated inertia of the whole system at the vehicle (arm and added mass included): the
    quantity the paper's ``b`` bounds (Eqs. 27-29) must contain."""
    from uvms.dynamics.api import Dynamics

    dynamics = Dynamics(model)
    values = []
    for k in range(0, len(result.time), every):
        inverse = np.linalg.inv(dynamics.vehicle_articulated_inertia(result.state(k)))
        values.append([1.0 / inverse[j, j] for j in (3, 4, 2)])     # X (surge), Y (sway), N (yaw) of [K M N X Y Z]
    v = np.array(values)
    return {axis: [float(v[:, j].min()), float(v[:, j].max())] for j, axis in enumerate(AXES)}


def _check_choice(value: str, choices, option: str) -> None:
    if value not in choices:
        from uvms.errors import UvmsInputError

        raise UvmsInputError(f"unknown {option.lstrip('-')} {value!r}; expected one of: {', '.join(choices)}",
                             path=option)


def run(model=None, *, actuators: str = "ideal", progress: Callable[[str], None] | None = None) -> dict:
    """The three runs ``{"fixed", "released", "controlled"}: Result``."""
    import uvms

    _check_choice(actuators, ACTUATORS, "--actuators")
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
             Case("smc-ne (noisy IMU)", "smc-ne", dict(IMU_NOISE)),
             Case("smc-vehicle", "smc-vehicle"), Case("pid", "pid"))
    frames = []
    for act in actuators:
        for factor in factors:
            if progress:
                progress(f"comparison: {act} actuators, model error factor {factor}")
            df = compare_controllers(model, cases, hydro_scale=factor, actuation=Actuation.named(ACTUATORS[act]))
            df.insert(1, "actuators", act)
            df.insert(2, "model_error_factor", factor)
            frames.append(df)
    return pd.concat(frames, ignore_index=True)


def _inside(b: dict, bounds: dict = PAPER_B) -> dict[str, bool]:
    """Per axis: is the plant's range ``b[axis] = [lo, hi]`` inside the paper's bounds?"""
    return {a: bounds[a][0] <= b[a][0] and b[a][1] <= bounds[a][1] for a in AXES if a in b}


def claims(metrics: dict, chatter: dict) -> list[dict[str, str]]:
    """Each claim of the paper next to what was measured, with a verdict (``holds`` / ``does not hold``)
    computed from the measured numbers."""
    c, r = metrics["cases"]["controlled"], metrics["cases"]["released"]
    eps = metrics["epsilon_m"]
    s_ratio = max(c["max_abs_s"][a] for a in AXES) / PAPER_PHI
    b = metrics["plant_b"]
    inside = all(_inside(b).values())
    rows = [
        {"claim": "Premise of Eqs. 27-29: the b bounds contain the plant's effective mass and inertia",
         "measured": "plant over the controlled run: " + ", ".join(
             f"{a} {b[a][0]:.3g}-{b[a][1]:.3g} (paper {PAPER_B[a][0]:g}-{PAPER_B[a][1]:g})" for a in AXES),
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
         "measured": f"peak drift (world frame) x {r['peak_abs_x_m']:.2f} m, y {r['peak_abs_y_m']:.2f} m, yaw "
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


# -- the paper's central claim: the articulated-body model against Newton-Euler with an IMU

def command_activity(result) -> dict[str, float]:
    """Precision and chatter of one controlled run: ``peak_xy_error_mm``, ``peak_yaw_error_deg`` (as
    :func:`uvms.control.compare.metrics`), ``chatter`` (slope sign changes of X, Y and N summed) and
    ``increment_rms_N`` (RMS of the step-to-step change of the commanded X and Y forces [N], counting only the
    samples where the command changes: the size of the chatter)."""
    from uvms.control.compare import metrics

    m = metrics(result)
    steps = []
    for name in ("X", "Y"):
        c = result.signals.get(f"command_{name}")
        if c is not None:
            d = np.diff(c[np.isfinite(c)])
            steps.append(d[d != 0])
    steps = np.concatenate(steps) if steps else np.zeros(0)
    return {"peak_xy_error_mm": m["peak_xy_error_mm"], "peak_yaw_error_deg": m["peak_yaw_error_deg"],
            "chatter": int(m["chatter_X"] + m["chatter_Y"] + m["chatter_N"]),
            "increment_rms_N": float(np.sqrt(np.mean(steps**2))) if steps.size else 0.0}


def central_claim(ab: dict, ne: dict, epsilon_mm: float) -> dict[str, str]:
    """The paper's central claim, that its articulated-body prediction (``smc-ab``, no acceleration measured)
    controls better than a Newton-Euler prediction fed by an IMU (``smc-ne``), judged from the measured
    :func:`command_activity` of both: precision (peak xy error; "the same" within :data:`SAME_PRECISION`) and
    chatter (slope sign changes; "more" from :data:`CHATTER_RATIO` times on).

    Returns ``claim``, ``measured``, ``verdict`` (``holds`` / ``does not hold``), ``finding`` (the verdict in
    words, e.g. "same precision; the difference is chatter") and ``details`` (the numbers behind it)."""
    a, n = ab["peak_xy_error_mm"], ne["peak_xy_error_mm"]
    larger = max(a, n)
    if abs(a - n) <= SAME_PRECISION * larger:
        precision = "same"
    else:
        precision = "ab" if a < n else "ne"
    ca, cn = ab["chatter"], ne["chatter"]
    if cn >= CHATTER_RATIO * max(ca, 1):
        smoother = "ab"
    elif ca >= CHATTER_RATIO * max(cn, 1):
        smoother = "ne"
    else:
        smoother = "neither"
    diff = f"{abs(a - n) / larger * 100:.0f} %" if larger > 0 else "0 %"
    within = "both within" if larger <= epsilon_mm else "not both within"
    words = (f"peak xy error {a:.3g} mm with smc-ab, {n:.3g} mm with smc-ne ({diff} apart, {within} epsilon = "
             f"{epsilon_mm:.2f} mm)")
    ratio = cn / max(ca, 1)
    chatter_words = {
        "ab": f"smc-ne's commands chatter: {cn} slope sign changes against {ca} ({ratio:.0f} x), steps of "
              f"{ne['increment_rms_N']:.3g} N RMS against {ab['increment_rms_N']:.3g} N",
        "ne": f"smc-ab's commands chatter more: {ca} slope sign changes against {cn}",
        "neither": f"the commands are equally smooth ({ca} and {cn} slope sign changes)",
    }[smoother]
    holds = (precision == "ab" and smoother != "ne") or (precision == "same" and smoother == "ab")
    if precision == "same" and smoother == "ab":
        finding = "same precision; the difference is chatter"
    elif holds:
        finding = "the articulated-body model is more precise"
    elif precision == "ne" and smoother == "ab":
        finding = "mixed: smc-ne is more precise, smc-ab smoother"
    else:
        finding = "no advantage for the articulated-body model"
    details = words + "; " + chatter_words
    return {"claim": "Central claim: the articulated-body prediction (smc-ab, no acceleration measured) controls "
                     "better than Newton-Euler fed by an IMU (smc-ne, noisy and delayed)",
            "measured": f"peak xy error smc-ab {a:.3g} mm, smc-ne {n:.3g} mm; command slope sign changes "
                        f"smc-ab {ca}, smc-ne {cn}",
            "verdict": "holds" if holds else "does not hold", "finding": finding, "details": details}


# -- explanations of results that look paradoxical, each conditioned on the data

def model_error_explanation(table, b_model: dict, actuators: str = "ideal") -> list[str]:
    """Why a perfect controller model (factor 1.0) may do worse than the paper's 0.4x one, from the
    comparison ``table`` (``smc-ab`` rows) and ``b_model`` (``{factor: {axis: [lo, hi]}}``: the controller
    model's effective mass over the run, :func:`plant_effective_inertia` of the scaled model).

    The law commands ``f = b_hat (u_hat - k sat)`` with ``u_hat ~ -f_hat``, and ``f_hat`` is the disturbance
    force ``D`` divided by the controller model's own effective mass ``b_model``: the feed-forward applies
    ``(b_hat / b_model) D``, so the part ``(1 - b_hat / b_model) D`` of the arm's reaction is left to the
    switching term. With the paper's fixed ``b_hat = sqrt(b_min b_max)`` this residual is smallest for the
    model whose effective mass is closest to ``b_hat``. Returns paragraphs; the mechanism is stated as the
    explanation only if the measured errors rank the factors in the same order as the residual."""
    if table is None:
        return ["The controller comparison was not run (`--no-comparison`), so the effect of the controller "
                "model's error is not measured here."]
    act = actuators if actuators in set(table["actuators"]) else "ideal"
    rows = table[(table["controller"] == "smc-ab") & (table["actuators"] == act)]
    if rows.empty:
        return []
    err = {float(f): float(e) for f, e in zip(rows["model_error_factor"], rows["peak_xy_error_mm"])}
    factors = sorted(f for f in err if f in b_model)
    if PAPER_MODEL_ERROR not in err or 1.0 not in err:
        return []
    b_hat = {a: math.sqrt(PAPER_B[a][0] * PAPER_B[a][1]) for a in ("surge", "sway")}
    residual = {f: max(abs(1 - b_hat[a] / (0.5 * sum(b_model[f][a]))) for a in ("surge", "sway"))
                for f in factors}
    listing = ", ".join(f"{f:g}x: {err[f]:.3g} mm" for f in factors)
    masses = "; ".join(f"{f:g}x model: " + ", ".join(f"{a} {b_model[f][a][0]:.3g}-{b_model[f][a][1]:.3g} kg"
                                                   for a in ("surge", "sway")) for f in factors)
    paragraphs = []
    if err[1.0] > err[PAPER_MODEL_ERROR]:
        paragraphs.append(f"**A perfect controller model does worse than the paper's 0.4x one** ({act} actuators, "
                          f"peak xy error of smc-ab: {listing}).")
    else:
        paragraphs.append(f"The perfect controller model does at least as well as the paper's 0.4x one ({act} "
                          f"actuators, peak xy error of smc-ab: {listing}): nothing paradoxical to explain.")
        return paragraphs
    bracket = (PAPER_MODEL_ERROR in b_model and 1.0 in b_model
               and all(_inside(b_model[PAPER_MODEL_ERROR], PAPER_B)[a] for a in ("surge", "sway"))
               and not any(_inside(b_model[1.0], PAPER_B)[a] for a in ("surge", "sway")))
    by_error = sorted(factors, key=lambda f: err[f])
    by_residual = sorted(factors, key=lambda f: residual[f])
    res_text = ", ".join(f"{f:g}x: {residual[f]:.2f}" for f in factors)
    if by_error == by_residual:
        paragraphs.append(
            "Why: the sliding-mode law uses the paper's fixed b_hat = sqrt(b_min b_max) = "
            f"{b_hat['surge']:.2f} kg, while f_hat is the arm's reaction divided by the controller model's own "
            f"effective mass ({masses}). The feed-forward thus applies b_hat / b_model of the reaction, and the "
            f"fraction 1 - b_hat / b_model (largest of surge and sway) is left to the switching term: {res_text}. "
            "The measured errors rank the factors in the same order: the model whose effective mass is closest "
            "to b_hat is favoured, whatever its error"
            + (", and the paper's b bounds bracket the 0.4x model rather than the plant, so the 0.4x model's "
               "error in mass cancels the bounds' error." if bracket else "."))
    else:
        paragraphs.append(
            f"The residual fraction 1 - b_hat / b_model of the feed-forward ({res_text}; b_hat = "
            f"{b_hat['surge']:.2f} kg; {masses}) does not rank the factors as the measured errors do, so this "
            "mechanism does not explain the result; it remains unexplained here.")
    return paragraphs


def premise_explanation(metrics: dict) -> list[str]:
    """Why the controller works although the premise of Eqs. 27-29 fails (or nothing, if it holds)."""
    b = metrics["plant_b"]
    inside = _inside(b)
    outside = [a for a in AXES if not inside[a]]
    if not outside:
        return []
    c = metrics["cases"]["controlled"]
    s_ratio = max(c["max_abs_s"][a] for a in AXES) / PAPER_PHI
    ranges = ", ".join(f"{a} {b[a][0]:.3g}-{b[a][1]:.3g} (bounds {PAPER_B[a][0]:g}-{PAPER_B[a][1]:g})"
                       for a in outside)
    text = (f"**The b bounds miss the plant on {', '.join(outside)}** ({ranges}): the plant's effective mass "
            "includes the added mass and the arm, which the paper's bounds leave out. Slotine's guarantee (Eq. 30) "
            "is then not formally met on those axes. ")
    if s_ratio <= 1.0:
        text += (f"It is a sufficient condition, not a necessary one: the measured max abs(s) / Phi = {s_ratio:.2f} "
                 "shows the switching gain k still exceeded what the mismatch required, so s never left the "
                 "boundary layer.")
    else:
        text += (f"Here it matters: s left the boundary layer (max abs(s) / Phi = {s_ratio:.2f}).")
    return [text]


# -- the report: one structure, two renderings

@dataclass
class Table:
    """A table of the report: column headers (with units) and rows of already formatted cells."""

    headers: list[str]
    rows: list[list[str]]


@dataclass
class Figure:
    """A figure file of the report (relative to it) and its caption (computed from the data)."""

    file: str
    caption: str


@dataclass
class Bullets:
    """A bulleted list of paragraphs."""

    items: list[str]


@dataclass
class Section:
    """A section of the report: a title and blocks (paragraph strings, :class:`Table`, :class:`Figure`,
    :class:`Bullets`). Paragraph text may hold ``**bold**``, ```code``` and ``[text](file)`` links."""

    title: str
    blocks: list = field(default_factory=list)


REPORT_TITLE = "Reproduction of the paper's Section 6"


def render_markdown(sections: list[Section], title: str = REPORT_TITLE) -> str:
    """The report as Markdown."""
    def cell(text: str) -> str:
        return str(text).replace("|", "\\|").replace("\n", " ")

    lines = [f"# {title}", ""]
    for sec in sections:
        lines += [f"## {sec.title}", ""]
        for block in sec.blocks:
            if isinstance(block, str):
                lines += [block, ""]
            elif isinstance(block, Bullets):
                lines += [f"- {item}" for item in block.items] + [""]
            elif isinstance(block, Table):
                lines.append("| " + " | ".join(cell(h) for h in block.headers) + " |")
                lines.append("|" + "---|" * len(block.headers))
                lines += ["| " + " | ".join(cell(c) for c in row) + " |" for row in block.rows]
                lines.append("")
            elif isinstance(block, Figure):
                if block.file.endswith(".pdf"):
                    lines += [f"[{block.file}]({block.file})", ""]
                else:
                    lines += [f"![{block.file}]({block.file})", ""]
                lines += [f"*{block.caption}*", ""]
    return "\n".join(lines).rstrip() + "\n"


def _inline_html(text: str) -> str:
    import html
    import re

    out = html.escape(str(text), quote=False)
    out = re.sub(r"\*\*(.+?)\*\*", r"<b>\1</b>", out)
    out = re.sub(r"`(.+?)`", r"<code>\1</code>", out)
    return re.sub(r"\[([^\]]+)\]\(([^)\s]+)\)", r'<a href="\2">\1</a>', out)


def render_html(sections: list[Section], out_dir: Path, title: str = REPORT_TITLE) -> str:
    """The report as one HTML page: the same sections, paragraphs, tables and captions as
    :func:`render_markdown`; PNG and SVG figures embedded (``data:`` URIs), PDF figures linked."""
    import html

    def figure(block: Figure) -> str:
        path = out_dir / block.file
        caption = f"<figcaption>{_inline_html(block.caption)}</figcaption>"
        if block.file.endswith(".pdf"):
            return (f'<figure><object data="{block.file}" type="application/pdf" width="100%" height="600">'
                    f'<a href="{block.file}">{block.file}</a></object>{caption}</figure>')
        mime = "image/svg+xml" if block.file.endswith(".svg") else "image/png"
        data = base64.b64encode(path.read_bytes()).decode()
        return f'<figure><img src="data:{mime};base64,{data}" alt="{block.file}">{caption}</figure>'

    parts = ["<!doctype html><html><head><meta charset='utf-8'>", f"<title>uvms: {html.escape(title)}</title>",
             "<style>body{font-family:sans-serif;max-width:1100px;margin:auto;line-height:1.4}"
             "table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #bbb;padding:4px 8px;"
             "font-size:90%;vertical-align:top}th{background:#eef}img{max-width:100%}"
             "figcaption{font-style:italic;font-size:90%}</style></head><body>", f"<h1>{html.escape(title)}</h1>"]
    for sec in sections:
        parts.append(f"<h2>{html.escape(sec.title)}</h2>")
        for block in sec.blocks:
            if isinstance(block, str):
                parts.append(f"<p>{_inline_html(block)}</p>")
            elif isinstance(block, Bullets):
                parts.append("<ul>" + "".join(f"<li>{_inline_html(i)}</li>" for i in block.items) + "</ul>")
            elif isinstance(block, Table):
                head = "".join(f"<th>{_inline_html(h)}</th>" for h in block.headers)
                body = "".join("<tr>" + "".join(f"<td>{_inline_html(c)}</td>" for c in row) + "</tr>"
                               for row in block.rows)
                parts.append(f"<table><tr>{head}</tr>{body}</table>")
            elif isinstance(block, Figure):
                parts.append(figure(block))
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


# -- provenance

LIBRARIES = ("numpy", "scipy", "numba", "matplotlib", "pandas", "pydantic", "plotly")


def git_commit(directory: Path | None = None) -> str:
    """``git rev-parse HEAD`` of the checkout holding ``directory`` (default: this package's source), with
    " (uncommitted changes)" if tracked files differ; "not a git checkout" otherwise (or without git)."""
    import subprocess

    directory = Path(directory or Path(__file__).resolve().parent)
    try:
        head = subprocess.run(["git", "-C", str(directory), "rev-parse", "HEAD"], capture_output=True, text=True,
                              timeout=20)
        if head.returncode != 0:
            return "not a git checkout"
        dirty = subprocess.run(["git", "-C", str(directory), "status", "--porcelain", "--untracked-files=no",
                                "--", "."], capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.SubprocessError):
        return "not a git checkout"
    commit = head.stdout.strip()
    return commit + (" (uncommitted changes)" if dirty.returncode == 0 and dirty.stdout.strip() else "")


def provenance(command_line: str | None = None) -> dict[str, Any]:
    """What produced a report: uvms version, git commit, UTC date, command line, Python and library versions."""
    import datetime
    import importlib.metadata
    import platform
    import shlex
    import sys

    import uvms

    def version(name: str) -> str:
        try:
            return importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            return "not installed"

    return {"uvms_version": uvms.__version__, "git_commit": git_commit(),
            "date_utc": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
            "command_line": command_line if command_line is not None else shlex.join(sys.argv),
            "python": platform.python_version(), "platform": platform.platform(),
            "libraries": {name: version(name) for name in LIBRARIES}}


def paper(out_dir="reproduce-paper", *, actuators: str = "ideal", compare: bool = True,
          figure_format: str = "png", animation: bool = True, command_line: str | None = None,
          progress: Callable[[str], None] | None = None) -> dict:
    """Run the three cases (and the runs the report adds), write figures (``figure_format``: png, svg or pdf),
    the time series of every run (``cases/<name>/``), ``metrics.json``, ``report.md``/``.html`` and, unless
    ``animation`` is False, ``animation_case2_vs_case3.html`` into ``out_dir``; return the metrics
    (``{"epsilon_m", "actuators", "cases": {"fixed"|"released"|"controlled": {...}}, ...}``).

    Everything is written into a temporary sibling folder that replaces ``out_dir`` in one rename at the end, so
    an interrupted run never leaves a mix of old and new files.
    """
    wall0 = _time.perf_counter()
    _check_choice(actuators, ACTUATORS, "--actuators")
    _check_choice(figure_format, FORMATS, "--format")
    final = _check_output(Path(out_dir))
    with staged_directory(final, kind="reproduction") as out:
        metrics = _reproduce_into(out, actuators, compare, progress, wall0, figure_format=figure_format,
                                  animation=animation, command_line=command_line)
    return metrics


def _check_output(out: Path) -> Path:
    """The output folder may be new, empty, or an earlier reproduction holding nothing else (then replaced whole)."""
    from uvms.output import check_destination

    out = out.resolve()
    check_destination(out, "--output", kind="replaced folder")
    return out


ANIMATION = "animation_case2_vs_case3.html"
"""The replay of case 2 (released) beside case 3 (controlled), a self-contained plotly page."""


def _chatter(controlled, small) -> dict:
    from uvms.sim.metrics import sign_changes

    return {"paper": {k: sign_changes(controlled.signals[f"command_{k}"]) for k in ("X", "Y", "N")},
            "small": {k: sign_changes(small.signals[f"command_{k}"]) for k in ("X", "Y", "N")}}


def _health_words(health: dict) -> str:
    """A case's run health (:mod:`uvms.sim.health`, ``metrics["health"][case]``) in a few words: ``healthy`` or
    its warning."""
    if not health:
        return "-"
    return "healthy" if health["healthy"] else health["warning"]


def _setup_words() -> str:
    """The controlled case's run settings, in words, from its scenario file."""
    spec = _case_spec("controlled")
    schedule = spec.inputs.torque_schedule()
    torques = ", then ".join(f"[{', '.join(f'{x:g}' for x in row)}] N m" + (f" until {schedule.times[k + 1]:g} s"
                                                                           if k + 1 < len(schedule.times) else "")
                             for k, row in enumerate(schedule.torques))
    return (f"{spec.duration:g} s at {spec.step * 1e3:g} ms RK4, controller every {spec.controller.period * 1e3:g} "
            f"ms; joint torques {torques}")


def _reproduce_into(out: Path, actuators: str, compare: bool, progress, wall0: float, *, figure_format: str = "png",
                    animation: bool = True, command_line: str | None = None) -> dict:
    """Everything of :func:`paper`, written into ``out``."""
    import uvms
    from uvms import paper_figures as figs
    from uvms.control.compare import Case, axis_series, run_case
    from uvms.sim.run import Actuation

    def say(message: str) -> None:
        if progress:
            progress(message)

    prov = provenance(command_line)
    model = uvms.load_model("paper")
    results = run(model, actuators=actuators, progress=progress)
    fixed = results["fixed"]
    metrics: dict[str, Any] = {"epsilon_m": PAPER_PHI / PAPER_LAMBDA, "actuators": actuators,
                               "cases": {name: case_metrics(res, fixed) for name, res in results.items()},
                               "health": {name: res.health().as_dict() for name, res in results.items()}}
    say("chatter check: Phi / 100")
    extra = {"controlled_phi_small": _simulate_case(model, "controlled", actuators, boundary_layer=PAPER_PHI / 100)}
    chatter = _chatter(results["controlled"], extra["controlled_phi_small"])
    metrics["chatter"] = chatter
    metrics["plant_b"] = plant_effective_inertia(model, results["controlled"])

    # the paper's own three thrusters, as a measured finding
    layout: dict[str, Any] = {}
    if actuators != "paper-layout":
        say("controlled case with the paper's 3-thruster layout")
        extra["controlled_paper_layout"] = _simulate_case(model, "controlled", "paper-layout")
        extra["controlled_paper_layout_phi_small"] = _simulate_case(model, "controlled", "paper-layout",
                                                                    boundary_layer=PAPER_PHI / 100)
        pl = extra["controlled_paper_layout"]
        pl_metrics = {"epsilon_m": metrics["epsilon_m"], "actuators": "paper-layout",
                      "cases": {"fixed": metrics["cases"]["fixed"], "released": metrics["cases"]["released"],
                                "controlled": case_metrics(pl, fixed)},
                      "health": {**metrics["health"], "controlled": pl.health().as_dict()},
                      "plant_b": plant_effective_inertia(model, pl)}
        pl_chatter = _chatter(pl, extra["controlled_paper_layout_phi_small"])
        unachieved = pl.signals.get("unachieved_Y")
        layout = {"case": pl_metrics["cases"]["controlled"], "chatter": pl_chatter, "plant_b": pl_metrics["plant_b"],
                  "claims": claims(pl_metrics, pl_chatter),
                  "peak_unachieved_Y_N": float(np.nanmax(np.abs(unachieved))) if unachieved is not None else 0.0}
    metrics["paper_layout"] = layout

    # the central claim: smc-ab against smc-ne with a noisy, delayed IMU, same actuators and model error
    say("central claim: smc-ne with a noisy IMU")
    extra["controlled_smc_ne_imu"] = run_case(model, Case("smc-ne (noisy IMU)", "smc-ne", dict(IMU_NOISE)),
                                              hydro_scale=PAPER_MODEL_ERROR,
                                              actuation=Actuation.named(ACTUATORS[actuators]))
    ab, ne = command_activity(results["controlled"]), command_activity(extra["controlled_smc_ne_imu"])
    metrics["central_claim"] = {"smc-ab": ab, "smc-ne (noisy IMU)": ne,
                                **central_claim(ab, ne, metrics["epsilon_m"] * 1e3)}

    say("saving the time series")
    for name, res in {**results, **extra}.items():
        res.save(out / CASE_FOLDER / name)

    say("figures")
    names = [f"{stem}.{figure_format}" for stem in FIGURE_STEMS]
    notes = {
        FIGURE_STEMS[0]: figs.fig4_ee_path(results, out / names[0]),
        FIGURE_STEMS[1]: figs.fig5_uncontrolled(results["released"], axis_series(results["released"]),
                                                out / names[1]),
        FIGURE_STEMS[2]: figs.fig6_controlled(results["controlled"], axis_series(results["controlled"]),
                                              out / names[2], metrics["epsilon_m"]),
        FIGURE_STEMS[3]: figs.fig7_sliding(results["controlled"], out / names[3], PAPER_PHI),
        FIGURE_STEMS[4]: figs.fig8_control(results["controlled"], out / names[4]),
    }
    metrics["figure_notes"] = notes
    metrics["figures"] = names
    if animation:
        say("animation: case 2 beside case 3")
        figs.case_animation(results["released"], results["controlled"], model, out / ANIMATION, fixed=fixed,
                            thrusters=Actuation.named(ACTUATORS[actuators]).thrusters)
        metrics["animation"] = ANIMATION
    table = None
    b_model = {}
    if compare:
        table = comparison(model, progress=progress)
        atomic_write_text(out / "comparison.csv", table.to_csv(index=False))
        for factor in sorted(set(float(f) for f in table["model_error_factor"])):
            scaled = model.with_hydrodynamics_scaled(added_mass=factor, drag=factor)
            b_model[factor] = plant_effective_inertia(scaled, results["controlled"])
    metrics["controller_model_b"] = {f"{k:g}": v for k, v in b_model.items()}
    claim_rows = claims(metrics, chatter)
    metrics["claims"] = claim_rows
    metrics["explanations"] = {"model_error": model_error_explanation(table, b_model, actuators),
                               "premise": premise_explanation(metrics)}
    metrics["time_series"] = {name: f"{CASE_FOLDER}/{name}" for name in {**results, **extra}}
    metrics["provenance"] = prov
    metrics["wall_time_s"] = _time.perf_counter() - wall0
    prov["wall_time_s"] = round(metrics["wall_time_s"], 1)
    atomic_write_text(out / "metrics.json", json.dumps(metrics, indent=2))
    sections = report_sections(metrics, table)
    atomic_write_text(out / "report.md", render_markdown(sections))
    atomic_write_text(out / "report.html", render_html(sections, out))
    return metrics


COMPARISON_HEADERS = {
    "case": "controller", "actuators": "actuators", "model_error_factor": "model error factor (x plant)",
    "peak_xy_error_mm": "peak xy error [mm]", "peak_yaw_error_deg": "peak yaw error [deg]",
    "max_abs_s_surge": "max abs(s) surge [mm/s]", "max_abs_s_sway": "max abs(s) sway [mm/s]",
    "max_abs_s_yaw": "max abs(s) yaw [mrad/s]", "rms_command_X_N": "RMS X [N]", "rms_command_Y_N": "RMS Y [N]",
    "rms_command_N_Nm": "RMS N [N m]", "chatter_X": "slope sign changes X", "chatter_Y": "slope sign changes Y",
    "chatter_N": "slope sign changes N", "complete": "complete",
}
"""The comparison table's columns in the report: readable headers with units (``comparison.csv`` keeps the
column names of :func:`uvms.control.compare.compare_controllers`)."""
_MILLI = {"max_abs_s_surge", "max_abs_s_sway", "max_abs_s_yaw"}      # m/s -> mm/s, rad/s -> mrad/s


def _g(value: float, digits: int = 3) -> str:
    return f"{value:.{digits}g}"


def comparison_table(table) -> Table:
    """The controller comparison with readable headers and units."""
    cols = [c for c in COMPARISON_HEADERS if c in table.columns]
    rows = []
    for _, r in table.iterrows():
        cells = []
        for c in cols:
            v = r[c]
            if c in _MILLI:
                v = float(v) * 1e3
            if isinstance(v, (bool, np.bool_)):
                cells.append("yes" if v else "no")
            elif isinstance(v, (float, np.floating)):
                cells.append(_g(float(v)))
            else:
                cells.append(str(v))
        rows.append(cells)
    return Table([COMPARISON_HEADERS[c] for c in cols], rows)


def _claim_rows(rows: list[dict]) -> list[list[str]]:
    return [[r["claim"], r["measured"], f"**{r['verdict']}**"] for r in rows]


def _lost_claims(rows: list[dict], layout_rows: list[dict]) -> list[str]:
    """The claims that hold in ``rows`` but not in ``layout_rows``."""
    held = {r["claim"] for r in rows if r["verdict"] == "holds"}
    return [r["claim"] for r in layout_rows if r["verdict"] != "holds" and r["claim"] in held]


def layout_failure_words(rows: list[dict], layout_rows: list[dict], act: str) -> str:
    """The one sentence that counts the claims the paper's 3-thruster layout fails (the summary and its section
    both say it, in these words): how many of all fail with it, and how many of those hold with ``act``."""
    failed = [r["claim"] for r in layout_rows if r["verdict"] != "holds"]
    lost = _lost_claims(rows, layout_rows)
    if not failed:
        return f"With the paper's 3-thruster layout (`paper-layout`), all {len(layout_rows)} claims hold."
    return (f"With the paper's 3-thruster layout (`paper-layout`), {len(failed)} of the {len(layout_rows)} claims "
            f"fail; {len(lost)} of these {len(failed)} hold with `{act}` actuators, so the layout is what breaks "
            "them" + (": " + "; ".join(lost) if lost else "") + ".")


def world_and_body_words(cases: dict) -> str:
    """Why a case's peak x (or y) differs between the Cases table (world frame) and Figs. 5-6 (body frame),
    with the released case's numbers."""
    c = cases.get("released") or next(iter(cases.values()))
    name = "released" if "released" in cases else next(iter(cases))
    return ("Peak abs x and y are the vehicle's displacement from its start in the world frame (north, east); the "
            "body x and y errors are the same displacement in the vehicle's own axes, R^T (p - p0), as Figs. 5-6 "
            "draw them. The body axes turn with the vehicle's yaw, so the two peaks differ: case "
            f"{name}, world x {c['peak_abs_x_m'] * 1e3:.3g} mm and body x {c['peak_body_error_x_m'] * 1e3:.3g} mm, "
            f"with yaw up to {math.degrees(c['peak_abs_yaw_rad']):.3g} deg.")


def report_sections(metrics: dict, table=None) -> list[Section]:
    """The report as one structure (rendered by :func:`render_markdown` and :func:`render_html`); every
    sentence that states a result is computed from ``metrics``."""
    eps_mm = metrics["epsilon_m"] * 1e3
    act = metrics["actuators"]
    rows = metrics["claims"]
    central = metrics["central_claim"]
    held = [r for r in rows if r["verdict"] == "holds"]
    layout = metrics.get("paper_layout") or {}
    summary = [f"With `{act}` actuators, {len(held)} of the {len(rows)} claims checked **hold**"
               + (", and these do not: " + "; ".join(r["claim"] for r in rows if r["verdict"] != "holds")
                  if len(held) < len(rows) else "") + ".",
               f"The paper's central claim (smc-ab against smc-ne with an IMU) **{central['verdict']}**: "
               f"{central['finding']} ({central['details']})."]
    if layout:
        summary.append(layout_failure_words(rows, layout["claims"], act))
    sections = [Section("Summary", [Bullets(summary)])]
    sections.append(Section("Setup", [
        f"Actuators `{act}`; controller model error factor {PAPER_MODEL_ERROR} (its added mass and drag are "
        f"{PAPER_MODEL_ERROR} x the plant's, the paper's 60 %); Phi = {PAPER_PHI}, lambda = {PAPER_LAMBDA} 1/s, "
        f"epsilon = Phi / lambda = {eps_mm:.2f} mm; {_setup_words()}."]))
    sections.append(Section("The paper's claims", [Table(["claim", "measured here", "verdict"],
                                                        _claim_rows([central] + rows))]))
    ab, ne = central["smc-ab"], central["smc-ne (noisy IMU)"]
    sections.append(Section("The central claim: articulated body against Newton-Euler with an IMU", [
        f"Verdict: the claim **{central['verdict']}**: {central['finding']}. Measured: {central['details']}. "
        f"smc-ne gets its accelerations from an IMU with {IMU_NOISE['imu_noise']} m/s^2 (rad/s^2) white noise, "
        f"{IMU_NOISE['imu_delay']} samples late; "
        f"both controllers use the same model error ({PAPER_MODEL_ERROR}x), actuators and gains. Precision counts "
        f"as the same within {SAME_PRECISION * 100:.0f} %, chatter as more from {CHATTER_RATIO:g} x the slope sign "
        "changes on.",
        Table(["controller", "peak xy error [mm]", "peak yaw error [deg]", "command slope sign changes (X+Y+N)",
               "command step RMS, X and Y [N]"],
              [[name, _g(m["peak_xy_error_mm"]), _g(m["peak_yaw_error_deg"]), str(m["chatter"]),
                _g(m["increment_rms_N"])] for name, m in (("smc-ab", ab), ("smc-ne (noisy IMU)", ne))])]))
    paradox = metrics["explanations"]["model_error"] + metrics["explanations"]["premise"]
    sections.append(Section("Results that look paradoxical", paradox or ["None found in this run."]))
    if layout:
        c = layout["case"]
        blocks = [f"The paper's vehicle has three thrusters (two surge, one heave) and none that pushes sideways. "
                  f"Run with them (`paper-layout`), the controlled case's sway force is unachievable: up to "
                  f"{layout['peak_unachieved_Y_N']:.3g} N of the commanded Y stayed unapplied; peak body-frame xy "
                  f"error {c['peak_body_error_xy_m'] * 1e3:.3g} mm (epsilon {eps_mm:.2f} mm), peak end-effector "
                  f"deviation {c['peak_ee_deviation_m'] * 1e3:.3g} mm, yaw "
                  f"{math.degrees(c['peak_abs_yaw_rad']):.3g} deg. "
                  + layout_failure_words(rows, layout["claims"], act),
                  Table(["claim", "measured with the paper's 3 thrusters", "verdict"], _claim_rows(layout["claims"]))]
        sections.append(Section("The paper's 3-thruster layout (measured finding)", blocks))
    case_rows = []
    for name, c in metrics["cases"].items():
        case_rows.append([name, f"{c['peak_abs_x_m'] * 1e3:.3g}", f"{c['peak_abs_y_m'] * 1e3:.3g}",
                          f"{c['peak_body_error_x_m'] * 1e3:.3g}", f"{c['peak_body_error_y_m'] * 1e3:.3g}",
                          f"{math.degrees(c['peak_abs_yaw_rad']):.3g}", f"{c['peak_body_error_xy_m'] * 1e3:.3g}",
                          f"{c['peak_ee_deviation_m'] * 1e3:.3g}",
                          ", ".join(f"{c['max_abs_s'][a] / PAPER_PHI:.3g}" for a in AXES)])
    by_case = metrics.get("health") or {}
    health = "; ".join(f"{name}: {_health_words(by_case.get(name) or {})}" for name in metrics["cases"])
    limits = (by_case.get("controlled") or {}).get("limits") or {
        "attitude_limit_rad": math.nan, "saturation_limit": math.nan}
    sections.append(Section("Cases", [Table(
        ["case", "peak abs x, world [mm]", "peak abs y, world [mm]", "peak abs body x error [mm]",
         "peak abs body y error [mm]", "peak abs yaw [deg]", "peak body xy error [mm]",
         "peak end-effector deviation [mm]", "max abs(s) / Phi [-] (surge, sway, yaw)"], case_rows),
        world_and_body_words(metrics["cases"]),
        f"Run health (healthy: roll and pitch within {math.degrees(limits['attitude_limit_rad']):.4g} deg, no "
        f"thruster saturated more than {limits['saturation_limit'] * 100:.4g} % of the run; `docs/scenarios.md`): "
        f"{health}."]))
    if table is not None:
        sections.append(Section("Controllers compared", [
            "Released vehicle, the paper's torques. Model error factor: the controller model's added mass and drag "
            "relative to the plant's (0.4: the paper's 60 % error; 1.0: a perfect model). Chatter: sign changes "
            "of the command's slope. The numbers are in `comparison.csv`.", comparison_table(table)]))
    notes = metrics["figure_notes"]
    sections.append(Section("Figures", [Figure(name, notes[stem]) for stem, name in zip(FIGURE_STEMS,
                                                                                        metrics["figures"])]))
    if metrics.get("animation"):
        sections.append(Section("Animation", [
            f"[Case 2 (released, control off) beside case 3 (released, smc-ab)]({metrics['animation']}): a 3-D "
            "replay of both runs on one time slider, each with its vehicle and end-effector trails and the fixed "
            "case's end-effector path (dashed) for reference."]))
    sections.append(Section("Time series", [
        f"Every run behind the claims, figures and animation (not the comparison's runs: their numbers are in "
        f"`comparison.csv`) is saved in `{CASE_FOLDER}/<name>/result.csv` (one column per series, SI "
        "units in the names) with a `result.json` summary; `uvms.Result.load(folder)` reads one back and "
        "`uvms plot` draws it.",
        Bullets([f"[{path}]({path}/result.csv)" for path in metrics["time_series"].values()])]))
    prov = metrics["provenance"]
    sections.append(Section("Provenance", [Table(["field", "value"], [
        ["uvms version", prov["uvms_version"]], ["git commit", prov["git_commit"]], ["date (UTC)", prov["date_utc"]],
        ["command line", f"`{prov['command_line']}`"], ["python", prov["python"]], ["platform", prov["platform"]],
        ["libraries", ", ".join(f"{k} {v}" for k, v in prov["libraries"].items())],
        ["wall time [s]", f"{prov.get('wall_time_s', 0):.1f}"]])]))
    return sections
