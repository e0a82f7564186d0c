"""``uvms reproduce``'s figures and wording without running the paper (made-up runs and metrics): Fig. 7's
boundary layer inside every panel, one sentence for the 3-thruster failure count, and the world-frame against
body-frame peaks said with their reason."""

from __future__ import annotations

import numpy as np
import pytest

from uvms import paper_figures as figs
from uvms.reproduce import layout_failure_words, world_and_body_words
from uvms.sim.result import Result

PHI = 0.02


def _run(s_peaks) -> Result:
    K = 101
    t = np.linspace(0.0, 10.0, K)
    states = np.zeros((K, 13 + 6))
    states[:, 3] = 1.0
    signals = {f"s_{a}": peak * np.sin(t) for a, peak in zip(figs.AXES, s_peaks)}
    return Result(time=t, states=states, n_joints=3, end_effector=np.zeros((K, 3)), joint_torques=np.zeros((K, 3)),
                  signals=signals)


@pytest.mark.parametrize("s_peaks", [(0.001, 0.0004, 0.0002), (0.015, 0.03, 0.5), (0.0, 0.02, 1e-6)])
def test_fig7_boundary_layer_is_inside_every_panel(s_peaks):
    fig, axes, note = figs.fig7_axes(_run(s_peaks), PHI)
    try:
        for ax, peak in zip(axes, s_peaks):
            bounds = sorted(line.get_ydata()[0] for line in ax.get_lines()[1:3])       # the two +/- Phi lines
            low, high = ax.get_ylim()
            assert bounds[0] == pytest.approx(-bounds[1]) and bounds[1] > 0
            assert low < bounds[0] < bounds[1] < high                                 # drawn and visible
            scale = bounds[1] / PHI
            assert high >= peak * scale                                               # so is s
            assert (len(ax.child_axes) == 1) == (0 < peak < figs.VISIBLE * PHI)       # the inset: s on its scale
        assert "beyond the axes" not in note and note.startswith("max abs(s) / Phi: surge")
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)


def test_fig7_still_writes_its_file(tmp_path):
    note = figs.fig7_sliding(_run((0.001, 0.0004, 0.0002)), tmp_path / "fig7.svg", PHI)
    assert "inset: s on its own scale (surge, sway, yaw)" in note
    assert (tmp_path / "fig7.svg").read_text().lstrip().startswith("<?xml")


CLAIMS = [{"claim": c, "verdict": v} for c, v in (("A", "holds"), ("B", "holds"), ("C", "does not hold"),
                                                   ("D", "holds"))]


def test_the_layout_failure_count_is_one_sentence():
    layout = [{"claim": c, "verdict": v} for c, v in (("A", "does not hold"), ("B", "holds"),
                                                       ("C", "does not hold"), ("D", "does not hold"))]
    words = layout_failure_words(CLAIMS, layout, "ideal")
    assert words == ("With the paper's 3-thruster layout (`paper-layout`), 3 of the 4 claims fail; 2 of these 3 hold "
                     "with `ideal` actuators, so the layout is what breaks them: A; D.")
    assert layout_failure_words(CLAIMS, CLAIMS, "ideal").startswith("With the paper's 3-thruster layout "
                                                                    "(`paper-layout`), 1 of the 4 claims fail; 0 of")
    held = [{"claim": c["claim"], "verdict": "holds"} for c in CLAIMS]
    assert layout_failure_words(CLAIMS, held, "ideal").endswith("all 4 claims hold.")


def test_the_report_uses_that_sentence_in_the_summary_and_the_section():
    import inspect

    from uvms import reproduce

    source = inspect.getsource(reproduce.report_sections)
    assert source.count("layout_failure_words(rows, layout[\"claims\"], act)") == 2
    assert "claims fail with it" not in inspect.getsource(reproduce)


def test_world_and_body_peaks_are_told_apart():
    cases = {"fixed": {}, "released": {"peak_abs_x_m": 0.41, "peak_body_error_x_m": 0.37,
                                       "peak_abs_yaw_rad": np.radians(30.0)}}
    words = world_and_body_words(cases)
    assert "world x 410 mm and body x 370 mm, with yaw up to 30 deg" in words
    assert "R^T (p - p0)" in words and "turn with the vehicle's yaw" in words
