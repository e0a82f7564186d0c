"""Writing a reproduction of the paper's Section 6 into one folder (:func:`paper`, ``uvms reproduce paper``).

Runs the three cases (:mod:`uvms.reproduce.cases`) and the runs the report adds: the controlled case with
``Phi / 100`` (chatter check), the controlled case with the paper's own three thrusters (``paper-layout``: a
measured finding), and ``smc-ne`` with a noisy, delayed IMU (the paper's central claim, against ``smc-ab``);
judges the claims (:mod:`uvms.reproduce.claims`); writes the figures, the time series of every run,
``metrics.json``, ``report.md`` and ``report.html`` (:mod:`uvms.reproduce.report`) and the animation.
``docs/reproduce.md`` describes the files.
"""

from __future__ import annotations

import json
import time as _time
from pathlib import Path
from typing import Any, Callable

import numpy as np

from uvms.control.compare import IMU_NOISE
from uvms.output import atomic_write_text, staged_directory
from uvms.reproduce.cases import (ACTUATORS, PAPER_LAMBDA, PAPER_MODEL_ERROR, PAPER_PHI, _chatter, _check_choice,
                                  _simulate_case, case_metrics, command_activity, comparison,
                                  plant_effective_inertia, run)
from uvms.reproduce.claims import central_claim, claims, model_error_explanation, premise_explanation
from uvms.reproduce.report import (ANIMATION, CASE_FOLDER, FIGURE_STEMS, FORMATS, provenance, render_html,
                                   render_markdown, report_sections)


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
