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

The package: :mod:`~uvms.reproduce.cases` (running the cases and measuring them),
``uvms/reproduce/claims.py`` (judging the claims; its :func:`claims` is the name exported here),
:mod:`~uvms.reproduce.report` (the report's structure, its two renderings and provenance) and
:mod:`~uvms.reproduce.write` (:func:`paper`: everything written into one folder). Every public name is
importable from here.
"""

from __future__ import annotations

from uvms.reproduce.cases import (
    ACTUATORS,
    AXES,
    CASE_SCENARIOS,
    COMMAND_OF_AXIS,
    CONTROL_PERIOD,
    DURATION,
    PAPER_B,
    PAPER_LAMBDA,
    PAPER_MODEL_ERROR,
    PAPER_PHI,
    STEP,
    case_metrics,
    command_activity,
    comparison,
    plant_effective_inertia,
    run,
)
from uvms.reproduce.report import (
    ANIMATION,
    CASE_FOLDER,
    COMPARISON_HEADERS,
    FIGURE_STEMS,
    FIGURES,
    FORMATS,
    LIBRARIES,
    REPORT_TITLE,
    Bullets,
    Figure,
    Section,
    Table,
    comparison_table,
    git_commit,
    layout_failure_words,
    provenance,
    render_html,
    render_markdown,
    report_sections,
    world_and_body_words,
)
from uvms.reproduce.write import paper

# last: the function ``claims`` takes the package attribute that importing the submodule ``claims`` set
from uvms.reproduce.claims import (  # noqa: E402, I001
    CHATTER_RATIO,
    SAME_PRECISION,
    central_claim,
    claims,
    model_error_explanation,
    premise_explanation,
)

__all__ = [
    "ACTUATORS", "ANIMATION", "AXES", "CASE_FOLDER", "CASE_SCENARIOS", "CHATTER_RATIO", "COMMAND_OF_AXIS",
    "COMPARISON_HEADERS", "CONTROL_PERIOD", "DURATION", "FIGURES", "FIGURE_STEMS", "FORMATS", "LIBRARIES",
    "PAPER_B", "PAPER_LAMBDA", "PAPER_MODEL_ERROR", "PAPER_PHI", "REPORT_TITLE", "SAME_PRECISION", "STEP",
    "Bullets", "Figure", "Section", "Table", "case_metrics", "central_claim", "claims", "command_activity",
    "comparison", "comparison_table", "git_commit", "layout_failure_words", "model_error_explanation", "paper",
    "plant_effective_inertia", "premise_explanation", "provenance", "render_html", "render_markdown",
    "report_sections", "run", "world_and_body_words",
]
