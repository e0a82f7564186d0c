"""The real robot: the bundled Hinsdale 2023 held-out trials replayed with the published-parameter model and the
fitted one, against the motion capture and beside the authors' own simulation (docs/logs.md, "The real
robot"). The fitted model never saw these trials (its record says so); the figures in docs/logs.md are these."""

import re
from pathlib import Path

import numpy as np
import pytest
import yaml

import uvms
from uvms.replays.hinsdale import LOST_TRACKING, held_out_scores, markdown_table

DOC = Path(__file__).resolve().parents[2] / "docs" / "logs.md"


@pytest.fixture(scope="module")
def scores():
    return (held_out_scores(uvms.load_model("hinsdale_bluerov2_alpha5")),
            held_out_scores(uvms.load_model("hinsdale_bluerov2_alpha5_fit")))


def test_the_fit_saw_only_traj_trials_and_none_held_out():
    record = yaml.safe_load(Path(uvms.load_model("hinsdale_bluerov2_alpha5_fit").source).read_text())[
        "identified"]["record"]
    assert record["fitted_on"] and all(name.startswith("traj0") for name in record["fitted_on"])
    assert not set(record["fitted_on"]) & set(LOST_TRACKING)
    assert sorted(record["held_out"]) == [f"traj_alt_{c}" for c in
                                          ("001-0", "001-1", "001-2", "002-0", "002-1", "008-0", "008-1", "008-2",
                                           "009-0", "009-1", "011-0", "011-1", "011-2")]


def test_held_out_targets(scores):
    published, fitted = scores
    assert len(fitted) == 13
    assert np.median([s.pitch for s in fitted]) <= 1.0
    assert np.median([s.roll for s in fitted]) <= 0.8
    assert sum(s.beats_authors for s in fitted) >= 11
    # the published parameters reproduce the authors' simulator: medians within 0.3 deg of theirs
    assert abs(np.median([s.pitch for s in published]) - np.median([s.authors_pitch for s in published])) <= 0.3
    assert abs(np.median([s.roll for s in published]) - np.median([s.authors_roll for s in published])) <= 0.3
    # and the replays have skill: below the no-skill score of the attitude held at its start
    assert np.median([s.pitch for s in fitted]) < 0.5 * np.median([s.held_pitch for s in fitted])


def test_the_table_in_the_docs_is_these_figures(scores):
    table = markdown_table(*scores)
    assert table in DOC.read_text(encoding="utf-8"), "regenerate it: python tools/hinsdale_table.py"


def test_the_left_out_trials_did_lose_tracking():
    """The three fit trials left out have attitude jumps no floating vehicle makes (> 500 deg/s)."""
    from uvms.logs.bundled import resolve_logs

    for name in LOST_TRACKING:
        log = uvms.Log.load(resolve_logs(f"hinsdale_2023/{name}")[0])
        t = log.grid(0.04)
        attitude = np.degrees(log.attitude(t).to_numpy()[:, :2])
        assert np.max(np.abs(np.diff(attitude, axis=0))) / 0.04 > 500.0, name
    assert re.search(r"traj007-1.*traj016-1.*traj019-0", DOC.read_text(encoding="utf-8"), re.S)


def _prose() -> str:
    return " ".join(DOC.read_text(encoding="utf-8").split())


def test_the_figures_in_the_prose_are_these(scores):
    """The sentences under the table repeat its medians and counts: they are these figures too."""
    published, fitted = scores

    def median(values) -> str:
        return f"{np.median(values):.2f}"

    authors_pitch, authors_roll = median([s.authors_pitch for s in fitted]), median([s.authors_roll for s in fitted])
    text = _prose()
    assert (f"median RMSE of **{median([s.pitch for s in fitted])} deg in pitch and "
            f"{median([s.roll for s in fitted])} deg in roll** against the motion capture, against {authors_pitch} "
            f"and {authors_roll} deg for the authors' own simulation and {median([s.held_pitch for s in fitted])} "
            f"and {median([s.held_roll for s in fitted])} deg for holding the start attitude") in text
    pitch_alone = sum(s.pitch < s.authors_pitch for s in fitted)
    roll_alone = sum(s.roll < s.authors_roll for s in fitted)
    assert (f"is below the authors' on **{sum(s.beats_authors for s in fitted)} of {len(fitted)}** trials (pitch "
            f"alone on {pitch_alone}, roll alone on {roll_alone})") in text
    assert (f"median pitch {median([s.pitch for s in published])} deg against their {authors_pitch}, roll "
            f"{median([s.roll for s in published])} against {authors_roll}") in text


def test_the_fit_figures_in_the_prose_are_its_record():
    """"What the fit says" quotes the bundled fit's record: the counts, each value and its inflated std."""
    record = yaml.safe_load(Path(uvms.load_model("hinsdale_bluerov2_alpha5_fit").source).read_text())[
        "identified"]["record"]
    p = record["parameters"]
    text = _prose()

    def entry(name):
        return p[name]["initial"], p[name]["value"], p[name]["std"]

    assert (f"({len(record['fitted_on'])} `traj*` trials, {len(p)} parameters, {record['evaluations']} evaluations, "
            f"{record['wall_time_s']:.0f} s on the 2-core machine") in text
    i, v, s = entry("damping.linear.roll")
    assert f"`damping.linear.roll` {i:.2f} -> {v:.2f} +/- {s:.2f}" in text
    i, v, s = entry("damping.linear.pitch")
    assert f"`pitch` {i:.2f} -> {v:.2f} +/- {s:.2f} N m s/rad" in text
    assert sorted(record["at_bound"]) == ["damping.quadratic.pitch", "damping.quadratic.roll"]
    assert all(p[n]["bounds"][0] == 0.0 for n in record["at_bound"]) and "the quadratic ones to their lower bound 0" in text
    i, v, s = entry("damping.linear.surge")
    assert f"`surge` {i:.2f} -> {v:.0f} +/- {s:.0f}" in text
    i, v, s = entry("damping.linear.sway")
    assert f"`sway` {i:.2f} -> {v:.0f} +/- {float(f'{s:.2g}'):.0f} N s/m" in text
    i, v, s = entry("cob.z")
    assert f"rises by {1000 * (v - i):.1f} mm (`cob.z` {1000 * i:.1f} -> {1000 * v:.2f} +/- {1000 * s:.2f} mm" in text
    assert all(abs(p[n]["value"] - p[n]["initial"]) < 0.15e-3 for n in ("cob.x", "cob.y")) \
        and "`cob.x` and `cob.y` move by 0.1 mm" in text
    (_, vr, sr), (_, vp, sp) = entry("added_mass.roll"), entry("added_mass.pitch")
    assert f"gains {vr:.2f} +/- {sr:.2f} (roll) and {vp:.2f} +/- {sp:.2f} (pitch) kg m^2" in text
    ratios = {round(q["std"] / q["std_white"], 6) for q in p.values()}
    assert len(ratios) == 1 and f"are {ratios.pop():.1f} times smaller" in text
