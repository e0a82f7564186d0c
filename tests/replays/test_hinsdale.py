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
