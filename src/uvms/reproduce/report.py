"""The reproduction's report: one structure rendered as Markdown and as HTML, and its provenance.

:func:`report_sections` turns the metrics (:mod:`uvms.reproduce.cases`, :mod:`uvms.reproduce.claims`) into
:class:`Section` s with paragraphs, tables and figures; every sentence that states a result is computed from
them. :func:`render_markdown` and :func:`render_html` render the same sections; :func:`provenance` records what
produced the report (version, git commit read by :func:`git_commit`, date, command line, libraries).
"""

from __future__ import annotations

import base64
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from uvms.control.compare import IMU_NOISE
from uvms.reproduce.cases import AXES, PAPER_LAMBDA, PAPER_MODEL_ERROR, PAPER_PHI, _case_spec
from uvms.reproduce.claims import CHATTER_RATIO, SAME_PRECISION

FIGURE_STEMS = ("fig4_ee_path", "fig5_uncontrolled", "fig6_controlled", "fig7_sliding", "fig8_control")
FIGURES = tuple(f"{stem}.png" for stem in FIGURE_STEMS)
"""The figures' file names in the default format (``--format png``)."""
FORMATS = ("png", "svg", "pdf")
"""``--format`` choices for the figures."""
CASE_FOLDER = "cases"
"""Subfolder of the report holding every run's time series (``cases/<name>/result.csv`` and ``.json``)."""
ANIMATION = "animation_case2_vs_case3.html"
"""The replay of case 2 (released) beside case 3 (controlled), a self-contained plotly page."""


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
    """``git rev-parse HEAD`` of the checkout holding ``directory`` (default: the uvms package's source), with
    " (uncommitted changes)" if tracked files differ; "not a git checkout" otherwise (or without git)."""
    import subprocess

    directory = Path(directory or Path(__file__).resolve().parents[1])
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
